/* The Glass BSDF, and what the Refraction BSDF (bsdf/closures/refraction.h) and the Principled BSDF's transmission
 * share with it: a dielectric interface
 * (bsdf/microfacet_dielectric.h), resolved for one view. Cycles 4.x/5.x: alpha = Roughness^2, the IOR at least
 * 1e-5 and inverted where the ray leaves through a back face; the Glass BSDF tints reflection and refraction by its
 * Color, the Refraction BSDF refracts only (no Fresnel, Color as its weight), the Principled BSDF reflects with f0
 * = F0(IOR) x Specular Tint and tints the refraction by sqrt(Base Color). A Roughness whose alpha^2 is at most
 * 2e-10 is Cycles' delta interface: the lobe keeps GGX_ALPHA_MIN and is marked smooth. Multiscatter GGX is not
 * modelled for these lobes (Cycles' energy tables for glass): they scatter once. No diffuse part. */
#ifndef RESTIRCL_BSDF_CLOSURES_GLASS_H
#define RESTIRCL_BSDF_CLOSURES_GLASS_H

#include "bsdf/closure.h"
#include "bsdf/microfacet_dielectric.h"

/* The dielectric lobe of a closure c for view cosine mu, reflection tint `reflect`, refraction tint `transmit`,
 * reflectance at normal incidence f0 (rgb) */
inline Lobe dielectric_closure_lobe(const ClosureInputs* c, float mu, float3 reflect, float3 transmit, float3 f0,
                                    bool no_fresnel)
{
    float r = clamp_f(c->roughness, 0.0f, 1.0f);
    float ior = fmax_f(c->ior, 1e-5f);
    MicrofacetDielectric m;
    m.reflect = reflect;
    m.transmit = transmit;
    m.alpha = fmax_f(r * r, GGX_ALPHA_MIN);
    m.eta = c->backfacing ? 1.0f / ior : ior;
    m.f0 = f0;
    m.smooth = (r * r) * (r * r) <= 2e-10f ? 1.0f : 0.0f;
    m.no_fresnel = no_fresnel ? 1.0f : 0.0f;
    m.p_reflect = dielectric_p_reflect(&m, mu);
    float3 t;
    float3 rr = dielectric_fresnel(&m, mu, &t);
    /* the sampling weight: what it scatters at the macroscopic normal (reflected plus transmitted) */
    return microfacet_dielectric_lobe(&m, fmax_f(avg3(rr + t), 1e-3f * avg3(reflect + transmit)));
}

/* Glass BSDF: its lobe (lobes[0], *count = 1), no diffuse part */
inline float3 glass_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                            Lobe* lobes, int* count)
{
    (void)tab;
    float3 col = base * w;
    lobes[0] = dielectric_closure_lobe(c, mu, col, col, (float3)(f0_from_ior(fmax_f(c->ior, 1e-5f))), false);
    *count = 1;
    return (float3)(0.0f);
}

/* The Principled BSDF's transmission at weight wt (its closure weight x (1 - Metallic) x Transmission Weight) */
inline Lobe principled_glass_lobe(const ClosureInputs* c, float wt, float3 base, float mu)
{
    float3 tint = max0_3(c->tint);
    float3 f0 = saturate3((float3)(f0_from_ior(fmax_f(c->ior, 1e-5f))) * tint);
    float3 sb = saturate3(base);
    float3 transmit = (float3)(sqrt(sb.x), sqrt(sb.y), sqrt(sb.z)) * wt;
    return dielectric_closure_lobe(c, mu, (float3)(wt), transmit, f0, false);
}

#endif
