/* The GGX dielectric lobe: an interface between two media that reflects and refracts (the Glass BSDF, the Refraction
 * BSDF, the Principled BSDF's Transmission), as Cycles 4.x/5.x models it: one GGX distribution (bsdf/ggx.h) about
 * the lobes' normal, the unpolarised dielectric Fresnel F at the microfacet normal, reflection tinted by
 * `reflect` and weighted F, refraction tinted by `transmit` and weighted 1 - F. eta is the relative IOR across the
 * interface seen from wo's side (the resolve gives IOR entering a front face, 1 / IOR leaving through a back face),
 * so with eta < 1 some microfacets reflect everything (total internal reflection).
 *
 * The refraction's f carries no eta^2 radiance scaling (as Cycles): a path's throughput through a smooth interface is
 * 1 - F, whichever way it goes, so a closed glass object in a uniform world stays as bright as the world. f
 * excludes the cosine at wi, as everywhere behind the BSDF seam; reflection has both directions on wo's side of the
 * normal, refraction wi on the other.
 *
 * Sampling draws a visible normal, then reflects wo about it with the probability that this microfacet reflects
 * (its reflected share of what it scatters, dielectric_p_reflect_at) and refracts otherwise. The pdf is that
 * mixture's density of wi. The choice at the microfacet, not at the macroscopic normal, keeps every sample's weight
 * f cos / pdf at G2 / G1 times what the microfacet scatters: a branch chosen by the macroscopic normal's Fresnel
 * carries F(h) / F(n) (or the same of 1 - F), which inside glass near the critical angle, where F(n) is 1 and a
 * tilted microfacet refracts, reaches 1 / the floor of that probability: the fireflies of rough glass. The choice
 * takes a third uniform, hashed from (u0, u1): the lobe seam passes two. An interface with eta 1 (within 1e-4, as
 * Cycles' singular case) bends no ray and reflects nothing: it passes wo straight on through a cone of half-angle
 * DIELECTRIC_PASS_ANGLE about -wo, uniformly, which keeps f, pdf and sampling finite and consistent (the cone is far
 * below a pixel's footprint). */
#ifndef RESTIRCL_BSDF_MICROFACET_DIELECTRIC_H
#define RESTIRCL_BSDF_MICROFACET_DIELECTRIC_H

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/lobe_record.h"
#ifdef HAS_THIN_FILM
#include "bsdf/thin_film.h"
#endif

#define LOBE_MICROFACET_DIELECTRIC 1
/* |eta - 1| below this: no refraction modelled, the interface passes rays straight on */
#define DIELECTRIC_ETA_ONE 1e-4f
/* 1 - cos of the pass-through cone's half-angle (1 mrad) */
#define DIELECTRIC_PASS_OMC 5e-7f

typedef struct {
    float3 reflect;   /* a.xyz: tint of the reflection, times the closure's weight */
    float alpha;      /* a.w: roughness^2, clamped to GGX_ALPHA_MIN */
    float3 transmit;  /* b.xyz: tint of the refraction, times the closure's weight */
    float eta;        /* b.w: IOR beyond the interface over IOR on wo's side */
    float3 f0;        /* c.xyz: reflectance at normal incidence: F0 of the IOR, times the Principled's Specular Tint */
    float smooth;     /* d.x: 1 where Cycles' Roughness makes the lobe a delta (no light sample can meet it) */
    float no_fresnel; /* d.y: 1 for the Refraction BSDF: it transmits all but what total internal reflection keeps */
    float film_thickness; /* c.w: a thin film's thickness (nm; at most THIN_FILM_CUTOFF: none, bsdf/thin_film.h) */
    float film_ior;   /* d.z: the film's IOR relative to the medium on wo's side */
} MicrofacetDielectric;

inline MicrofacetDielectric microfacet_dielectric(const Lobe* l)
{
    MicrofacetDielectric m = {l->a.xyz, l->a.w, l->b.xyz, l->b.w, l->c.xyz, l->d.x, l->d.y, l->c.w, l->d.z};
    return m;
}

/* The reflectance (returned, rgb) and *transmittance (rgb, tints applied) at a microfacet that wo meets at cosine c:
 * the real Fresnel curve of eta remapped from [F0(eta), 1] onto [f0, 1] (Cycles' generalised Schlick with the real
 * curve: with f0 = F0(eta) it is the real Fresnel), or for the Refraction BSDF no reflection and all transmitted
 * unless the microfacet reflects totally. */
