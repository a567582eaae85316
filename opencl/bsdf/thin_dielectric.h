/* The thin dielectric lobe: an infinitely thin sheet of dielectric (Blender 5.3's Principled BSDF with Thin Wall on,
 * bsdf/closures/thin_wall.h), as Cycles 5.3 models it after OpenPBR's thin-walled case. Two GGX lobes about the
 * lobes' normal, their weights fixed for the pixel's view by the resolve (the slab's Fresnel with its internal
 * reflections summed):
 *   reflection    R x GGX reflection of roughness alpha_r (no Fresnel per microfacet: R holds it);
 *   transmission  T x the same GGX reflection, of roughness alpha_t, with wi mirrored through the surface's plane:
 *                 the two refractions of a sheet cancel, so the light leaves along -wo, blurred only by the
 *                 roughness (a smooth sheet passes rays straight on, unbent).
 * Sampling picks the transmission with probability T / (R + T) (rgb sums), then draws a visible normal of that
 * part's roughness and reflects wo about it (mirrored below for the transmission). The pdf is that mixture's
 * density; each part has its own side of the surface, so the two never overlap. f excludes the cosine at wi. */
#ifndef RESTIRCL_BSDF_THIN_DIELECTRIC_H
#define RESTIRCL_BSDF_THIN_DIELECTRIC_H

#include "bsdf/ggx.h"
#include "bsdf/lobe_record.h"

#define LOBE_THIN_DIELECTRIC 2

typedef struct {
    float3 reflect;   /* a.xyz: R, the reflection's weight (rgb, the closure's weight and energy compensation in) */
    float alpha_r;    /* a.w: the reflection's roughness^2, clamped to GGX_ALPHA_MIN */
    float3 transmit;  /* b.xyz: T, the transmission's weight (rgb) */
    float alpha_t;    /* b.w: the transmission's roughness^2 (roughened for the two interfaces), clamped likewise */
    float smooth;     /* c.x: 1 where both parts are Cycles' deltas (no light sample can meet them) */
} ThinDielectric;

inline ThinDielectric thin_dielectric(const Lobe* l)
{
    ThinDielectric m = {l->a.xyz, l->a.w, l->b.xyz, l->b.w, l->c.x};
    return m;
}

/* The record of m with sampling weight `weight` */
inline Lobe thin_dielectric_lobe(const ThinDielectric* m, float weight)
{
    Lobe l = lobe_record(LOBE_THIN_DIELECTRIC, m->alpha_r, weight);
    l.a.xyz = m->reflect;
    l.b = (float4)(m->transmit, m->alpha_t);
    l.c.x = m->smooth;
    return l;
}

/* The probability that sampling takes the transmission */
inline float thin_p_transmit(const ThinDielectric* m)
{
    float r = m->reflect.x + m->reflect.y + m->reflect.z, t = m->transmit.x + m->transmit.y + m->transmit.z;
    return r + t > 0.0f ? t / (r + t) : 0.0f;
}

/* f (returned) and *pdf of (wo, wi) about n */
inline float3 thin_dielectric_eval_pdf(const Lobe* l, float3 n, float3 wo, float3 wi, float* pdf)
{
    ThinDielectric m = thin_dielectric(l);
    float co = dot3(n, wo), ci = dot3(n, wi);
    *pdf = 0.0f;
    if (co < GGX_COS_MIN || abs_f(ci) < GGX_COS_MIN) return (float3)(0.0f);
    float pt = thin_p_transmit(&m), p, c_h;  /* no Fresnel per microfacet: R and T hold it */
    if (ci > 0.0f) {
        float f = ggx_reflection(m.alpha_r, n, wo, wi, co, ci, &p, &c_h);
        *pdf = (1.0f - pt) * p;
        return m.reflect * f;
    }
    float f = ggx_reflection(m.alpha_t, n, wo, wi - 2.0f * ci * n, co, -ci, &p, &c_h);  /* wi mirrored above */
    *pdf = pt * p;
#ifdef TEST_THIN_TRANSMISSION_PDF_SCALE  /* negative control of tests/render/test_thin_wall_furnace.py only */
    *pdf *= TEST_THIN_TRANSMISSION_PDF_SCALE;
#endif
    return m.transmit * f;
}

inline float3 thin_dielectric_eval(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    float pdf;
    return thin_dielectric_eval_pdf(l, n, wo, wi, &pdf);
}

inline float thin_dielectric_pdf(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    float pdf;
    (void)thin_dielectric_eval_pdf(l, n, wo, wi, &pdf);
    return pdf;
}

/* u0 picks the part (transmission below thin_p_transmit) and is rescaled within it for the visible normal */
inline bool thin_dielectric_sample(const Lobe* l, float3 n, float3 wo, float u0, float u1, float3* wi)
{
    ThinDielectric m = thin_dielectric(l);
    float co = dot3(n, wo);
    if (co < GGX_COS_MIN) return false;
    float pt = thin_p_transmit(&m);
    bool through = u0 < pt;
    u0 = through ? u0 / pt : (u0 - pt) / (1.0f - pt);
    u0 = clamp_f(u0, 0.0f, 0.99999994f);
    float3 h = ggx_sample_normal(n, wo, co, through ? m.alpha_t : m.alpha_r, u0, u1);
    float3 r = 2.0f * dot3(wo, h) * h - wo;
    float cr = dot3(n, r);
    if (!(cr > 0.0f)) return false;
    *wi = through ? r - 2.0f * cr * n : r;
    return true;
}

/* What it reflects at the pixel's view: the denoiser's guide albedo */
inline float3 thin_dielectric_albedo(const Lobe* l) { return thin_dielectric(l).reflect; }

/* What it lets through at the pixel's view (the light passes' Transmission Color) */
inline float3 thin_dielectric_transmittance(const Lobe* l) { return thin_dielectric(l).transmit; }

/* Its weights summed over rgb: no metallic part; the rest is what it reflects and transmits */
inline float2 thin_dielectric_weights(const Lobe* l)
{
    ThinDielectric m = thin_dielectric(l);
    float3 t = m.reflect + m.transmit;
    return (float2)(0.0f, t.x + t.y + t.z);
}

inline bool thin_dielectric_transmits(const Lobe* l)
{
    float3 t = thin_dielectric(l).transmit;
    return t.x + t.y + t.z > 0.0f;
}

#endif
