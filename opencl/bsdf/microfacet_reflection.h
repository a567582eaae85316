/* The GGX reflection lobe: a Principled closure's metallic part (F82-tint Fresnel; a Glossy BSDF is one with f0 = 1
 * and b = 0, no Fresnel) and its dielectric specular (the real Fresnel of eta remapped from its F0 onto [f0, 1]),
 * sharing one GGX distribution (bsdf/ggx.h), about the lobes' normal. Reflection only: both directions above the
 * surface. The weights include the closure's weight and, for multiscatter GGX, the energy compensation for the
 * pixel's view (bsdf/closures/principled.h, glossy.h fill them). f excludes the cosine at the surface (the light
 * evaluation carries it), as everywhere behind the BSDF seam. */
#ifndef RESTIRCL_BSDF_MICROFACET_REFLECTION_H
#define RESTIRCL_BSDF_MICROFACET_REFLECTION_H

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/lobe_record.h"

#define LOBE_MICROFACET_REFLECTION 0

typedef struct {
    float3 metal_f0;  /* a.xyz: F82-tint f0 */
    float alpha;      /* a.w: roughness^2, clamped to GGX_ALPHA_MIN */
    float3 metal_b;   /* b.xyz: F82-tint b */
    float eta;        /* b.w: eta of the dielectric specular (1: none) */
    float3 metal_w;   /* c.xyz: weight of the metallic / Glossy part */
    float f0_eta;     /* c.w: F0 of eta */
    float3 diel_f0;   /* d.xyz: dielectric f0 (F0 scaled by the Specular IOR Level, times Specular Tint) */
    float3 diel_w;    /* e.xyz: weight of the dielectric specular */
} MicrofacetReflection;

inline MicrofacetReflection microfacet_reflection(const Lobe* l)
{
    MicrofacetReflection m = {l->a.xyz, l->a.w, l->b.xyz, l->b.w, l->c.xyz, l->c.w, l->d.xyz, l->e.xyz};
    return m;
}

/* No reflection yet, of roughness^2 alpha: what a closure's resolve starts from */
inline MicrofacetReflection microfacet_reflection_none(float alpha)
{
    MicrofacetReflection m = {(float3)(0.0f), alpha, (float3)(0.0f), 1.0f, (float3)(0.0f), 0.0f, (float3)(0.0f),
                              (float3)(0.0f)};
    return m;
}

/* The record of m with sampling weight `weight` */
inline Lobe microfacet_reflection_lobe(const MicrofacetReflection* m, float weight)
{
    Lobe l = lobe_record(LOBE_MICROFACET_REFLECTION, m->alpha, weight);
    l.a.xyz = m->metal_f0;
    l.b = (float4)(m->metal_b, m->eta);
    l.c = (float4)(m->metal_w, m->f0_eta);
    l.d.xyz = m->diel_f0;
    l.e.xyz = m->diel_w;
    return l;
}

/* f(wo, wi) about normal n: D G2 / (4 cos_o cos_i) (bsdf/ggx.h ggx_reflection) times the Fresnel-weighted colour,
 * the F82-tint part and the dielectric part sharing D and G2 (0 unless both directions are above the surface). */
inline float3 microfacet_reflection_eval(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    float co = dot3(n, wo), ci = dot3(n, wi);
    if (co < GGX_COS_MIN || ci < GGX_COS_MIN) return (float3)(0.0f);
    MicrofacetReflection m = microfacet_reflection(l);
    float pdf, c_hi;
    float f = ggx_reflection(m.alpha, n, wo, wi, co, ci, &pdf, &c_hi);
    float3 F = m.metal_w * fresnel_f82(c_hi, m.metal_f0, m.metal_b);
    if (m.eta > 1.0f)
        F += m.diel_w * fresnel_principled(c_hi, m.eta, m.f0_eta, m.diel_f0);
    return F * f;
}

/* The solid-angle density of microfacet_reflection_sample's wi: D G1(wo) / (4 cos_o) at the half vector (0 below
 * the surface) */
inline float microfacet_reflection_pdf(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    float co = dot3(n, wo), ci = dot3(n, wi);
    if (co < GGX_COS_MIN || ci < GGX_COS_MIN) return 0.0f;
    float pdf, c_h;
    (void)ggx_reflection(lobe_alpha(l), n, wo, wi, co, ci, &pdf, &c_h);
    return pdf;
}

/* Reflect wo about a visible normal drawn from (u0, u1): wi (which may point below the surface: its pdf is then 0).
 * false when wo is below the surface (nothing drawn). */
inline bool microfacet_reflection_sample(const Lobe* l, float3 n, float3 wo, float u0, float u1, float3* wi)
{
    float co = dot3(n, wo);
    if (co < GGX_COS_MIN) return false;
    float3 h = ggx_sample_normal(n, wo, co, lobe_alpha(l), u0, u1);
    *wi = 2.0f * dot3(wo, h) * h - wo;
    return true;
}

/* What it reflects at normal incidence (F0 times weight): the denoiser's guide albedo (still/aux.cl) */
inline float3 microfacet_reflection_albedo(const Lobe* l)
{
    MicrofacetReflection m = microfacet_reflection(l);
    return m.metal_w * m.metal_f0 + m.diel_w * m.diel_f0;
}

/* Its weights summed over rgb: x of the metallic (F82-tint) part, y of the rest; reuse compares the metallic share
 * (surface/surface.h) */
inline float2 microfacet_reflection_weights(const Lobe* l)
{
    MicrofacetReflection m = microfacet_reflection(l);
    return (float2)(m.metal_w.x + m.metal_w.y + m.metal_w.z, m.diel_w.x + m.diel_w.y + m.diel_w.z);
}

#endif
