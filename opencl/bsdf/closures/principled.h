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

/* The closure's diffuse albedo (returned) at weight w > 0 and clamped Base Color base, and its lobes (lobes[0 ..
 * *count)) for view cosine mu: the reflection lobe when it has a metallic or a specular part (with a Thin Film,
 * bsdf/closures/principled_thin_film.h, a thin-film lobe per part), the transmission's. */
inline float3 principled_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                                 Lobe* lobes, int* count)
{
#ifdef HAS_THIN_FILM  /* a Thin Film replaces the Fresnel of both parts, their weights stay */
    bool film = principled_has_film(c);
    float3 spec_mu = (float3)(0.0f);  /* the filmed specular's Fresnel at mu */
#else
    const bool film = false;
#endif
    ClosureGgx g = closure_ggx(c, mu, tab);
    MicrofacetReflection m = microfacet_reflection_none(g.alpha);
    bool metal = false, specular = false;
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
        metal = true;
    }
    float wr = w * (1.0f - metallic);
#ifdef HAS_TRANSMISSION  /* Transmission Weight: that share of the dielectric part is glass (bsdf/closures/glass.h) */
    float wt = principled_transmission_split(c, &wr);
#endif
    float f0;
    float eta = principled_specular_eta(c, &f0);
    float3 diffuse_w = (float3)(wr);
    /* an IOR below 1 (without a film, of 1 too): no reflection modelled (no transmission) */
    if (wr > CLOSURE_WEIGHT_CUTOFF && (eta > 1.0f || (film && eta == 1.0f))) {
        float3 df0 = saturate3((float3)(f0) * tint);
        float f0_eta = f0_from_ior(eta);
        float s_avg = clamp_f((fresnel_dielectric_avg(eta) - f0_eta) / (1.0f - f0_eta), 0.0f, 1.0f);
        float3 comp = g.ms ? multiscatter_factor(mix3(df0, (float3)(1.0f), s_avg), g.e, g.e_avg) : (float3)(1.0f);
        m.eta = eta;
        m.f0_eta = f0_eta;
        m.diel_f0 = df0;
        m.diel_w = (float3)(wr) * comp;
        specular = true;
        /* layering: the diffuse gets what the specular's estimated albedo at this view leaves */
        float3 albedo;
#ifdef HAS_THIN_FILM
        if (film) {
            spec_mu = principled_film_specular(c, &m, mu);
            albedo = comp * spec_mu;
        } else
#endif
        {
            sample_w += avg3(m.diel_w * fresnel_principled(mu, eta, f0_eta, df0));
            float3 darkening = g.ms ? comp * g.e : (float3)(1.0f);
            albedo = darkening * mix3(df0, (float3)(1.0f), ggx_fresnel_blend(tab, g.r, mu, eta));
        }
        diffuse_w *= clamp_f(1.0f - max3_f(albedo), 0.0f, 1.0f);
    }
    *count = 0;
#ifdef HAS_THIN_FILM
    if (film) principled_film_lobes(c, &m, metal, specular, spec_mu, mu, lobes, count);
#endif
    /* a lobe that reflects only at grazing half vectors still needs a chance to be sampled */
    if (!film && (metal || specular))
        lobes[(*count)++] = microfacet_reflection_lobe(&m, fmax_f(sample_w, 1e-3f * (avg3(m.metal_w) +
                                                                                        avg3(m.diel_w))));
#ifdef HAS_TRANSMISSION
    if (wt > CLOSURE_WEIGHT_CUTOFF && *count < MAX_LAYERS)  /* Thin Wall: a sheet (bsdf/closures/thin_wall.h) */
        lobes[(*count)++] = c->thin_wall ? principled_thin_wall_lobe(c, wt, base, mu, tab)
                                         : principled_glass_lobe(c, wt, base, mu, tab);
#endif
    return base * diffuse_w;
}

#endif
