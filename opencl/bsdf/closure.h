/* What the resolves of the closure kinds (bsdf/closures/<kind>.h) share: the cutoff below which a closure's weight
 * counts as none, and for the kinds on a GGX distribution its roughness, alpha and the multiscatter energy
 * compensation (Kulla and Conty's, with a Fresnel-coloured multiple-scattering term; E and E_avg from the tables),
 * all functions of the view cosine mu only. */
#ifndef RESTIRCL_BSDF_CLOSURE_H
#define RESTIRCL_BSDF_CLOSURE_H

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/tables.h"

#define CLOSURE_WEIGHT_CUTOFF 1e-5f

inline float avg3(float3 c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

inline float3 max0_3(float3 c) { return (float3)(fmax_f(c.x, 0.0f), fmax_f(c.y, 0.0f), fmax_f(c.z, 0.0f)); }

/* The multiscatter factor 1 + F_ms (1 - E) / E of a lobe whose single-scattering Fresnel averages f_ss. */
inline float3 multiscatter_factor(float3 f_ss, float e, float e_avg)
{
    float3 f_ms = f_ss * e_avg / ((float3)(1.0f) - f_ss * (1.0f - e_avg));
    return (float3)(1.0f) + f_ms * ((1.0f - e) / e);
}

/* The Principled BSDF's specular: its relative IOR (returned) and F0 (*f0) after the Specular IOR Level, which
 * scales F0 by 2 x the level (0.5: the IOR's own) and takes the IOR of that F0 */
inline float principled_specular_eta(const ClosureInputs* c, float* f0)
{
    float ior = fmax_f(c->ior, 1e-5f);
    *f0 = f0_from_ior(ior);
    float eta = ior;
    float level = fmax_f(c->specular, 0.0f);
    if (level != 0.5f) {
        *f0 *= 2.0f * level;
        eta = ior_from_f0(*f0);
        if (ior < 1.0f) eta = 1.0f / eta;
    }
    return eta;
}

/* The Principled BSDF's Transmission Weight: the glass's share (returned) of its dielectric part *wr, which keeps the
 * rest */
inline float principled_transmission_split(const ClosureInputs* c, float* wr)
{
    float transmission = clamp_f(c->transmission, 0.0f, 1.0f);
    float wt = *wr * transmission;
    *wr *= 1.0f - transmission;
    return wt;
}

/* The albedos of GGX of roughness r at view cosine mu that its energy compensation reads: E(r, mu) (x) and E_avg(r)
 * (y), floored at 1e-3 (the factor divides by E) */
inline float2 ggx_compensation_albedos(const __global float* tab, float r, float mu)
{
    return (float2)(fmax_f(ggx_albedo(tab, r, mu), 1e-3f), fmax_f(ggx_albedo_avg(tab, r), 1e-3f));
}

/* A closure's GGX distribution at view cosine mu: Roughness clamped to [0, 1], alpha = Roughness^2 (at least
 * GGX_ALPHA_MIN), and for multiscatter GGX the directional and average albedos E, E_avg (1 for plain GGX). */
typedef struct {
    float r;
    float alpha;
    float e;
    float e_avg;
    bool ms;
} ClosureGgx;

inline ClosureGgx closure_ggx(const ClosureInputs* c, float mu, const __global float* tab)
{
    ClosureGgx g;
    g.r = clamp_f(c->roughness, 0.0f, 1.0f);
    g.alpha = fmax_f(g.r * g.r, GGX_ALPHA_MIN);
    g.e = 1.0f;
    g.e_avg = 1.0f;
    g.ms = c->multiscatter != 0;
    if (g.ms) {
        float2 e = ggx_compensation_albedos(tab, g.r, mu);
        g.e = e.x;
        g.e_avg = e.y;
    }
    return g;
}

#endif
