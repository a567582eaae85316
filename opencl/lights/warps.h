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

#endif
