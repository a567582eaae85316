/* Visibility of a light sample from a surface: the shadow ray, and the support test of the unbiased reuse. */
#ifndef RESTIRCL_VISIBILITY_H
#define RESTIRCL_VISIBILITY_H

/* The shadow ray o + t d, 0 < t < tmax, from surface s towards the light sample in e (tmax 0: the sample is at
 * the origin, nothing can block it). The origin is moved off the surface by a bound of the rounding error of
 * the hit point p = v0 + u e1 + v e2 (RESTIRCL_OFFSET_ULPS epsilons of the largest magnitude in that sum), the end off an emissive triangle by the same bound for the light sample (e->eps); other lights are not
 * geometry and need no offset (the ray stops 1e-4 short of them). A bound relative to p alone (256 ulps of p) is 2 m
 * at 1e5 from the origin, and a light closer than that to a surface was found shadowed by the surface itself (the
 * stress case offset_1e5). */
inline void shadow_ray(const __global Tri* tris, const Surface* s, const LightEval* e, float3* o, float3* d,
                       float* tmax, uint2* blocks)
{
#ifdef HAS_LIGHT_LINKING
    const uint2 blockers = e->blockers;  /* the objects that shadow this light (lights/linking.h) */
#else
    const uint2 blockers = (uint2)(0xFFFFFFFFu);
#endif
    Tri tri = tris[s->prim];
    float err = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(s->x) + max_abs3(tri.e1.xyz) + max_abs3(tri.e2.xyz));
    *o = s->x + err * (dot3(s->ng, e->wi) >= 0.0f ? s->ng : -s->ng);
    *d = e->wi;
    *tmax = INFINITY;
    *blocks = blockers;
    if (!finite_f(e->dist)) return;
    float3 t = e->pos + e->eps * e->nl;
    float3 v = t - *o;
    float len = len3(v);
    *tmax = 0.0f;
    if (!(len > 0.0f)) return;
    *d = v / len;
    *tmax = len * 0.9999f;
}

#ifdef HAS_TRANSPARENCY
/* How many transparent surfaces a shadow ray from s may pass: Transparent Max Bounces less those the path passed to
 * reach s, as Cycles counts them (bvh/transparent.h). TEST_SHADOW_ALLOWANCE_WHOLE, a negative control of the tests
 * only (tests/bias_controls.py): the whole bound, whatever the path passed. */
inline int shadow_allowance(const Surface* s)
{
#ifdef TEST_SHADOW_ALLOWANCE_WHOLE
    (void)s;
    return TRANSPARENT_MAX_BOUNCES;
#else
    return TRANSPARENT_MAX_BOUNCES - s->passed;
#endif
}
#endif

/* Is the light sample in e unblocked from surface s (the shadow ray of shadow_ray)? */
inline bool visible(const __global BVHNode* nodes, const __global Tri* tris, const Surface* s, const LightEval* e)
{
    float3 o, d;
    float tmax;
    uint2 blockers;
    shadow_ray(tris, s, e, &o, &d, &tmax, &blockers);
    if (!(tmax > 0.0f)) return true;
#ifdef HAS_THIN_SHADOW  /* smooth thin walls pass some light: the sample is in the support where any of it passes */
    return shadow_any(trace_transmittance(nodes, tris, o, d, tmax, blockers, shadow_allowance(s)));
#endif
#ifdef HAS_TRANSPARENCY  /* trace_any passes transparent surfaces by their coverage (bvh/transparent.h); the yes/no
                          * test of a light with linked shadows takes its blockers as opaque */
#ifdef TEST_OPAQUE_SHADOWS
    if (blockers.x == 0xFFFFFFFFu && blockers.y == 0xFFFFFFFFu) return !trace_any(nodes, tris, o, d, tmax);
#else
    if (blockers.x == 0xFFFFFFFFu && blockers.y == 0xFFFFFFFFu)
        return !trace_any_transparent(nodes, tris, o, d, tmax, shadow_allowance(s));
#endif
#endif
    return !trace_any_of(nodes, tris, o, d, tmax, blockers);
}

/* The fraction of light sample e that reaches s: visible()'s 1 or 0; in transparent builds the product of the
 * transparencies of the surfaces on the way (bvh/transparent.h trace_transmittance), Cycles' transparent shadows,
 * for the estimators whose shadow ray is the last word on the sample (the direct samplers, NEE at path vertices):
 * no coin per surface to add noise. Past smooth thin walls it is a colour (Shadow: bvh/thin_wall_shadow.h). */
inline Shadow transmittance(const __global BVHNode* nodes, const __global Tri* tris, const Surface* s,
                           const LightEval* e)
{
#ifdef HAS_TRANSPARENCY
    float3 o, d;
    float tmax;
    uint2 blockers;
    shadow_ray(tris, s, e, &o, &d, &tmax, &blockers);
    return tmax > 0.0f ? trace_transmittance(nodes, tris, o, d, tmax, blockers, shadow_allowance(s)) : 1.0f;
#else
    return visible(nodes, tris, s, e) ? 1.0f : 0.0f;
#endif
}

/* Is sample y = (light, u, v) in the support of the reservoir of surface s: p-hat_s(y) > 0 and, when
 * reservoirs keep only visible samples (visibility reuse), V_s(y) = 1? Used by the 1/Z support tests of the
 * unbiased reuse (a sample taken from another pixel is shadow-tested with the evaluation made when it was picked). */
inline bool in_support(const Surface* s, const __global BVHNode* nodes, const __global Tri* tris,
                       const __global Light* lights, int light, float u, float v, int visibility)
{
    LightEval e;
    if (!(target_of(s, lights, light, u, v, &e) > 0.0f)) return false;
    return !visibility || visible(nodes, tris, s, &e);
}

#endif
