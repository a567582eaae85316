/* The Principled BSDF's transmission in thin-walled mode (Blender 5.3's Thin Wall input), resolved for one view into
 * a thin dielectric lobe (bsdf/thin_dielectric.h), as Cycles 5.3 has it:
 *   - the slab's R and T at the view cosine mu (bsdf/thin_wall_slab.h: Fresnel per face, Beer-Lambert tint,
 *     internal reflections summed);
 *   - the reflection keeps alpha = Roughness^2; the transmission, refracted twice, a roughened alpha_t = alpha
 *     sqrt(3.4 (IOR - 1) (IOR - 0.5)^2 / IOR^3) clamped to [0, 1] (Kulla and Conty 2017; 0 for an IOR <= 1);
 *   - each part is scaled by its GGX energy compensation 1 + F_ms (1 - E) / E (bsdf/closure.h; F_ss the Specular
 *     Tint for the reflection, 1 for the transmission), for GGX and Multiscatter GGX alike, as Cycles does;
 *   - a part whose alpha^2 is at most 2e-10 is Cycles' delta (smooth): kept at GGX_ALPHA_MIN.
 * Shadow rays pass a smooth thin wall as a transparent surface of colour T, as Cycles' do (bvh/thin_wall_shadow.h). */
#ifndef RESTIRCL_BSDF_CLOSURES_THIN_WALL_H
#define RESTIRCL_BSDF_CLOSURES_THIN_WALL_H

#include "bsdf/closure.h"
#include "bsdf/thin_dielectric.h"
#include "bsdf/thin_wall_slab.h"

/* alpha_t of the transmission for reflection alpha and IOR eta */
inline float thin_wall_alpha_t(float alpha, float eta)
{
    float k = 3.4f * (eta - 1.0f) * sqr_f(eta - 0.5f) / (eta * eta * eta);
    return k > 0.0f ? clamp_f(alpha * sqrt(k), 0.0f, 1.0f) : 0.0f;
}

/* The energy compensation of a GGX part of alpha at view cosine mu whose single-scattering Fresnel averages fss
 * (closure_ggx's albedos at the part's own roughness: the transmission's is not the closure's) */
inline float3 thin_wall_compensation(float alpha, float mu, float3 fss, const __global float* tab)
{
    float2 e = ggx_compensation_albedos(tab, sqrt(alpha), mu);
    return multiscatter_factor(fss, e.x, e.y);
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
    float3 R;
    float3 T = thin_wall_slab(mu, ior, tint, base, &R);
    ThinDielectric m;
    m.alpha_r = fmax_f(alpha, GGX_ALPHA_MIN);
    m.alpha_t = fmax_f(alpha_t, GGX_ALPHA_MIN);
    m.reflect = wt * R * thin_wall_compensation(m.alpha_r, mu, tint, tab);
    m.transmit = wt * T * thin_wall_compensation(m.alpha_t, mu, (float3)(1.0f), tab);
    m.smooth = alpha * alpha <= 2e-10f && alpha_t * alpha_t <= 2e-10f ? 1.0f : 0.0f;
    return thin_dielectric_lobe(&m, fmax_f(avg3(m.reflect + m.transmit), 1e-3f * wt));
}

#endif
