/* The isotropic GGX microfacet distribution: its normal distribution D, Smith's masking Lambda, and sampling of the
 * visible normals (Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 2018), for one resolved lobe
 * (SpecLobe, types.h). Directions are unit vectors leaving the surface: wo towards the viewer, wi towards the light;
 * f excludes the cosine at the surface (the light evaluation carries it), as everywhere behind the BSDF seam. */
#ifndef RESTIRCL_BSDF_GGX_H
#define RESTIRCL_BSDF_GGX_H

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

/* The lobe's f(wo, wi) about normal n: D G2 / (4 cos_o cos_i) times its Fresnel-weighted colour, the F82-tint
 * part and the dielectric part sharing D and G2 (0 unless both directions are above the surface). */
inline float3 ggx_lobe_eval(const SpecLobe* l, float3 n, float3 wo, float3 wi)
{
    float co = dot3(n, wo), ci = dot3(n, wi);
    float3 hv = wo + wi;
    float hl = dot3(hv, hv);
    if (co < GGX_COS_MIN || ci < GGX_COS_MIN || !(hl > 1e-12f)) return (float3)(0.0f);
    float alpha = l->metal_f0.w, alpha2 = alpha * alpha;
    float c_hi = clamp_f(dot3(hv, wo) / sqrt(hl), 0.0f, 1.0f);
    float3 F = l->metal_w.xyz * fresnel_f82(c_hi, l->metal_f0.xyz, l->metal_b.xyz);
    if (l->metal_b.w > 1.0f)
        F += l->diel_w.xyz * fresnel_principled(c_hi, l->metal_b.w, l->metal_w.w, l->diel_f0.xyz);
    float g2 = 1.0f / (1.0f + ggx_lambda(alpha2, co) + ggx_lambda(alpha2, ci));
    return F * (ggx_d_half(alpha2, n, hv, hl) * g2 / (4.0f * co * ci));
}

/* The solid-angle density of ggx_lobe_sample's wi: D G1(wo) / (4 cos_o) at the half vector (0 below the surface) */
inline float ggx_lobe_pdf(const SpecLobe* l, float3 n, float3 wo, float3 wi)
{
    float co = dot3(n, wo), ci = dot3(n, wi);
    float3 hv = wo + wi;
    float hl = dot3(hv, hv);
    if (co < GGX_COS_MIN || ci < GGX_COS_MIN || !(hl > 1e-12f)) return 0.0f;
    float alpha = l->metal_f0.w, alpha2 = alpha * alpha;
    return ggx_d_half(alpha2, n, hv, hl) / (4.0f * co * (1.0f + ggx_lambda(alpha2, co)));
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

/* Reflect wo about a visible normal of the lobe: wi. false when wo is below the surface (nothing drawn). */
inline bool ggx_lobe_sample(const SpecLobe* l, float3 n, float3 wo, float u0, float u1, float3* wi)
{
    float co = dot3(n, wo);
    if (co < GGX_COS_MIN) return false;
    float3 t, b;
    light_onb(n, &t, &b);
    float3 wl = (float3)(dot3(wo, t), dot3(wo, b), co);
    float3 hl = ggx_visible_normal(wl, l->metal_f0.w, u0, u1);
    float3 h = hl.x * t + hl.y * b + hl.z * n;
    *wi = 2.0f * dot3(wo, h) * h - wo;
    return true;
}

#endif
