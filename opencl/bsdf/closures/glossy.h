/* The Glossy BSDF: the GGX reflection lobe (bsdf/microfacet_reflection.h) of the metallic kind with f0 = 1 (no
 * Fresnel), its colour times the closure's weight as the lobe's weight; no diffuse part. */
#ifndef RESTIRCL_BSDF_CLOSURES_GLOSSY_H
#define RESTIRCL_BSDF_CLOSURES_GLOSSY_H

#include "bsdf/closure.h"
#include "bsdf/microfacet_reflection.h"

/* The closure's diffuse albedo (0, returned) at weight w > 0 and clamped colour base, and its lobe (lobes[0],
 * *count = 1) for view cosine mu. */
inline float3 glossy_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                             Lobe* lobes, int* count)
{
    ClosureGgx g = closure_ggx(c, mu, tab);
    MicrofacetReflection m = microfacet_reflection_none(g.alpha);
    m.metal_f0 = (float3)(1.0f);
    m.metal_w = base * w * (g.ms ? multiscatter_factor(base, g.e, g.e_avg) : (float3)(1.0f));
    lobes[0] = microfacet_reflection_lobe(&m, avg3(m.metal_w));
    *count = 1;
    return (float3)(0.0f);
}

#endif
