/* The shading of a pixel from its final ReSTIR reservoir: f * Le * G * V * W, plus emission seen directly. Shared
 * by restir_shade.cl and the last spatial pass, which shades each pixel as it writes its reservoir (one pass over
 * the image fewer: no second read of the G-buffer and the reservoirs). visible_known: the reuse passes already kept
 * W = 0 for samples occluded at this pixel (unbiased mode with visibility reuse), so the shadow ray is left out. */
#ifndef RESTIRCL_RESTIR_SHADE_H
#define RESTIRCL_RESTIR_SHADE_H

inline float4 restir_shade_pixel(const __global GSample* gbuf, const Surface* s, const Reservoir* r, int i,
                                 const __global BVHNode* nodes, const __global Tri* tris,
                                 const __global Light* lights, int visible_known, volatile __global int* guards)
{
    float3 c = gbuf[i].emission.xyz;
    LightEval e;
    if (s->valid && r->light >= 0 && r->W > 0.0f && target_of(s, lights, r->light, r->u, r->v, &e) > 0.0f
        && (visible_known || visible(nodes, tris, s, &e)))
        c += unshadowed_contrib(s, &e) * r->W;
    return (float4)(guard_finite(c, guards, GUARD_NONFINITE_SAMPLE), 1.0f);
}

#endif
