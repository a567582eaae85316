/* The camera, pinhole or orthographic: rays through pixels, projection of world points back to pixels, and the
 * motion of the background (directions) between two cameras, which may be of different kinds. */
#ifndef RESTIRCL_CAMERA_H
#define RESTIRCL_CAMERA_H

#include "numerics.h"

/* View-plane coordinates (tan units, or world units when orthographic) of continuous pixel (px, py); row 0 is
 * the top. */
inline float2 camera_plane(const __global Camera* cam, float px, float py)
{
    float nx = 2.0f * px / (float)cam->width - 1.0f;
    float ny = 1.0f - 2.0f * py / (float)cam->height;
    return (float2)(nx * cam->lens.x + cam->lens.z, ny * cam->lens.y + cam->lens.w);
}

/* Direction (not normalised) of the perspective ray through continuous pixel coordinates (px, py). */
inline float3 camera_direction(const __global Camera* cam, float px, float py)
{
    float2 a = camera_plane(cam, px, py);
    return cam->forward.xyz + a.x * cam->right.xyz + a.y * cam->up.xyz;
}

/* The camera ray through continuous pixel coordinates (px, py): origin *o and unit direction *d. An
 * orthographic ray leaves the plane through the camera's origin, along forward. */
inline void camera_ray(const __global Camera* cam, float px, float py, float3* o, float3* d)
{
    if (cam->kind == CAMERA_ORTHO) {
        float2 a = camera_plane(cam, px, py);
        *o = cam->origin.xyz + a.x * cam->right.xyz + a.y * cam->up.xyz;
        *d = cam->forward.xyz;
    } else {
        *o = cam->origin.xyz;
        *d = norm3(camera_direction(cam, px, py));
    }
}

/* Width of one pixel's ray cone at distance t along unit direction d: it spreads by 2 tan(fov_y / 2) / height
 * on the axis and cos^2 of the angle to it off the axis (a plane facing the camera gets its true pixel
 * footprint); an orthographic pixel is a tube of the pixel's width. */
inline float camera_footprint(const __global Camera* cam, float3 d, float t)
{
    if (cam->kind == CAMERA_ORTHO) return 2.0f * cam->lens.y / (float)cam->height;
    float cf = dot3(d, cam->forward.xyz);
    return t * cf * cf * 2.0f * cam->lens.y / (float)cam->height;
}

inline float2 camera_pixel(const __global Camera* cam, float x, float y)
{
    float nx = (x - cam->lens.z) / cam->lens.x;
    float ny = (y - cam->lens.w) / cam->lens.y;
    return (float2)((nx + 1.0f) * 0.5f * (float)cam->width, (1.0f - ny) * 0.5f * (float)cam->height);
}

/* Continuous pixel coordinates of world point p (no jitter); returns false behind the camera (the plane
 * through its origin, for both kinds). */
inline bool camera_project(const __global Camera* cam, float3 p, float2* px)
{
    float3 d = p - cam->origin.xyz;
    float z = dot3(d, cam->forward.xyz);
    if (!(z > 0.0f)) return false;
    float x = dot3(d, cam->right.xyz), y = dot3(d, cam->up.xyz);
    if (cam->kind != CAMERA_ORTHO) {
        x /= z;
        y /= z;
    }
    *px = camera_pixel(cam, x, y);
    return finite_f(px->x) && finite_f(px->y);
}

/* Continuous pixel coordinates of the direction d (a point at infinity) in a perspective camera; false when it
 * points backwards. */
inline bool camera_project_dir(const __global Camera* cam, float3 d, float2* px)
{
    float z = dot3(d, cam->forward.xyz);
    if (!(z > 0.0f)) return false;
    *px = camera_pixel(cam, dot3(d, cam->right.xyz) / z, dot3(d, cam->up.xyz) / z);
    return finite_f(px->x) && finite_f(px->y);
}

/* Where the background seen along d by the ray at pixel position ray_px of `cam` is in camera `other`, as a
 * pixel offset (other minus this, the same direction in both: no jitter in it). An orthographic camera sees one
 * direction, forward, at every pixel: between two of them the background stays where it is; a perspective camera
 * finds it at one pixel; an orthographic camera sees none of a perspective camera's directions but its forward, so
 * that has no history. */
inline bool camera_dir_motion(const __global Camera* cam, const __global Camera* other, float3 d, float2 ray_px,
                              float2* delta)
{
    float2 cur_px, other_px;
    if (other->kind == CAMERA_ORTHO) {
        *delta = (float2)(0.0f);
        return cam->kind == CAMERA_ORTHO;
    }
    if (cam->kind == CAMERA_ORTHO) cur_px = ray_px;
    else if (!camera_project_dir(cam, d, &cur_px)) return false;
    if (!camera_project_dir(other, d, &other_px)) return false;
    *delta = other_px - cur_px;
    return true;
}

inline float camera_depth(const __global Camera* cam, float3 p)
{
    return dot3(p - cam->origin.xyz, cam->forward.xyz);
}

#endif
