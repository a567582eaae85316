/* Maps of a sample (u, v) in [0,1)^2 onto the shapes lights are made of: a disk, the sphere of directions, a cone;
 * and the orthonormal basis they are built in. */
#ifndef RESTIRCL_LIGHTS_WARPS_H
#define RESTIRCL_LIGHTS_WARPS_H

#include "numerics.h"

#define RESTIRCL_PI 3.14159265358979f
#define RESTIRCL_INV_PI 0.318309886183791f

/* Orthonormal basis around unit n (Duff et al. 2017). */
inline void light_onb(float3 n, float3* s, float3* t)
{
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    *s = (float3)(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *t = (float3)(b, sign + n.y * n.y * a, -n.y);
}

/* Shirley-Chiu concentric map of [0,1)^2 to the unit disk. */
inline float2 concentric_disk(float u, float v)
{
    float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
    if (a == 0.0f && b == 0.0f) return (float2)(0.0f, 0.0f);
    float r, phi;
    if (abs_f(a) > abs_f(b)) { r = a; phi = (RESTIRCL_PI * 0.25f) * (b / a); }
    else { r = b; phi = (RESTIRCL_PI * 0.5f) - (RESTIRCL_PI * 0.25f) * (a / b); }
    return (float2)(r * cos(phi), r * sin(phi));
}

/* Unit sphere direction <-> (u, v): u = (z + 1) / 2, v = azimuth / 2pi. */
inline float3 sphere_dir(float u, float v)
{
    float z = 2.0f * u - 1.0f;
    float rxy = sqrt(fmax_f(0.0f, 1.0f - z * z));
    float phi = 2.0f * RESTIRCL_PI * v;
    return (float3)(rxy * cos(phi), rxy * sin(phi), z);
}

inline float2 sphere_uv(float3 d)
{
    float u = clamp_f(0.5f * (d.z + 1.0f), 0.0f, 1.0f);
    float v = atan2(d.y, d.x) * (0.5f * RESTIRCL_INV_PI);
    if (v < 0.0f) v += 1.0f;
    return (float2)(u, v >= 1.0f ? 0.0f : v);
}

/* Direction inside a cone around unit axis w with 1 - cos(half-angle) = omc, from (u, v) uniform in solid angle. */
inline float3 cone_dir(float3 w, float omc, float u, float v)
{
    float omc_t = u * omc;                              /* 1 - cos(theta), exact for tiny cones */
    float sin_t = sqrt(fmax_f(0.0f, omc_t * (2.0f - omc_t)));
    float phi = 2.0f * RESTIRCL_PI * v;
    float3 s, t;
    light_onb(w, &s, &t);
    return norm3(sin_t * cos(phi) * s + sin_t * sin(phi) * t + (1.0f - omc_t) * w);
}

/* Inverse of concentric_disk: the (u, v) in [0,1)^2 that maps to the point q of the unit disk. */
inline float2 concentric_disk_inverse(float2 q)
{
    float R = sqrt(q.x * q.x + q.y * q.y);
    if (!(R > 0.0f)) return (float2)(0.5f, 0.5f);
    /* forward: |a| > |b| gives r = a, phi = pi/4 b/a; else r = b, phi = pi/2 - pi/4 a/b; r may be negative, so a
     * point of the left (lower) half has r = -R and phi the angle of -q */
    float a, b;
    if (abs_f(q.x) >= abs_f(q.y)) {
        a = q.x >= 0.0f ? R : -R;
        float phi = q.x >= 0.0f ? atan2(q.y, q.x) : atan2(-q.y, -q.x);
        b = a * phi * (4.0f * RESTIRCL_INV_PI);
    } else {
        b = q.y >= 0.0f ? R : -R;
        float phi = q.y >= 0.0f ? atan2(q.y, q.x) : atan2(-q.y, -q.x);
        a = b * (RESTIRCL_PI * 0.5f - phi) * (4.0f * RESTIRCL_INV_PI);
    }
    return (float2)(clamp_f(0.5f * (a + 1.0f), 0.0f, 0.99999994f), clamp_f(0.5f * (b + 1.0f), 0.0f, 0.99999994f));
}

/* Inverse of cone_dir: the (u, v) of unit direction d near the cone around unit w with 1 - cos = omc. 1 - cos is
 * computed from the sine (|d - (d.w) w|^2 / (1 + cos)), exact for tiny cones where 1 - d.w would cancel. */
inline float2 cone_dir_inverse(float3 w, float omc, float3 d)
{
    float3 s, t;
    light_onb(w, &s, &t);
    float ds = dot3(d, s), dt = dot3(d, t), c = dot3(d, w);
    float omc_t = (ds * ds + dt * dt) / (1.0f + c);
    float v = atan2(dt, ds) * (0.5f * RESTIRCL_INV_PI);
    if (v < 0.0f) v += 1.0f;
    return (float2)(omc_t / omc, v >= 1.0f ? 0.0f : v);  /* u >= 1: outside the cone */
}

#endif
