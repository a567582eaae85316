/* Emissive triangles (mesh lights): the lights that are also geometry, sampled uniformly in area. The host makes
 * them two-sided, as Cycles' emission shader is. */
#ifndef RESTIRCL_LIGHTS_TRIANGLE_H
#define RESTIRCL_LIGHTS_TRIANGLE_H

#include "lights/eval.h"
#include "lights/record.h"

#define LIGHT_TRIANGLE 0

typedef struct {
    float3 v0;    /* p.xyz */
    float3 e1;    /* a.xyz: v1 - v0 */
    float3 e2;    /* b.xyz: v2 - v0 */
    float area;   /* b.w */
} TriangleLight;

inline TriangleLight triangle_light(const __global Light* l)
{
    TriangleLight t = {l->p.xyz, l->a.xyz, l->b.xyz, l->b.w};
    return t;
}

/* (u, v) -> barycentrics (sqrt(u) (1 - v), sqrt(u) v): uniform in area. */
inline bool triangle_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    TriangleLight t = triangle_light(l);
    float su = sqrt(u);
    float3 ny = norm3(cross3(t.e1, t.e2));
    float3 y = t.v0 + t.e1 * (su * (1.0f - v)) + t.e2 * (su * v);
    /* the same bound as the shading point's: y is computed from the same kind of sum */
    e->eps = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(t.v0) + max_abs3(t.e1) + max_abs3(t.e2));
    return area_contrib(y, ny, light_radiance(l), light_two_sided(l), x, n, e);
}

inline float2 triangle_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    *pdf = 1.0f / triangle_light(l).area;
    return (float2)(r0, r1);
}

#endif
