/* The Glass BSDF, and what the Refraction BSDF (bsdf/closures/refraction.h) and the Principled BSDF's transmission
 * share with it: a dielectric interface
 * (bsdf/microfacet_dielectric.h), resolved for one view. Cycles 4.x/5.x: alpha = Roughness^2, the IOR at least
 * 1e-5 and inverted where the ray leaves through a back face; the Glass BSDF tints reflection and refraction by its
 * Color, the Refraction BSDF refracts only (no Fresnel, Color as its weight), the Principled BSDF reflects with f0
 * = F0(IOR) x Specular Tint and tints the refraction by sqrt(Base Color). A Roughness whose alpha^2 is at most
 * 2e-10 is Cycles' delta interface: the lobe keeps GGX_ALPHA_MIN and is marked smooth. Multiscatter GGX scales the
 * lobe by its energy compensation (dielectric_closure_lobe). No diffuse part. */
#ifndef RESTIRCL_BSDF_CLOSURES_GLASS_H
#define RESTIRCL_BSDF_CLOSURES_GLASS_H

#include "bsdf/closure.h"
#include "bsdf/microfacet_dielectric.h"

/* E (returned) and *e_avg of the clear dielectric lobe of roughness r at view cosine mu and relative IOR eta: the
 * tables of upload/glass_tables.py, indexed by z = sqrt(|(IOR - 1) / (IOR + 1)|) of eta or, seen from inside
 * (eta < 1), of 1 / eta in their own tables */
inline float glass_albedo(const __global float* tab, float r, float mu, float eta, float* e_avg)
{
    bool inside = eta < 1.0f;
    float ior = inside ? 1.0f / eta : eta;
    float z = sqrt(abs_f((ior - 1.0f) / (ior + 1.0f)));
    *e_avg = fmax_f(table_2d(tab, inside ? GLASS_E_INV_AVG_OFFSET : GLASS_E_AVG_OFFSET, r, z, GLASS_SIZE), 1e-3f);
    return fmax_f(table_3d(tab, inside ? GLASS_E_INV_OFFSET : GLASS_E_OFFSET, r, mu, z, GLASS_SIZE), 1e-3f);
}

/* The dielectric lobe of a closure c for view cosine mu, reflection tint `reflect`, refraction tint `transmit`,
 * reflectance at normal incidence f0 (rgb). Multiscatter GGX (not for the Refraction BSDF, which Cycles has no
 * Multiscatter GGX for) scales the lobe by 1 + F_ms (1 - E) / E, the single-scattering average F_ss being the
 * refraction's tint `fss` (as Cycles: the transmitted colour makes most of a glass's), so clear glass keeps all
 * the energy at every roughness. */
inline Lobe dielectric_closure_lobe(const ClosureInputs* c, float mu, float3 reflect, float3 transmit, float3 f0,
                                    bool no_fresnel, float3 fss, const __global float* tab)
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
    /* Thin Film: Cycles rescales the film's IOR by the glass's where the ray leaves through a back face (the stack
     * glass | film | air seen as air | film / IOR | 1 / IOR) */
    m.film_thickness = 0.0f;
    m.film_ior = 0.0f;
#ifdef HAS_THIN_FILM
    if (!no_fresnel && c->film_thickness > THIN_FILM_CUTOFF) {
        m.film_thickness = c->film_thickness;
        m.film_ior = fmax_f(c->film_ior, 1e-5f) / (c->backfacing ? ior : 1.0f);
    }
#endif
    if (c->multiscatter && !no_fresnel && !dielectric_passes(&m)) {
        float e_avg, e = glass_albedo(tab, r, mu, m.eta, &e_avg);
        float3 k = multiscatter_factor(fss, e, e_avg);
        m.reflect *= k;
        m.transmit *= k;
    }
    float3 t;
    float3 rr = dielectric_fresnel(&m, mu, &t);
    /* the sampling weight: what it scatters at the macroscopic normal (reflected plus transmitted) */
    return microfacet_dielectric_lobe(&m, fmax_f(avg3(rr + t), 1e-3f * avg3(reflect + transmit)));
}

/* Glass BSDF: its lobe (lobes[0], *count = 1), no diffuse part */
inline float3 glass_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                            Lobe* lobes, int* count)
{
    float3 col = base * w;
    lobes[0] = dielectric_closure_lobe(c, mu, col, col, (float3)(f0_from_ior(fmax_f(c->ior, 1e-5f))), false, base,
                                       tab);
    *count = 1;
    return (float3)(0.0f);
}

/* The Principled BSDF's transmission at weight wt (its closure weight x (1 - Metallic) x Transmission Weight) */
inline Lobe principled_glass_lobe(const ClosureInputs* c, float wt, float3 base, float mu, const __global float* tab)
{
    float3 tint = max0_3(c->tint);
    float3 f0 = saturate3((float3)(f0_from_ior(fmax_f(c->ior, 1e-5f))) * tint);
    float3 sb = saturate3(base);
    float3 through = (float3)(sqrt(sb.x), sqrt(sb.y), sqrt(sb.z));
    return dielectric_closure_lobe(c, mu, (float3)(wt), through * wt, f0, false, through, tab);
}

#endif
