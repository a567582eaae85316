/* What evaluating a light sample at a shading point gives (LightEval), and the contribution of a point on an area
 * emitter, which every type with an area measure (triangle, quad, disk, sphere) ends in. */
#ifndef RESTIRCL_LIGHTS_EVAL_H
#define RESTIRCL_LIGHTS_EVAL_H

#include "numerics.h"

typedef struct {
    float3 contrib;   /* Le * cos_x * G: cos_l / d^2 for area measure, 1 for solid angle, 1 / d^2 for points */
    float3 wi;        /* unit direction from the shading point towards the sample */
    float3 pos;       /* point on the light (shadow ray target); unused for the sun */
    float3 nl;        /* light normal at pos, facing the shading point (for offsetting the shadow ray end) */
    float dist;       /* distance to pos; INFINITY for the sun */
    float eps;        /* emissive triangles (lights that are also geometry): a bound of the float32 error of pos, by
                         which the shadow ray stops short of it (direct/visibility.h visible); 0 for every other light */
#ifdef HAS_LIGHT_LINKING
    uint2 blockers;   /* the blocker sets that shadow the light (lights/linking.h light_links) */
#endif
} LightEval;

/* Shadow ray ends are moved off their surfaces by RESTIRCL_OFFSET_ULPS float32 epsilons of the largest magnitude in
 * the sum that computed the point (p = v0 + u e1 + v e2): a bound of its rounding error with a margin, like pbrt's
 * error bounds (gamma(7) sum |b_i v_i|). */
#define RESTIRCL_OFFSET_ULPS 8.0f

inline float max_abs3(float3 v) { return fmax_f(abs_f(v.x), fmax_f(abs_f(v.y), abs_f(v.z))); }

inline float luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/* The unit direction *wi from x towards the light point y, the distance *dist and its square *d2; false when y is
 * too close to x for a direction. */
inline bool towards(float3 y, float3 x, float3* wi, float* dist, float* d2)
{
    float3 d = y - x;
    *d2 = dot3(d, d);
    if (!(*d2 > 1e-30f)) return false;
    *dist = sqrt(*d2);
    *wi = d / *dist;
    return true;
}

/* Contribution of an emitter point y with normal ny (area measure) seen from x with normal n. */
inline bool area_contrib(float3 y, float3 ny, float3 Le, bool two_sided, float3 x, float3 n, LightEval* e)
{
    float3 wi;
    float dist, d2;
    if (!towards(y, x, &wi, &dist, &d2)) return false;
    float cos_x = dot3(n, wi);
    float cos_l = -dot3(ny, wi);
    if (two_sided) { if (cos_l < 0.0f) { cos_l = -cos_l; ny = -ny; } }
    if (!(cos_x > 0.0f) || !(cos_l > 0.0f)) return false;
    e->contrib = Le * (cos_x * cos_l / d2);
    e->wi = wi;
    e->pos = y;
    e->nl = ny;
    e->dist = dist;
    return true;
}

#endif