inline float3 dielectric_fresnel(const MicrofacetDielectric* m, float c, float3* transmittance)
{
    float F = fresnel_dielectric(c, m->eta);
    if (m->no_fresnel != 0.0f) {
        *transmittance = F < 1.0f ? m->transmit : (float3)(0.0f);
        return (float3)(0.0f);
    }
    float f0_eta = f0_from_ior(m->eta);
    float s = f0_eta < 1.0f ? clamp_f((F - f0_eta) / (1.0f - f0_eta), 0.0f, 1.0f) : 1.0f;
    float3 Fc = mix3(m->f0, (float3)(1.0f), s);
#ifdef HAS_THIN_FILM  /* a film replaces the curve (per channel), its transmission is what it does not reflect */
    if (m->film_thickness > THIN_FILM_CUTOFF) Fc = thin_film_specular(c, m->eta, m->f0, m->film_thickness, m->film_ior);
#endif
#ifdef DIELECTRIC_WITHOUT_FRESNEL_IN_REFRACTION  /* defined only by the negative control of the white furnace test */
    *transmittance = m->transmit;
#else
    *transmittance = ((float3)(1.0f) - Fc) * m->transmit;
#endif
    return Fc * m->reflect;
}

/* The probability that sampling reflects at a microfacet that wo meets at cosine c: the rgb sum of what it reflects
 * over that of all it scatters. 0 where it reflects nothing and 1 where it transmits nothing (total internal
 * reflection), so each branch is drawn wherever its f is not 0; where it scatters nothing (the Refraction BSDF under
 * total internal reflection) 0: the refraction, which finds no direction there, so nothing is drawn. */
inline float dielectric_p_reflect_at(const MicrofacetDielectric* m, float c)
{
    float3 t;
    float3 r = dielectric_fresnel(m, c, &t);
    float sr = r.x + r.y + r.z, st = t.x + t.y + t.z;
    return sr + st > 0.0f ? sr / (sr + st) : 0.0f;
}

