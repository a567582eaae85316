/* How much of a surface's look moves with the viewer: 0 for a diffuse surface (its shading follows the surface, so
 * reprojected history stays right), towards 1 for a sharp reflection (its image moves with the camera: the
 * reprojected history shows the reflection where it was, a ghost). TAA shortens and clips that history harder, and
 * ReSTIR's temporal reuse caps its history lower, as it rises (the lecture's "specular surfaces" failure case). */
#ifndef RESTIRCL_VIEW_DEPENDENCE_H
#define RESTIRCL_VIEW_DEPENDENCE_H

#include "bsdf/lambert.h"

/* Roughness above which a specular lobe is wide enough to count as view-independent for reprojection. */
#define VIEW_DEPENDENT_ROUGHNESS 0.5f

/* In [0, 1]: the view dependence of surface s, the share of its lobes in its reflectance (their sampling weights
 * against the Lambert part's, bsdf/bsdf.h) weighted by how sharp each is: 1 at roughness 0, 0 from
 * VIEW_DEPENDENT_ROUGHNESS up. Diffuse surfaces, and every surface of a diffuse-only build: 0. */
inline float view_dependence(const Surface* s)
{
#if defined(HAS_GLOSSY) && !defined(VIEW_DEPENDENCE_OFF)  /* OFF: the before of the ghosting test (render/test_taa_glossy.py) */
    if (!s->valid || s->mat.lobes == 0) return 0.0f;
    float total = lambert_weight(s->mat.albedo), sharp = 0.0f;
    for (int k = 0; k < s->mat.lobes; ++k) {
#if defined(HAS_TRANSMISSION) && defined(GLASS_KEEPS_HISTORY)
        /* the negative control of tests/render/test_taa_glass.py only: glass left out, so it keeps its history.
         * Glass is rated as a mirror (docs/design.md, "Glass under motion"): what it shows moves with the view. */
        if (lobe_kind(&s->mat.lobe[k]) == LOBE_MICROFACET_DIELECTRIC) continue;
#endif
        float w = lobe_weight(&s->mat.lobe[k]);
        float roughness = sqrt(fmax_f(lobe_alpha(&s->mat.lobe[k]), 0.0f));  /* alpha = roughness^2 */
        sharp += w * clamp_f(1.0f - roughness / VIEW_DEPENDENT_ROUGHNESS, 0.0f, 1.0f);
        total += w;
    }
    return total > 0.0f ? clamp_f(sharp / total, 0.0f, 1.0f) : 0.0f;
#else
    (void)s;
    return 0.0f;
#endif
}

/* TAA's blend floor a_min raised towards TAA_GLOSSY_ALPHA on a sharp reflection. 1: a perfect mirror keeps no
 * history. Measured on tests/render/test_taa_glossy.py's mirror floor (relMSE of the TAA output, 4 seeds): no raise
 * 10.8, towards 0.5: 2.9, 0.8: 0.71, 1.0: 0.17 (a single frame without TAA: 0.10). */
#ifndef TAA_GLOSSY_ALPHA
#define TAA_GLOSSY_ALPHA 1.0f
#endif
/* the clipping box's width shrinks to this fraction of gamma on a sharp reflection */
#ifndef TAA_GLOSSY_GAMMA
#define TAA_GLOSSY_GAMMA 0.25f
#endif
/* ReSTIR's temporal history cap shrinks to this fraction on a sharp reflection */
#ifndef RESTIR_GLOSSY_CAP
#define RESTIR_GLOSSY_CAP 0.25f
#endif

inline float view_dependent_alpha_min(const Surface* s, float alpha_min)
{
    float v = view_dependence(s);
    return v > 0.0f ? fmax_f(alpha_min, alpha_min + (TAA_GLOSSY_ALPHA - alpha_min) * v) : alpha_min;
}

inline float view_dependent_gamma(const Surface* s, float gamma)
{
    float v = view_dependence(s);
    return v > 0.0f ? gamma * (1.0f - (1.0f - TAA_GLOSSY_GAMMA) * v) : gamma;
}

/* The factor of ReSTIR's temporal history cap at s (1: the setting's cap). */
inline float view_dependent_cap(const Surface* s)
{
    float v = view_dependence(s);
    return v > 0.0f ? 1.0f - (1.0f - RESTIR_GLOSSY_CAP) * v : 1.0f;
}

#endif
