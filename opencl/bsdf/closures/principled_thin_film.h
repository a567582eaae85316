/* The Principled BSDF with a Thin Film (Thickness > THIN_FILM_CUTOFF; bsdf/closures/principled.h hands such a
 * closure here), and Cycles' Metallic BSDF with one (a Principled of Metallic 1): the model of principled.h with the
 * film's Fresnel (bsdf/thin_film.h) in place of the metal's F82 curve and of the specular's dielectric curve, and in
 * the transmission's (bsdf/closures/glass.h passes the film to the dielectric lobe). As Cycles:
 *   metal     the film over the F82-tint metal of f0 = the clamped Base Color, tint = Specular Tint;
 *   specular  the film over a dielectric of the specular's IOR (the Specular IOR Level's), each channel scaled
 *             towards f0 / F0(IOR) (thin_film_specular); a film makes a specular part even at IOR 1;
 *   diffuse   Lambert under the specular, weighted 1 - max(the specular's albedo at this view), that albedo being
 *             the film's Fresnel at the macroscopic normal (no tables of the film's albedo; Cycles' estimate);
 * multiscatter GGX compensates each part's energy as without the film. The film needs lanes the plain reflection
 * lobe uses for the other part, so a closure with both a metal and a specular part makes two thin-film lobes. */
#ifndef RESTIRCL_BSDF_CLOSURES_PRINCIPLED_THIN_FILM_H
#define RESTIRCL_BSDF_CLOSURES_PRINCIPLED_THIN_FILM_H

#include "bsdf/closure.h"
#include "bsdf/thin_film_reflection.h"
#ifdef HAS_TRANSMISSION
#include "bsdf/closures/glass.h"
#endif

/* the film's lobe of a part with Fresnel F(mu) at view cosine mu: sampled by what it reflects there */
inline Lobe principled_film_lobe(const ThinFilmReflection* m, float3 f_mu)
{
    return thin_film_reflection_lobe(m, fmax_f(avg3(m->w * f_mu), 1e-3f * avg3(m->w)));
}

/* The closure's diffuse albedo (returned) at weight w > 0 and clamped Base Color base, and its lobes (lobes[0 ..
 * *count)): a metal's, a specular's and, with a Transmission Weight, the glass's, for view cosine mu. */
inline float3 principled_thin_film_resolve(const ClosureInputs* c, float w, float3 base, float mu,
                                           const __global float* tab, Lobe* lobes, int* count)
{
    ClosureGgx g = closure_ggx(c, mu, tab);
    ThinFilmReflection m;
    m.alpha = g.alpha;
    m.thickness = c->film_thickness;
    m.film_ior = fmax_f(c->film_ior, 1e-5f);
    *count = 0;
    float metallic = clamp_f(c->metallic, 0.0f, 1.0f);
    float3 tint = max0_3(c->tint);
    if (metallic > CLOSURE_WEIGHT_CUTOFF) {
        float3 f0 = saturate3(base);
        float3 f82 = (float3)(fmin_f(tint.x, 1.0f), fmin_f(tint.y, 1.0f), fmin_f(tint.z, 1.0f));
        float3 b = fresnel_f82_b(f0, f82);
        m.f0 = f0;
        m.g = fresnel_f82(1.0f / 7.0f, f0, b);
        m.eta = 0.0f;
        m.w = (float3)(w * metallic) * (g.ms ? multiscatter_factor(fresnel_f82_avg(f0, b), g.e, g.e_avg)
                                               : (float3)(1.0f));
        lobes[(*count)++] = principled_film_lobe(&m, thin_film_metal(mu, f0, m.g, m.thickness, m.film_ior));
    }
    float wr = w * (1.0f - metallic);
#ifdef HAS_TRANSMISSION
    float wt = principled_transmission_split(c, &wr);
#endif
    float f0;
    float eta = principled_specular_eta(c, &f0);
    float3 diffuse_w = (float3)(wr);
    if (wr > CLOSURE_WEIGHT_CUTOFF && eta >= 1.0f) {  /* an IOR < 1: no reflection modelled (as principled.h) */
        float3 df0 = saturate3((float3)(f0) * tint);
        float3 comp = (float3)(1.0f);
        if (g.ms) {
            float f0_eta = f0_from_ior(eta);
            float s_avg = f0_eta < 1.0f ? clamp_f((fresnel_dielectric_avg(eta) - f0_eta) / (1.0f - f0_eta), 0.0f,
                                                  1.0f) : 1.0f;
            comp = multiscatter_factor(mix3(df0, (float3)(1.0f), s_avg), g.e, g.e_avg);
        }
        m.f0 = df0;
        m.g = (float3)(0.0f);
        m.eta = eta;
        m.w = (float3)(wr) * comp;
        float3 f_mu = thin_film_specular(mu, eta, df0, m.thickness, m.film_ior);
        if (*count < MAX_LAYERS) lobes[(*count)++] = principled_film_lobe(&m, f_mu);
        /* layering: the diffuse gets what the specular's estimated albedo at this view leaves, that albedo being
         * (as Cycles estimates a film's) its weight times the film's Fresnel at the macroscopic normal */
        diffuse_w *= clamp_f(1.0f - max3_f(comp * f_mu), 0.0f, 1.0f);
    }
#ifdef HAS_TRANSMISSION
    if (wt > CLOSURE_WEIGHT_CUTOFF && *count < MAX_LAYERS)  /* a Thin Wall stays a sheet (without the film) */
        lobes[(*count)++] = c->thin_wall ? principled_thin_wall_lobe(c, wt, base, mu, tab)
                                         : principled_glass_lobe(c, wt, base, mu, tab);
#endif
    return base * diffuse_w;
}

#endif
