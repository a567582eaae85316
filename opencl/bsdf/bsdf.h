/* The BSDF seam: f, its sampling and its pdf at a surface for two unit directions leaving it, wo towards the
 * viewer and wi towards the light. The target function (direct/target.h) and every shading site reach the material only
 * through these three, so another BSDF changes these bodies (or a bsdf_<name>.h they dispatch to) and what
 * surface_load fills in SurfaceMaterial, not the resampling. The cosine at the surface is not part of f: the light
 * evaluation carries it (LightEval.contrib, lights/lights.h), which is also where a light below the surface gives 0.
 *
 * f = albedo / pi (Lambert, the diffuse part) + the GGX lobes the primary pass resolved (glossy builds:
 * bsdf/ggx.h, bsdf/principled.h). Sampling picks the diffuse part or a lobe in proportion to their estimated
 * albedos (the average of the diffuse albedo; SpecLobe.diel_f0.w), then a cosine direction or a visible normal;
 * the pdf is the mixture's. */
#ifndef RESTIRCL_BSDF_H
#define RESTIRCL_BSDF_H

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"

/* f(wo, wi) for wi in the hemisphere of s->n (the caller knows it: a light evaluation with a contribution had
 * cos_x > 0). Lambert's f does not depend on the directions; no branch, as it runs once per RIS candidate. The
 * lobes are evaluated about their own normal s->nl; the caller's cosine is about s->n, so on a normal-mapped pixel
 * (where the two differ) their f is rescaled by cos(nl) / cos(n), and every part gets its bump_shadowing. */
inline float3 bsdf_eval(const Surface* s, float3 wo, float3 wi)
{
    float3 f = s->mat.albedo * RESTIRCL_INV_PI;
#ifdef HAS_TEXTURES
    if (s->bumped) f *= bump_shadowing(s->nb, s->n, wi, true);
#endif
#ifdef HAS_GLOSSY
    float3 fl = (float3)(0.0f);
    for (int k = 0; k < s->mat.lobes; ++k) fl += ggx_lobe_eval(&s->mat.lobe[k], s->nl, wo, wi);
#ifdef HAS_TEXTURES
    if (s->bumped && s->mat.lobes > 0) {
        float cn = dot3(s->n, wi);
        fl *= cn > 0.0f ? bump_shadowing(s->nb, s->nl, wi, false) * fmax_f(dot3(s->nl, wi), 0.0f) / cn : 0.0f;
    }
#endif
    f += fl;
#else
    (void)wo;
    (void)wi;
#endif
    return f;
}

/* the probability of sampling the diffuse part (returned) and *total, the sum of all parts' sampling weights */
inline float bsdf_diffuse_weight(const Surface* s, float* total)
{
    float wd = (s->mat.albedo.x + s->mat.albedo.y + s->mat.albedo.z) * (1.0f / 3.0f);
    float t = wd;
#ifdef HAS_GLOSSY
    for (int k = 0; k < s->mat.lobes; ++k) t += s->mat.lobe[k].diel_f0.w;
#endif
    *total = t;
    return wd;
}

/* The solid-angle density of bsdf_sample's wi: cos / pi in the hemisphere of s->n, 0 below it, mixed with the lobes'
 * visible-normal densities about s->nl in glossy builds. */
inline float bsdf_pdf(const Surface* s, float3 wo, float3 wi)
{
    float c = dot3(s->n, wi);
    float pd = c > 0.0f ? c * RESTIRCL_INV_PI : 0.0f;
#ifdef HAS_GLOSSY
    if (s->mat.lobes > 0) {
        float total, wd = bsdf_diffuse_weight(s, &total);
        if (!(total > 0.0f)) return pd;
        float p = wd * pd;
        for (int k = 0; k < s->mat.lobes; ++k)
            p += s->mat.lobe[k].diel_f0.w * ggx_lobe_pdf(&s->mat.lobe[k], s->nl, wo, wi);
        return p / total;
    }
#else
    (void)wo;
#endif
    return pd;
}

/* Draw wi for wo from (u0, u1) uniform in [0, 1)^2. Returns f(wo, *wi); *pdf = bsdf_pdf(s, wo, *wi), 0 for a direction
 * that grazes or leaves below the surface (f is then not to be used). With lobes, u0 first picks the part and is
 * rescaled to [0, 1) within it. Diffuse: a concentric-disk point lifted onto the hemisphere (density cos / pi). */
inline float3 bsdf_sample(const Surface* s, float3 wo, float u0, float u1, float3* wi, float* pdf)
{
#ifdef HAS_GLOSSY
    if (s->mat.lobes > 0) {
        float total, wd = bsdf_diffuse_weight(s, &total);
        float x = u0 * total;
        int pick = -1;
        if (total > 0.0f && !(x < wd)) {
            float acc = wd;
            for (int k = 0; k < s->mat.lobes && pick < 0; ++k) {
                float wk = s->mat.lobe[k].diel_f0.w;
                if (x < acc + wk || k == s->mat.lobes - 1) {
                    pick = k;
                    u0 = fmin_f((x - acc) / fmax_f(wk, 1e-30f), 0.99999994f);
                }
                acc += wk;
            }
        } else if (total > 0.0f) {
            u0 = fmin_f(x / wd, 0.99999994f);
        }
        if (pick >= 0) {
            if (!ggx_lobe_sample(&s->mat.lobe[pick], s->nl, wo, clamp_f(u0, 0.0f, 0.99999994f), u1, wi)) {
                *pdf = 0.0f;
                return (float3)(0.0f);
            }
            *pdf = bsdf_pdf(s, wo, *wi);
            return bsdf_eval(s, wo, *wi);
        }
    }
#endif
    float2 d = concentric_disk(u0, u1);
    float z = sqrt(fmax_f(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    float3 t, b;
    light_onb(s->n, &t, &b);
    *wi = d.x * t + d.y * b + z * s->n;
    *pdf = bsdf_pdf(s, wo, *wi);
    return bsdf_eval(s, wo, *wi);
}

#endif
