/* The slab of a thin wall (Blender 5.3's Principled Thin Wall) seen at cosine mu: what it reflects and lets through,
 * its internal reflections summed, as Cycles 5.3 has it. Both the wall's lobe (bsdf/closures/thin_wall.h) and shadow
 * rays through a smooth wall (bvh/thin_wall_shadow.h) read it, so the light they pass is the same:
 *   - each face has the Principled's dielectric Fresnel at mu: the real curve of the IOR remapped onto [f0, 1],
 *     f0 = F0(IOR) x Specular Tint (r); it lets 1 - r through (t); both faces are an entry (no inverted IOR);
 *   - inside, the Base Color c0 is the transmittance at normal incidence, c = c0^(1 / cos_t) along the refracted
 *     cosine cos_t (Beer-Lambert; 0 under total internal reflection);
 *   - T = c t^2 / (1 - (r c)^2), R = r + T r c. */
#ifndef RESTIRCL_BSDF_THIN_WALL_SLAB_H
#define RESTIRCL_BSDF_THIN_WALL_SLAB_H

#include "bsdf/fresnel.h"

/* T of the slab of IOR ior (> 0), Specular Tint tint and Base Color base at view cosine mu; its R in *R */
inline float3 thin_wall_slab(float mu, float ior, float3 tint, float3 base, float3* R)
{
    float f0_eta = f0_from_ior(ior);
    float3 r = fresnel_principled(mu, ior, f0_eta, (float3)(f0_eta) * tint);
    float3 t = (float3)(1.0f) - r;
    float ct2 = 1.0f - (1.0f - mu * mu) / (ior * ior);
    float3 c0 = saturate3(base);
    float3 k = (float3)(0.0f);
    if (ct2 > 0.0f) {
        float e = 1.0f / sqrt(ct2);
        k = (float3)(pow(c0.x, e), pow(c0.y, e), pow(c0.z, e));
    }
    float3 rc = r * k;
    float3 T = k * t * t / ((float3)(1.0f) - rc * rc);
    *R = r + T * rc;
    return T;
}

#endif
