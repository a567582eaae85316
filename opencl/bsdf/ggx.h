/* The isotropic GGX microfacet distribution: its normal distribution D, Smith's masking Lambda, and sampling of the
 * visible normals (Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 2018). The maths the microfacet
 * lobes share, and the f and pdf of reflection about a microfacet, which every reflection lobe reads
 * (bsdf/microfacet_reflection.h, thin_film_reflection.h, thin_dielectric.h); a lobe's weights, its Fresnel and its
 * sampling live in its own file. Directions are unit vectors leaving the surface: wo towards the viewer. */
#ifndef RESTIRCL_BSDF_GGX_H
#define RESTIRCL_BSDF_GGX_H

#include "sampling/warps.h"

/* alpha below this is a mirror that no light sample can hit; clamped to it, a smooth surface keeps a finite D
 * (1 / (pi alpha^2) = 3e7 at the peak) and reflects lights of finite size as a small highlight */
#define GGX_ALPHA_MIN 1e-4f
/* cosines below this are the horizon: no reflection (guards the 1 / cos factors) */
#define GGX_COS_MIN 1e-6f

/* D at a half vector of squared cosine c2 and squared sine s2 about the normal (both given: near a sharp peak,
 * 1 - c2 in float loses the digits that D depends on, while s2 = |n x h|^2 keeps them) */
inline float ggx_d(float alpha2, float c2, float s2)
{
    float k = s2 + alpha2 * c2;
    return alpha2 / (RESTIRCL_PI * k * k);
}

/* D at the half vector of wo and wi (hv = wo + wi, |hv|^2 = hl > 0) */
inline float ggx_d_half(float alpha2, float3 n, float3 hv, float hl)
{
    float c = dot3(n, hv);
    float3 x = cross3(n, hv);
    return ggx_d(alpha2, c * c / hl, dot3(x, x) / hl);
}

inline float ggx_lambda(float alpha2, float cos_n)
{
    float c2 = fmax_f(cos_n * cos_n, 1e-12f);
    return 0.5f * (sqrt(1.0f + alpha2 * fmax_f(1.0f / c2 - 1.0f, 0.0f)) - 1.0f);
}

/* GGX reflection without Fresnel of wo to wi about n, at their cosines co, ci >= GGX_COS_MIN with n (given: a lobe
 * that mirrors wi through the surface passes the mirrored cosine as it has it): D G2 / (4 cos_o cos_i) (returned),
 * the density of reflecting wo about a visible normal D G1(wo) / (4 cos_o) (*pdf) and the cosine of wo with the half
 * vector (*c_h, where a Fresnel is read); 0 and *pdf = 0 where wo + wi is too short to give a half vector. The
 * reflection lobes' f and pdf (bsdf/microfacet_reflection.h, thin_film_reflection.h, thin_dielectric.h). */
inline float ggx_reflection(float alpha, float3 n, float3 wo, float3 wi, float co, float ci, float* pdf, float* c_h)
{
    float3 hv = wo + wi;
    float hl = dot3(hv, hv);
    *pdf = 0.0f;
    *c_h = 0.0f;
    if (!(hl > 1e-12f)) return 0.0f;
    float alpha2 = alpha * alpha;
    float D = ggx_d_half(alpha2, n, hv, hl);
    float lo = ggx_lambda(alpha2, co);
    *pdf = D / (4.0f * co * (1.0f + lo));
    *c_h = clamp_f(dot3(hv, wo) / sqrt(hl), 0.0f, 1.0f);
    float g2 = 1.0f / (1.0f + lo + ggx_lambda(alpha2, ci));
    return D * g2 / (4.0f * co * ci);
}

/* A visible normal for the view wl (local frame, z the normal; wl.z > 0) from (u0, u1) in [0, 1)^2: the view is
 * stretched to the alpha = 1 configuration, where visible normals are a disk's points lifted onto the hemisphere
 * about it, the disk warped towards the view's horizon. */
inline float3 ggx_visible_normal(float3 wl, float alpha, float u0, float u1)
{
    float3 v = norm3((float3)(alpha * wl.x, alpha * wl.y, wl.z));
    float lsq = v.x * v.x + v.y * v.y;
    float3 t1 = lsq > 1e-7f ? (float3)(-v.y, v.x, 0.0f) * (1.0f / sqrt(lsq)) : (float3)(1.0f, 0.0f, 0.0f);
    float3 t2 = cross3(v, t1);
    float2 d = concentric_disk(u0, u1);
    float s = 0.5f * (1.0f + v.z);
    d.y = (1.0f - s) * sqrt(fmax_f(0.0f, 1.0f - d.x * d.x)) + s * d.y;
    float3 hs = d.x * t1 + d.y * t2 + sqrt(fmax_f(0.0f, 1.0f - d.x * d.x - d.y * d.y)) * v;
    return norm3((float3)(alpha * hs.x, alpha * hs.y, fmax_f(hs.z, 0.0f)));
}

/* A visible normal about n (world space) for the view wo at cos(n, wo) = co > 0 */
inline float3 ggx_sample_normal(float3 n, float3 wo, float co, float alpha, float u0, float u1)
{
    float3 t, b;
    light_onb(n, &t, &b);
    float3 wl = (float3)(dot3(wo, t), dot3(wo, b), co);
    float3 hl = ggx_visible_normal(wl, alpha, u0, u1);
    return hl.x * t + hl.y * b + hl.z * n;
}

#endif
