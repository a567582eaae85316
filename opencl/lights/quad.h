/* Quad lights (Blender's square and rectangle area lights): a parallelogram sampled uniformly in area. Lanes:
 * planar.h, origin a corner, spans the two edges from it. */
#ifndef RESTIRCL_LIGHTS_QUAD_H
#define RESTIRCL_LIGHTS_QUAD_H

#include "lights/planar.h"

#define LIGHT_QUAD 1

inline bool quad_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    PlanarLight pl = planar_light(l);
    float3 corner = pl.origin, edge_u = pl.span_u, edge_v = pl.span_v;
    return planar_contrib(l, pl, corner + u * edge_u + v * edge_v, x, n, e);
}

inline float2 quad_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    return planar_sample(l, r0, r1, pdf);
}

/* The sample (u, v) of l that the ray x + t wi (t > 0) hits; false when it misses the quad. */
inline bool quad_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    float2 ab;
    if (!planar_ray_coords(planar_light(l), x, wi, &ab)) return false;
    *uv = ab;
    return ab.x >= 0.0f && ab.x < 1.0f && ab.y >= 0.0f && ab.y < 1.0f;
}

#endif
