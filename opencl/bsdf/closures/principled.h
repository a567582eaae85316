/* The Principled BSDF as Cycles 4.x/5.0 defines it, without coat, sheen and subsurface, resolved for one view into a
 * diffuse albedo, one GGX reflection lobe (bsdf/microfacet_reflection.h) and, with a Transmission Weight t > 0 in
 * builds that transmit, a dielectric lobe of weight w (1 - metallic) t (bsdf/closures/glass.h) that takes t of the
 * specular and the diffuse below:
 *   metal     weight w * metallic, F82-tint Fresnel from the clamped Base Color with Specular Tint as the tint;
 *   specular  weight w * (1 - metallic), the real dielectric Fresnel of the IOR remapped onto [f0, 1], f0 = F0(IOR)
 *             scaled by 2 * Specular IOR Level (0.5: unchanged; 0: no specular) times Specular Tint;
 *   diffuse   Lambert, Base Color * w * (1 - metallic) * (1 - the specular's estimated albedo at this view), the
 *             albedo-scaling layering that keeps diffuse + specular <= 1;
 * metal and specular share one GGX distribution (alpha = Roughness^2). Multiscatter GGX scales each part by
 * 1 + F_ms (1 - E) / E (bsdf/closure.h), which makes a white metal reflect all the energy at every roughness. */
#ifndef RESTIRCL_BSDF_CLOSURES_PRINCIPLED_H
#define RESTIRCL_BSDF_CLOSURES_PRINCIPLED_H

#include "bsdf/closure.h"
#include "bsdf/microfacet_reflection.h"
#ifdef HAS_TRANSMISSION
#include "bsdf/closures/glass.h"
#include "bsdf/closures/thin_wall.h"
#endif
#ifdef HAS_THIN_FILM
#include "bsdf/closures/principled_thin_film.h"
#endif

/* The closure's diffuse albedo (returned) at weight w > 0 and clamped Base Color base, and its lobe (lobes[0],
 * *count = 1) when it has a metallic or a specular part, for view cosine mu. */
inline float3 principled_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                                 Lobe* lobes, int* count)
{
#ifdef HAS_THIN_FILM  /* a Thin Film changes every Fresnel of the closure */
    if (c->film_thickness > THIN_FILM_CUTOFF) return principled_thin_film_resolve(c, w, base, mu, tab, lobes, count);
#endif
    ClosureGgx g = closure_ggx(c, mu, tab);
    MicrofacetReflection m = microfacet_reflection_none(g.alpha);
    bool has_lobe = false;
    float metallic = clamp_f(c->metallic, 0.0f, 1.0f);
    float3 tint = max0_3(c->tint);
    float sample_w = 0.0f;
    if (metallic > CLOSURE_WEIGHT_CUTOFF) {
        float3 f0 = saturate3(base);
        float3 f82 = (float3)(fmin_f(tint.x, 1.0f), fmin_f(tint.y, 1.0f), fmin_f(tint.z, 1.0f));
        float3 b = (f82.x == 1.0f && f82.y == 1.0f && f82.z == 1.0f) ? (float3)(0.0f) : fresnel_f82_b(f0, f82);
        m.metal_f0 = f0;
        m.metal_b = b;
        m.metal_w = (float3)(w * metallic) * (g.ms ? multiscatter_factor(fresnel_f82_avg(f0, b), g.e, g.e_avg)
                                                   : (float3)(1.0f));
        sample_w += avg3(m.metal_w * fresnel_f82(mu, f0, b));
        has_lobe = true;
    }
    float wr = w * (1.0f - metallic);
#ifdef HAS_TRANSMISSION  /* Transmission Weight: that share of the dielectric part is glass (bsdf/closures/glass.h) */
    float wt = principled_transmission_split(c, &wr);
#endif
    float f0;
    float eta = principled_specular_eta(c, &f0);
    float3 diffuse_w = (float3)(wr);
    if (wr > CLOSURE_WEIGHT_CUTOFF && eta > 1.0f) {  /* an IOR <= 1: no reflection modelled (no transmission) */
        float3 df0 = saturate3((float3)(f0) * tint);
        float f0_eta = f0_from_ior(eta);
        float s_avg = clamp_f((fresnel_dielectric_avg(eta) - f0_eta) / (1.0f - f0_eta), 0.0f, 1.0f);
        float3 darkening = (float3)(1.0f);
        float3 comp = (float3)(1.0f);
        if (g.ms) {
            comp = multiscatter_factor(mix3(df0, (float3)(1.0f), s_avg), g.e, g.e_avg);
            darkening = comp * g.e;
        }
        m.eta = eta;
        m.f0_eta = f0_eta;
        m.diel_f0 = df0;
        m.diel_w = (float3)(wr) * comp;
        sample_w += avg3(m.diel_w * fresnel_principled(mu, eta, f0_eta, df0));
        /* layering: the diffuse gets what the specular's estimated albedo at this view leaves */
        float3 albedo = darkening * mix3(df0, (float3)(1.0f), ggx_fresnel_blend(tab, g.r, mu, eta));
        diffuse_w *= clamp_f(1.0f - max3_f(albedo), 0.0f, 1.0f);
        has_lobe = true;
    }
    /* a lobe that reflects only at grazing half vectors still needs a chance to be sampled */
    lobes[0] = microfacet_reflection_lobe(&m, fmax_f(sample_w, 1e-3f * (avg3(m.metal_w) + avg3(m.diel_w))));
    *count = has_lobe ? 1 : 0;
#ifdef HAS_TRANSMISSION
    if (wt > CLOSURE_WEIGHT_CUTOFF)  /* Thin Wall: a sheet, not an interface (bsdf/closures/thin_wall.h) */
        lobes[(*count)++] = c->thin_wall ? principled_thin_wall_lobe(c, wt, base, mu, tab)
                                         : principled_glass_lobe(c, wt, base, mu, tab);
#endif
    return base * diffuse_w;
}

#endif
