/* The Principled BSDF's reflection under a Thin Film (Thickness > THIN_FILM_CUTOFF), and Cycles' Metallic BSDF's (a
 * Principled of Metallic 1): principled_resolve (bsdf/closures/principled.h) weighs the metal and the specular part
 * as without the film, multiscatter GGX's energy compensation included (as Cycles: no tables of the film's albedo),
 * and hands them here, where the film's Fresnel (bsdf/thin_film.h) replaces the metal's F82 curve and the
 * specular's dielectric curve (bsdf/closures/glass.h passes the film to the transmission's dielectric lobe):
 *   metal     the film over the F82-tint metal of f0 = the clamped Base Color, tint = Specular Tint;
 *   specular  the film over a dielectric of the specular's IOR (the Specular IOR Level's), each channel scaled
 *             towards f0 / F0(IOR) (thin_film_specular); a film makes a specular part even at IOR 1;
 *   diffuse   under the specular, weighted 1 - max(the specular's albedo at this view), that albedo being the
 *             film's Fresnel at the macroscopic normal (Cycles' estimate) times the compensation.
 * The film needs lanes the plain reflection lobe uses for the other part, so a closure with both a metal and a
 * specular part makes two thin-film lobes. */
#ifndef RESTIRCL_BSDF_CLOSURES_PRINCIPLED_THIN_FILM_H
#define RESTIRCL_BSDF_CLOSURES_PRINCIPLED_THIN_FILM_H

#include "bsdf/closure.h"
#include "bsdf/microfacet_reflection.h"
#include "bsdf/thin_film_reflection.h"

/* Whether closure c has a film */
inline bool principled_has_film(const ClosureInputs* c) { return c->film_thickness > THIN_FILM_CUTOFF; }

/* The specular part of r (principled_resolve's) under c's film: its Fresnel at view cosine mu */
inline float3 principled_film_specular(const ClosureInputs* c, const MicrofacetReflection* r, float mu)
{
    return thin_film_specular(mu, r->eta, r->diel_f0, c->film_thickness, fmax_f(c->film_ior, 1e-5f));
}

/* the film's lobe of a part with Fresnel F(mu) at view cosine mu: sampled by what it reflects there */
inline Lobe principled_film_lobe(const ThinFilmReflection* m, float3 f_mu)
{
    return thin_film_reflection_lobe(m, fmax_f(avg3(m->w * f_mu), 1e-3f * avg3(m->w)));
}

/* The thin-film lobes of r's parts under c's film, from lobes[*count] on: its metal's where `metal`, its specular's
 * (of Fresnel spec_mu at view cosine mu, principled_film_specular) where `specular`. */
inline void principled_film_lobes(const ClosureInputs* c, const MicrofacetReflection* r, bool metal, bool specular,
                                  float3 spec_mu, float mu, Lobe* lobes, int* count)
{
    float d = c->film_thickness, n_f = fmax_f(c->film_ior, 1e-5f);
    if (metal) {
        float3 g = fresnel_f82(1.0f / 7.0f, r->metal_f0, r->metal_b);
        ThinFilmReflection m = thin_film_reflection_metal(r->metal_f0, g, r->metal_w, d, n_f, r->alpha);
        lobes[(*count)++] = principled_film_lobe(&m, thin_film_reflection_fresnel(&m, mu));
    }
    if (specular && *count < MAX_LAYERS) {
        ThinFilmReflection m = thin_film_reflection_specular(r->diel_f0, r->eta, r->diel_w, d, n_f, r->alpha);
        lobes[(*count)++] = principled_film_lobe(&m, spec_mu);
    }
}

#endif
