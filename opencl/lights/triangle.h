/* Emissive triangles (mesh lights): the lights that are also geometry, sampled uniformly in area. The host makes
 * them two-sided, as Cycles' emission shader is. Lanes: planar.h, origin v0, spans e1 = v1 - v0, e2 = v2 - v0. */
#ifndef RESTIRCL_LIGHTS_TRIANGLE_H
#define RESTIRCL_LIGHTS_TRIANGLE_H

#include "lights/planar.h"

#define LIGHT_TRIANGLE 0

/* (u, v) -> barycentrics (sqrt(u) (1 - v), sqrt(u) v): uniform in area. */
inline bool triangle_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    PlanarLight pl = planar_light(l);
    float3 v0 = pl.origin, e1 = pl.span_u, e2 = pl.span_v;
    float su = sqrt(u);
    float3 y = v0 + e1 * (su * (1.0f - v)) + e2 * (su * v);
    /* the bound the shading point gets (visibility.h visible): y is the same kind of sum */
    e->eps = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(v0) + max_abs3(e1) + max_abs3(e2));
    return planar_contrib(l, pl, y, x, n, e);
}

inline float2 triangle_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    return planar_sample(l, r0, r1, pdf);
}

/* The sample (u, v) of the point with barycentric weights b1 (of v1) and b2 (of v2): the inverse of
 * triangle_eval's map, for a ray that hit the triangle (bvh.h Hit.u, Hit.v). */
inline float2 triangle_uv(float b1, float b2)
{
    float su = b1 + b2;
    if (!(su > 0.0f)) return (float2)(0.0f, 0.0f);
    return (float2)(clamp_f(su * su, 0.0f, 0.99999994f), clamp_f(b2 / su, 0.0f, 0.99999994f));
}

#endif
