/* The BSDF seam: f, its sampling and its pdf at a surface for two unit directions leaving it, wo towards the
 * viewer and wi towards the light. The target function (direct/target.h) and every shading site reach the material
 * only through these three, so another BSDF changes what the surface holds (SurfaceMaterial, surface/surface.h) and
 * the lobes, not the resampling. The cosine at the surface is not part of f: the light evaluation carries it
 * (LightEval.contrib, lights/lights.h), which is also where a light below the surface gives 0.
 *
 * The BSDF is a mixture: the Lambert part (bsdf/lambert.h) about the shading normal n, plus in glossy builds the
 * lobes the primary pass resolved for the pixel (bsdf/resolve.h), each reached through the dispatch of bsdf/lobes.h
 * by its kind, about the lobes' normal nl. f is the parts' sum; sampling picks a part in proportion to the parts'
 * sampling weights (lambert_weight, lobe_weight: their estimated albedos) and draws from it; the pdf is the
 * weighted average of the parts' pdfs. This file knows no lobe kind: a new one is its file and its line in
 * bsdf/lobes.h. */
#ifndef RESTIRCL_BSDF_H
#define RESTIRCL_BSDF_H

#include "bsdf/lambert.h"
#include "bsdf/lobes.h"

/* f(wo, wi) for wi in the hemisphere of s->n (the caller knows it: a light evaluation with a contribution had
 * cos_x > 0), or, in builds with refracting lobes (HAS_TRANSMISSION), on either side. The lobes are evaluated
 * about their own normal s->nl; the caller's cosine is about s->n, so on a normal-mapped pixel (where the two
 * differ) their f is rescaled by cos(nl) / cos(n), and every part gets its bump_shadowing. */
/* The Lambert part of bsdf_eval alone: what the light passes count as diffuse (film/light_passes.h). */
inline float3 bsdf_eval_diffuse(const Surface* s, float3 wi)
{
    float3 f = lambert_eval(s->mat.albedo);
#ifdef HAS_TRANSMISSION  /* a refracting lobe asks for directions below the surface too: the Lambert part has none */
    if (!(dot3(s->n, wi) > 0.0f)) return (float3)(0.0f);
#endif
#ifdef HAS_TEXTURES
    if (s->bumped) f *= bump_shadowing(s->nb, s->n, wi, true);
#else
    (void)wi;
#endif
    return f;
}

inline float3 bsdf_eval(const Surface* s, float3 wo, float3 wi)
{
    float3 f = bsdf_eval_diffuse(s, wi);
#ifdef HAS_GLOSSY
    float3 fl = (float3)(0.0f);
    for (int k = 0; k < s->mat.lobes; ++k) fl += lobe_eval(&s->mat.lobe[k], s->nl, wo, wi);
#ifdef HAS_TEXTURES
    if (s->bumped && s->mat.lobes > 0) {
        float cn = dot3(s->n, wi);
#ifdef HAS_TRANSMISSION  /* refracted light below the surface keeps the lobes' own f */
        if (cn > 0.0f)
#endif
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

/* The sampling weight of the Lambert part (returned) and *total, the sum of all parts' sampling weights */
inline float bsdf_diffuse_weight(const Surface* s, float* total)
{
    float wd = lambert_weight(s->mat.albedo);
    float t = wd;
#ifdef HAS_GLOSSY
    for (int k = 0; k < s->mat.lobes; ++k) t += lobe_weight(&s->mat.lobe[k]);
#endif
    *total = t;
    return wd;
}

/* The solid-angle density of bsdf_sample's wi: the parts' densities averaged with their sampling weights; a surface
 * without lobes has Lambert's alone. */
inline float bsdf_pdf(const Surface* s, float3 wo, float3 wi)
{
    float pd = lambert_pdf(s->n, wi);
#ifdef HAS_GLOSSY
    if (s->mat.lobes > 0) {
        float total, wd = bsdf_diffuse_weight(s, &total);
        if (!(total > 0.0f)) return pd;
        float p = wd * pd;
        for (int k = 0; k < s->mat.lobes; ++k)
            p += lobe_weight(&s->mat.lobe[k]) * lobe_pdf(&s->mat.lobe[k], s->nl, wo, wi);
        return p / total;
    }
#else
    (void)wo;
#endif
    return pd;
}

/* Draw wi for wo from (u0, u1) uniform in [0, 1)^2. Returns f(wo, *wi); *pdf = bsdf_pdf(s, wo, *wi), 0 for a direction
 * that grazes or leaves below the surface (f is then not to be used). With lobes, u0 first picks the part and is
 * rescaled to [0, 1) within it. *part: the part drawn, -1 for the Lambert part, else the lobe's index (a path counts
 * diffuse and glossy bounces by it). */
inline float3 bsdf_sample_part(const Surface* s, float3 wo, float u0, float u1, float3* wi, float* pdf, int* part)
{
    *part = -1;
#ifdef HAS_GLOSSY
    if (s->mat.lobes > 0) {
        float total, wd = bsdf_diffuse_weight(s, &total);
        float x = u0 * total;
        int pick = -1;
        if (total > 0.0f && !(x < wd)) {
            float acc = wd;
            for (int k = 0; k < s->mat.lobes && pick < 0; ++k) {
                float wk = lobe_weight(&s->mat.lobe[k]);
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
            *part = pick;
            if (!lobe_sample(&s->mat.lobe[pick], s->nl, wo, clamp_f(u0, 0.0f, 0.99999994f), u1, wi)
#ifdef HAS_TRANSMISSION  /* a reflection drawn below the surface is none: the mixture's pdf there is another lobe's */
                || !(lobe_pdf(&s->mat.lobe[pick], s->nl, wo, *wi) > 0.0f)
#endif
            ) {
                *pdf = 0.0f;
                return (float3)(0.0f);
            }
            *pdf = bsdf_pdf(s, wo, *wi);
            return bsdf_eval(s, wo, *wi);
        }
    }
#endif
    *wi = lambert_sample(s->n, u0, u1);
    *pdf = bsdf_pdf(s, wo, *wi);
    return bsdf_eval(s, wo, *wi);
}

/* bsdf_sample_part without the part. */
inline float3 bsdf_sample(const Surface* s, float3 wo, float u0, float u1, float3* wi, float* pdf)
{
    int part;
    return bsdf_sample_part(s, wo, u0, u1, wi, pdf, &part);
}

#endif
