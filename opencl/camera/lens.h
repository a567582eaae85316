/* A thin lens in front of the camera (depth of field, HAS_DOF): every camera ray of a pixel leaves its own point
 * of the aperture and passes through the one point where the pinhole ray of that pixel meets the plane in focus
 * (Camera.focus.x along forward), so that surfaces on that plane stay sharp and the rest spreads over the image of
 * the aperture. The aperture is a disc, or a regular polygon of `blades` corners on the circle of its radius,
 * turned by `rotation`; its width is the radius over `ratio` (Blender's anamorphic Ratio: above 1 the bokeh is
 * taller than wide).
 *
 * The lens point of a pixel: in still renders with the Sobol sampler its own scrambled pair (QMC_LENS), each
 * sample another point of it; otherwise the pixel's random stream of this frame. An animation or viewport frame so
 * takes one lens point per pixel per frame, and TAA and ReSTIR reproject the point that ray hit (camera/primary.cl:
 * the hit's own motion; docs/design.md "Depth of field in motion"). */
#ifndef RESTIRCL_CAMERA_LENS_H
#define RESTIRCL_CAMERA_LENS_H

#ifdef HAS_DOF

#include "sampling/qmc.h"
#include "sampling/warps.h"

#define QMC_LENS 0x50000u  /* the dimension pair of the lens point (sampling/qmc.h's groups stay below) */
#define RNG_PASS_LENS 20u  /* the random stream of the lens point (the passes' numbers below it are taken) */

/* A point of the aperture polygon of n >= 3 corners on the unit circle, uniform in its area from (u, v): u picks
 * one of the n triangles (centre, corner k, corner k + 1) and is reused within it. Corner k sits at angle
 * rotation + (2k + 1) pi / n, so that rotation 0 puts the middle of an edge on the +x axis. */
inline float2 lens_polygon(int n, float rotation, float u, float v)
{
    float fk = floor(u * (float)n);
    float k = fmin_f(fk, (float)(n - 1));
    float r = u * (float)n - k;  /* uniform in [0, 1) again */
    float step = 2.0f * RESTIRCL_PI / (float)n;
    float a0 = rotation + (k + 0.5f) * step, a1 = a0 + step;
    /* uniform in the triangle: sqrt(r) picks the distance from the centre, v the place along the far edge */
    float s = sqrt(r);
    float b = s * v, a = s - b;
    return (float2)(a * cos(a0) + b * cos(a1), a * sin(a0) + b * sin(a1));
}

/* The point of the aperture (camera right, up; world units) for (u, v) in [0, 1)^2. */
inline float2 lens_point(const __global Camera* cam, float2 uv)
{
    int blades = (int)cam->aperture.z;
    float2 q = blades >= 3 ? lens_polygon(blades, cam->aperture.w, uv.x, uv.y) : concentric_disk(uv.x, uv.y);
    return (float2)(q.x / cam->aperture.y, q.y) * cam->aperture.x;
}

/* This frame's (u, v) of pixel i's lens point. */
inline float2 lens_uv(const FrameParams* fp, int i)
{
    Qmc q = qmc_stream(fp->qmc, fp->qmc_index, fp->qmc_key, (uint)i);
    if (q.on) return qmc_pair(&q, QMC_LENS);
    uint rng = rng_seed((uint)i, fp->sample, fp->seed, RNG_PASS_LENS);
    float u = rng_next(&rng);
    return (float2)(u, rng_next(&rng));
}

/* The camera ray of continuous pixel (px, py) through the lens point uv: origin *o and unit direction *d. The
 * pinhole ray (camera_ray) meets the plane in focus at f; the ray leaves the lens point towards f. */
inline void camera_lens_ray(const __global Camera* cam, float px, float py, float2 uv, float3* o, float3* d)
{
    float3 o0, d0;
    camera_ray(cam, px, py, &o0, &d0);
    float t = cam->focus.x / dot3(d0, cam->forward.xyz);  /* the plane in focus is at that depth along forward */
    float3 f = o0 + t * d0;
    float2 l = lens_point(cam, uv);
    *o = o0 + l.x * cam->right.xyz + l.y * cam->up.xyz;
    *d = norm3(f - *o);
}

#endif
#endif
