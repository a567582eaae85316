/* The BSDF seam: f, its sampling and its pdf at a surface for two unit directions leaving it, wo towards the
 * viewer and wi towards the light. The target function (target.h) and every shading site reach the material only
 * through these three, so another BSDF changes these bodies (or a bsdf_<name>.h they dispatch to) and what
 * surface_load fills in SurfaceMaterial, not the resampling. The cosine at the surface is not part of f: the light
 * evaluation carries it (LightEval.contrib, lights.h), which is also where a light below the surface gives 0.
 *
 * One BSDF so far: Lambert, f = albedo / pi. */
#ifndef RESTIRCL_BSDF_H
#define RESTIRCL_BSDF_H

/* f(wo, wi) for wi in the hemisphere of s->n (the caller knows it: a light evaluation with a contribution had
 * cos_x > 0). Lambert's f does not depend on the directions; no branch, as it runs once per RIS candidate. */
inline float3 bsdf_eval(const Surface* s, float3 wo, float3 wi)
{
    (void)wo;
    (void)wi;
    return s->mat.albedo * RESTIRCL_INV_PI;
}

/* The solid-angle density of bsdf_sample's wi: cos / pi in the hemisphere of s->n, 0 below it. */
inline float bsdf_pdf(const Surface* s, float3 wo, float3 wi)
{
    (void)wo;
    float c = dot3(s->n, wi);
    return c > 0.0f ? c * RESTIRCL_INV_PI : 0.0f;
}

/* Draw wi for wo from (u0, u1) uniform in [0, 1)^2, cosine-distributed about s->n (a concentric-disk point lifted
 * onto the hemisphere: its density is cos / pi). Returns f(wo, *wi); *pdf = bsdf_pdf(s, wo, *wi), 0 for a direction
 * that grazes the surface. */
inline float3 bsdf_sample(const Surface* s, float3 wo, float u0, float u1, float3* wi, float* pdf)
{
    float2 d = concentric_disk(u0, u1);
    float z = sqrt(fmax_f(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    float3 t, b;
    light_onb(s->n, &t, &b);
    *wi = d.x * t + d.y * b + z * s->n;
    *pdf = bsdf_pdf(s, wo, *wi);
    return bsdf_eval(s, wo, *wi);
}

#endif
