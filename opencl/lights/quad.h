/* Quad lights (Blender's square and rectangle area lights): a parallelogram sampled uniformly in area, emitting
 * along cross(edge_u, edge_v). */
#ifndef RESTIRCL_LIGHTS_QUAD_H
#define RESTIRCL_LIGHTS_QUAD_H

#include "lights/eval.h"
#include "lights/record.h"

#define LIGHT_QUAD 1

typedef struct {
    float3 corner;   /* p.xyz */
    float3 edge_u;   /* a.xyz */
    float3 edge_v;   /* b.xyz */
    float area;      /* b.w */
} QuadLight;

inline QuadLight quad_light(const __global Light* l)
{
    QuadLight q = {l->p.xyz, l->a.xyz, l->b.xyz, l->b.w};
    return q;
}

inline bool quad_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    QuadLight q = quad_light(l);
    float3 ny = norm3(cross3(q.edge_u, q.edge_v));
    float3 y = q.corner + u * q.edge_u + v * q.edge_v;
    return area_contrib(y, ny, light_radiance(l), light_two_sided(l), x, n, e);
}

inline float2 quad_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    *pdf = 1.0f / quad_light(l).area;
    return (float2)(r0, r1);
}

#endif
