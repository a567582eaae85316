/* Pinhole camera: rays through pixels and projection of world points back to pixels. */
#ifndef RESTIRCL_CAMERA_H
#define RESTIRCL_CAMERA_H

#include "numerics.h"

/* Direction (not normalised) of the ray through continuous pixel coordinates (px, py); row 0 is the top. */
inline float3 camera_direction(const __global Camera* cam, float px, float py)
{
    float nx = 2.0f * px / (float)cam->width - 1.0f;
    float ny = 1.0f - 2.0f * py / (float)cam->height;
    return cam->forward.xyz + (nx * cam->lens.x + cam->lens.z) * cam->right.xyz
         + (ny * cam->lens.y + cam->lens.w) * cam->up.xyz;
}

/* Continuous pixel coordinates of world point p (no jitter); returns false behind the camera. */
inline bool camera_project(const __global Camera* cam, float3 p, float2* px)
{
    float3 d = p - cam->origin.xyz;
    float z = dot3(d, cam->forward.xyz);
    if (!(z > 0.0f)) return false;
    float x = dot3(d, cam->right.xyz) / z;
    float y = dot3(d, cam->up.xyz) / z;
    float nx = (x - cam->lens.z) / cam->lens.x;
    float ny = (y - cam->lens.w) / cam->lens.y;
    *px = (float2)((nx + 1.0f) * 0.5f * (float)cam->width, (1.0f - ny) * 0.5f * (float)cam->height);
    return finite_f(px->x) && finite_f(px->y);
}

/* Continuous pixel coordinates of the direction d (a point at infinity); false when it points backwards. */
inline bool camera_project_dir(const __global Camera* cam, float3 d, float2* px)
{
    float z = dot3(d, cam->forward.xyz);
    if (!(z > 0.0f)) return false;
    float nx = (dot3(d, cam->right.xyz) / z - cam->lens.z) / cam->lens.x;
    float ny = (dot3(d, cam->up.xyz) / z - cam->lens.w) / cam->lens.y;
    *px = (float2)((nx + 1.0f) * 0.5f * (float)cam->width, (1.0f - ny) * 0.5f * (float)cam->height);
    return finite_f(px->x) && finite_f(px->y);
}

inline float camera_depth(const __global Camera* cam, float3 p)
{
    return dot3(p - cam->origin.xyz, cam->forward.xyz);
}

#endif