/* The third uniform of a sample, for its branch: a hash of the two it was given (the visible normal's) */
inline float dielectric_branch_uniform(float u0, float u1)
{
    uint h = pcg_hash(as_uint(u0) ^ pcg_hash(as_uint(u1) ^ 0x3c6ef372u));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* The record of m with sampling weight `weight` */
inline Lobe microfacet_dielectric_lobe(const MicrofacetDielectric* m, float weight)
{
    Lobe l = lobe_record(LOBE_MICROFACET_DIELECTRIC, m->alpha, weight);
    l.a.xyz = m->reflect;
    l.b = (float4)(m->transmit, m->eta);
    l.c = (float4)(m->f0, m->film_thickness);
    l.d.xyz = (float3)(m->smooth, m->no_fresnel, m->film_ior);
    return l;
}

inline bool dielectric_passes(const MicrofacetDielectric* m) { return abs_f(m->eta - 1.0f) < DIELECTRIC_ETA_ONE; }

/* 1 - cos of the angle between wi and -wo, with its digits near 0 */
inline float dielectric_pass_omc(float3 wo, float3 wi)
{
    float3 d = wi + wo;
    return 0.5f * dot3(d, d);
}

/* The refraction's half vector of (wo, wi) on wo's side of n, normalised; false where the pair cannot refract (the
 * same side, or a half vector that does not separate them). *co_h, *ci_h: its cosines with wo and wi, *hl2: the
 * squared length of wo + eta wi, which the Jacobian divides by. */
inline bool dielectric_refraction_half(float3 n, float3 wo, float3 wi, float eta, float3* h, float* co_h,
                                       float* ci_h, float* hl2)
{
    float3 hv = -(wo + eta * wi);
    float l2 = dot3(hv, hv);
    if (!(l2 > 1e-20f)) return false;
    if (dot3(hv, n) < 0.0f) hv = -hv;
    *h = hv * (1.0f / sqrt(l2));
    *co_h = dot3(*h, wo);
    *ci_h = dot3(*h, wi);
    *hl2 = l2;
    return *co_h > 0.0f && *ci_h < 0.0f;
}

/* f(wo, wi) about normal n */
inline float3 microfacet_dielectric_eval(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    float co = dot3(n, wo), ci = dot3(n, wi);
    if (co < GGX_COS_MIN || abs_f(ci) < GGX_COS_MIN) return (float3)(0.0f);
    if (dielectric_passes(&m)) {
        if (!(ci < 0.0f) || dielectric_pass_omc(wo, wi) > DIELECTRIC_PASS_OMC) return (float3)(0.0f);
        return m.transmit * (1.0f / (-ci * (2.0f * RESTIRCL_PI) * DIELECTRIC_PASS_OMC));
    }
    float alpha2 = m.alpha * m.alpha;
    float g2 = 1.0f / (1.0f + ggx_lambda(alpha2, co) + ggx_lambda(alpha2, ci));
    if (ci > 0.0f) {
        float3 hv = wo + wi;
        float hl = dot3(hv, hv);
        if (!(hl > 1e-12f)) return (float3)(0.0f);
        float3 t;
        float3 R = dielectric_fresnel(&m, clamp_f(dot3(hv, wo) / sqrt(hl), 0.0f, 1.0f), &t);
        return R * (ggx_d_half(alpha2, n, hv, hl) * g2 / (4.0f * co * ci));
    }
    float3 h;
    float co_h, ci_h, hl2;
    if (!dielectric_refraction_half(n, wo, wi, m.eta, &h, &co_h, &ci_h, &hl2)) return (float3)(0.0f);
    float3 t;
    dielectric_fresnel(&m, co_h, &t);
    float D = ggx_d_half(alpha2, n, h, 1.0f);
    return t * (D * g2 * m.eta * m.eta * co_h * -ci_h / (co * -ci * hl2));
}

/* The solid-angle density of microfacet_dielectric_sample's wi */
inline float microfacet_dielectric_pdf(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    float co = dot3(n, wo), ci = dot3(n, wi);
    if (co < GGX_COS_MIN || abs_f(ci) < GGX_COS_MIN) return 0.0f;
    if (dielectric_passes(&m))
        return (ci < 0.0f && dielectric_pass_omc(wo, wi) <= DIELECTRIC_PASS_OMC)
                   ? 1.0f / ((2.0f * RESTIRCL_PI) * DIELECTRIC_PASS_OMC) : 0.0f;
    float alpha2 = m.alpha * m.alpha;
    float g1 = 1.0f / (1.0f + ggx_lambda(alpha2, co));
    if (ci > 0.0f) {
        float3 hv = wo + wi;
        float hl = dot3(hv, hv);
        if (!(hl > 1e-12f)) return 0.0f;
        float pr = dielectric_p_reflect_at(&m, clamp_f(dot3(hv, wo) / sqrt(hl), 0.0f, 1.0f));
#ifdef TEST_DIELECTRIC_REFLECT_PDF_SCALE  /* negative control of tests/materials/test_dielectric_branch.py only */
        pr *= TEST_DIELECTRIC_REFLECT_PDF_SCALE;
#endif
        return pr * ggx_d_half(alpha2, n, hv, hl) * g1 / (4.0f * co);
    }
    float3 h;
    float co_h, ci_h, hl2;
    if (!dielectric_refraction_half(n, wo, wi, m.eta, &h, &co_h, &ci_h, &hl2)) return 0.0f;
    float D = ggx_d_half(alpha2, n, h, 1.0f);
    float pt = 1.0f - dielectric_p_reflect_at(&m, co_h);
    return pt * D * g1 * m.eta * m.eta * co_h * -ci_h / (co * hl2);
}

/* Reflect or refract wo about a visible normal drawn from (u0, u1), reflecting with that microfacet's probability
 * (dielectric_p_reflect_at); false where nothing was drawn: wo below the surface, or a direction on the wrong side
 * for its branch (the pdf counts each branch on its own side only). */
inline bool microfacet_dielectric_sample(const Lobe* l, float3 n, float3 wo, float u0, float u1, float3* wi)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    float co = dot3(n, wo);
    if (co < GGX_COS_MIN) return false;
    if (dielectric_passes(&m)) {  /* uniform in the cone about -wo */
        float omc = u0 * DIELECTRIC_PASS_OMC;
        float s = sqrt(omc * (2.0f - omc)), phi = 2.0f * RESTIRCL_PI * u1;
        float3 t, b, w = -wo;
        light_onb(w, &t, &b);
        *wi = norm3(s * cos(phi) * t + s * sin(phi) * b + (1.0f - omc) * w);
        return dot3(n, *wi) < -GGX_COS_MIN;
    }
    float3 h = ggx_sample_normal(n, wo, co, m.alpha, u0, u1);
    float c = dot3(wo, h);
    if (dielectric_branch_uniform(u0, u1) < dielectric_p_reflect_at(&m, clamp_f(c, 0.0f, 1.0f))) {
        *wi = 2.0f * c * h - wo;
        return dot3(n, *wi) > 0.0f;
    }
    float inv = 1.0f / m.eta;
    float ct2 = 1.0f - (1.0f - c * c) * inv * inv;
    if (!(ct2 > 0.0f)) return false;
    *wi = norm3((c * inv - sqrt(ct2)) * h - wo * inv);
    return dot3(n, *wi) < 0.0f;
}

/* What it reflects at normal incidence: the denoiser's guide albedo */
inline float3 microfacet_dielectric_albedo(const Lobe* l)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    return m.reflect * m.f0;
}

/* What it lets through at view cosine mu: 1 - F at the macroscopic normal times the refraction's tint (the light
 * passes' Transmission Color, film/light_passes.h) */
inline float3 microfacet_dielectric_transmittance(const Lobe* l, float mu)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    float3 t;
    (void)dielectric_fresnel(&m, mu, &t);
    return t;
}

/* Its weights summed over rgb: no metallic part; the rest is what it reflects and transmits */
inline float2 microfacet_dielectric_weights(const Lobe* l)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    float3 t = m.reflect + m.transmit;
    return (float2)(0.0f, t.x + t.y + t.z);
}

/* Whether the lobe transmits light from behind the surface: a light there is evaluated about the flipped normal */
inline bool microfacet_dielectric_transmits(const Lobe* l)
{
    MicrofacetDielectric m = microfacet_dielectric(l);
    return m.transmit.x + m.transmit.y + m.transmit.z > 0.0f;
}

#endif
