/* The diffuse part every surface has: Lambert, f = albedo / pi about the shading normal n, sampled by a cosine
 * direction (density cos / pi). Its parameter is the surface's diffuse albedo (SurfaceMaterial.albedo, under the
 * specular layer already scaled for it), not a Lobe record: a diffuse-only build has this part alone. */
#ifndef RESTIRCL_BSDF_LAMBERT_H
#define RESTIRCL_BSDF_LAMBERT_H

#include "sampling/warps.h"

/* f does not depend on the directions: no branch, as it runs once per RIS candidate */
inline float3 lambert_eval(float3 albedo) { return albedo * RESTIRCL_INV_PI; }

/* the solid-angle density of lambert_sample's wi: cos / pi in the hemisphere of n, 0 below it */
inline float lambert_pdf(float3 n, float3 wi)
{
    float c = dot3(n, wi);
    return c > 0.0f ? c * RESTIRCL_INV_PI : 0.0f;
}

/* a concentric-disk point of (u0, u1) in [0, 1)^2 lifted onto the hemisphere of n */
inline float3 lambert_sample(float3 n, float u0, float u1)
{
    float2 d = concentric_disk(u0, u1);
    float z = sqrt(fmax_f(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    float3 t, b;
    light_onb(n, &t, &b);
    return d.x * t + d.y * b + z * n;
}

/* its sampling weight in the BSDF's mixture: the albedo's average (what it reflects of uniform light) */
inline float lambert_weight(float3 albedo) { return (albedo.x + albedo.y + albedo.z) * (1.0f / 3.0f); }

#endif
