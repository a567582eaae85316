/* The Principled BSDF's transmission in thin-walled mode (Blender 5.3's Thin Wall input), resolved for one view into
 * a thin dielectric lobe (bsdf/thin_dielectric.h), as Cycles 5.3 has it:
 *   - each face of the sheet has the Principled's dielectric Fresnel at the view cosine mu: the real curve of the
 *     IOR remapped onto [f0, 1], f0 = F0(IOR) x Specular Tint (r); it lets 1 - r through (t); the IOR is not
 *     inverted on a back face: both faces are an entry;
 *   - inside, the Base Color c0 is the sheet's transmittance at normal incidence, c = c0^(1 / cos_t) along the
 *     refracted cosine cos_t (Beer-Lambert; 0 under total internal reflection);
 *   - summing the internal reflections: T = c t^2 / (1 - (r c)^2), R = r + T r c;
 *   - the reflection keeps alpha = Roughness^2; the transmission, refracted twice, a roughened alpha_t = alpha
 *     sqrt(3.4 (IOR - 1) (IOR - 0.5)^2 / IOR^3) clamped to [0, 1] (Kulla and Conty 2017; 0 for an IOR <= 1);
 *   - each part is scaled by its GGX energy compensation 1 + F_ms (1 - E) / E (bsdf/closure.h; F_ss the Specular
 *     Tint for the reflection, 1 for the transmission), for GGX and Multiscatter GGX alike, as Cycles does;
 *   - a part whose alpha^2 is at most 2e-10 is Cycles' delta (smooth): kept at GGX_ALPHA_MIN.
 * Not modelled: Cycles passes shadow rays through a smooth thin wall as a transparent surface; here the shadow ray
 * is blocked and the light reaches what is behind the sheet through the paths' BSDF rays only (docs/blender.md). */
#ifndef RESTIRCL_BSDF_CLOSURES_THIN_WALL_H
#define RESTIRCL_BSDF_CLOSURES_THIN_WALL_H

#include "bsdf/closure.h"
#include "bsdf/thin_dielectric.h"

/* alpha_t of the transmission for reflection alpha and IOR eta */
inline float thin_wall_alpha_t(float alpha, float eta)
{
    float k = 3.4f * (eta - 1.0f) * sqr_f(eta - 0.5f) / (eta * eta * eta);
    return k > 0.0f ? clamp_f(alpha * sqrt(k), 0.0f, 1.0f) : 0.0f;
}

/* The energy compensation of a GGX part of alpha at view cosine mu whose single-scattering Fresnel averages fss */
inline float3 thin_wall_compensation(float alpha, float mu, float3 fss, const __global float* tab)
{
    float r = sqrt(alpha);
    float e = fmax_f(ggx_albedo(tab, r, mu), 1e-3f);
    return multiscatter_factor(fss, e, fmax_f(ggx_albedo_avg(tab, r), 1e-3f));
}

/* The Principled BSDF's transmission at weight wt (its closure weight x (1 - Metallic) x Transmission Weight) on a
 * thin wall, for view cosine mu */
inline Lobe principled_thin_wall_lobe(const ClosureInputs* c, float wt, float3 base, float mu, const __global float* tab)
{
    float ior = fmax_f(c->ior, 1e-5f);
    float3 tint = max0_3(c->tint);
    float r0 = clamp_f(c->roughness, 0.0f, 1.0f);
    float alpha = r0 * r0;
    float alpha_t = thin_wall_alpha_t(alpha, ior);
    float f0_eta = f0_from_ior(ior);
    float3 r = fresnel_principled(mu, ior, f0_eta, (float3)(f0_eta) * tint);
    float3 t = (float3)(1.0f) - r;
    float ct2 = 1.0f - (1.0f - mu * mu) / (ior * ior);
    float3 c0 = saturate3(base);
    float3 k = (float3)(0.0f);
    if (ct2 > 0.0f) {
        float e = 1.0f / sqrt(ct2);
        k = (float3)(pow(c0.x, e), pow(c0.y, e), pow(c0.z, e));
    }
    float3 rc = r * k;
    float3 T = k * t * t / ((float3)(1.0f) - rc * rc);
    float3 R = r + T * rc;
    ThinDielectric m;
    m.alpha_r = fmax_f(alpha, GGX_ALPHA_MIN);
    m.alpha_t = fmax_f(alpha_t, GGX_ALPHA_MIN);
    m.reflect = wt * R * thin_wall_compensation(m.alpha_r, mu, tint, tab);
    m.transmit = wt * T * thin_wall_compensation(m.alpha_t, mu, (float3)(1.0f), tab);
    m.smooth = alpha * alpha <= 2e-10f && alpha_t * alpha_t <= 2e-10f ? 1.0f : 0.0f;
    return thin_dielectric_lobe(&m, fmax_f(avg3(m.reflect + m.transmit), 1e-3f * wt));
}

#endif
