/* The GGX reflection lobe under a thin film (bsdf/thin_film.h): one part of a Principled BSDF with a Thin Film, its
 * metal (F82-tint, Cycles' Metallic BSDF too) or its dielectric specular, whose Fresnel the film replaces. The
 * distribution, its pdf and sampling are bsdf/microfacet_reflection.h's (they read only alpha); f is D G2 /
 * (4 cos_o cos_i) (bsdf/ggx.h ggx_reflection) times the weight times the film's Fresnel at the half vector. A closure with both parts makes two
 * of these (bsdf/closures/principled.h): the film needs the record's lanes that microfacet_reflection.h gives the
 * other part. The weight includes the closure's weight and, for multiscatter GGX, the energy compensation of the
 * part without its film, as Cycles (no tables of the film's albedo). */
#ifndef RESTIRCL_BSDF_THIN_FILM_REFLECTION_H
#define RESTIRCL_BSDF_THIN_FILM_REFLECTION_H

#include "bsdf/microfacet_reflection.h"
#include "bsdf/thin_film.h"

#define LOBE_THIN_FILM_REFLECTION 3

typedef struct {
    float3 f0_n;      /* a.xyz: dielectric: F0 x Specular IOR Level x Specular Tint; metal: n of its complex IOR */
    float alpha;      /* a.w: roughness^2, clamped to GGX_ALPHA_MIN */
    float3 g;         /* b.xyz: metal: the F82-tint curve's value at cos = 1/7; dielectric: unused */
    float eta;        /* b.w: dielectric: the relative IOR under the film; 0: a metal */
    float3 w;         /* c.xyz: weight */
    float thickness;  /* c.w: the film's thickness (nm) */
    float film_ior;   /* d.x: the film's IOR */
    float3 k;         /* e.xyz: metal: k of its complex IOR n + ik (thin_film_metal_ior, once per lobe); dielectric:
                       * unused */
} ThinFilmReflection;

inline ThinFilmReflection thin_film_reflection(const Lobe* l)
{
    ThinFilmReflection m = {l->a.xyz, l->a.w, l->b.xyz, l->b.w, l->c.xyz, l->c.w, l->d.x, l->e.xyz};
    return m;
}

/* A metal's part: the F82-tint metal of f0 (the clamped Base Color) and 82-degree value g, of weight w, under a film
 * of thickness d and IOR n_f, and GGX alpha */
inline ThinFilmReflection thin_film_reflection_metal(float3 f0, float3 g, float3 w, float d, float n_f, float alpha)
{
    ThinFilmReflection m;
    m.f0_n = thin_film_metal_ior(f0, g, &m.k);
    m.alpha = alpha;
    m.g = g;
    m.eta = 0.0f;
    m.w = w;
    m.thickness = d;
    m.film_ior = n_f;
    return m;
}

/* A dielectric specular's part: the dielectric of relative IOR eta and f0 (F0 x Specular IOR Level x Specular Tint),
 * of weight w, under a film of thickness d and IOR n_f, and GGX alpha */
inline ThinFilmReflection thin_film_reflection_specular(float3 f0, float eta, float3 w, float d, float n_f,
                                                        float alpha)
{
    ThinFilmReflection m = {f0, alpha, (float3)(0.0f), eta, w, d, n_f, (float3)(0.0f)};
    return m;
}

inline Lobe thin_film_reflection_lobe(const ThinFilmReflection* m, float weight)
{
    Lobe l = lobe_record(LOBE_THIN_FILM_REFLECTION, m->alpha, weight);
    l.a.xyz = m->f0_n;
    l.b = (float4)(m->g, m->eta);
    l.c = (float4)(m->w, m->thickness);
    l.d.x = m->film_ior;
    l.e.xyz = m->k;
    return l;
}

/* the film's Fresnel at cosine c (without the weight) */
inline float3 thin_film_reflection_fresnel(const ThinFilmReflection* m, float c)
{
    return m->eta > 0.0f ? thin_film_specular(c, m->eta, m->f0_n, m->thickness, m->film_ior)
                         : thin_film_metal_nk(c, m->f0_n, m->k, m->g, m->thickness, m->film_ior);
}

inline float3 thin_film_reflection_eval(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    float co = dot3(n, wo), ci = dot3(n, wi);
    if (co < GGX_COS_MIN || ci < GGX_COS_MIN) return (float3)(0.0f);
    ThinFilmReflection m = thin_film_reflection(l);
    float pdf, c_h;
    float f = ggx_reflection(m.alpha, n, wo, wi, co, ci, &pdf, &c_h);
    return m.w * thin_film_reflection_fresnel(&m, c_h) * f;
}

inline float thin_film_reflection_pdf(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    return microfacet_reflection_pdf(l, n, wo, wi);
}

inline bool thin_film_reflection_sample(const Lobe* l, float3 n, float3 wo, float u0, float u1, float3* wi)
{
    return microfacet_reflection_sample(l, n, wo, u0, u1, wi);
}

/* what it reflects at normal incidence: the denoiser's guide albedo */
inline float3 thin_film_reflection_albedo(const Lobe* l)
{
    ThinFilmReflection m = thin_film_reflection(l);
    return m.w * thin_film_reflection_fresnel(&m, 1.0f);
}

/* its weight summed over rgb: x for a metal, y for a dielectric (reuse compares the metallic share) */
inline float2 thin_film_reflection_weights(const Lobe* l)
{
    ThinFilmReflection m = thin_film_reflection(l);
    float s = m.w.x + m.w.y + m.w.z;
    return m.eta > 0.0f ? (float2)(0.0f, s) : (float2)(s, 0.0f);
}

#endif
