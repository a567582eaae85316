/* How much of a surface's look moves with the viewer: 0 for a diffuse surface (its shading follows the surface, so
 * reprojected history stays right), towards 1 for a sharp reflection (its image moves with the camera: the
 * reprojected history shows the reflection where it was, a ghost). TAA shortens and clips that history harder, and
 * ReSTIR's temporal reuse caps its history lower, as it rises (the lecture's "specular surfaces" failure case). */
#ifndef RESTIRCL_VIEW_DEPENDENCE_H
#define RESTIRCL_VIEW_DEPENDENCE_H

/* Roughness above which a specular lobe is wide enough to count as view-independent for reprojection. */
#define VIEW_DEPENDENT_ROUGHNESS 0.5f

/* In [0, 1]: the view dependence of surface s. The Lambert-only Surface has no specular lobe: 0. */
inline float view_dependence(const Surface* s)
{
    (void)s;
    return 0.0f;
}

/* TAA's blend floor a_min raised towards TAA_GLOSSY_ALPHA on a sharp reflection: its history lasts a few frames. */
#define TAA_GLOSSY_ALPHA 0.5f
/* the clipping box's width shrinks to this fraction of gamma on a sharp reflection */
#define TAA_GLOSSY_GAMMA 0.25f
/* ReSTIR's temporal history cap shrinks to this fraction on a sharp reflection */
#define RESTIR_GLOSSY_CAP 0.25f

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
