/* Shading at a G-buffer surface: the target function p-hat of a light sample, the shadow ray, the estimate,
 * and the guard that keeps NaN/Inf out of every output. Diffuse surfaces only: f = albedo / pi. */
#ifndef RESTIRCL_SHADING_H
#define RESTIRCL_SHADING_H

#include "numerics.h"

typedef struct {
    float3 x;       /* world position */
    float3 n;       /* shading normal facing the camera */
    float3 ng;      /* geometric normal facing the camera */
    float3 brdf;    /* albedo / pi */
    float depth;    /* view depth */
    int valid;      /* 0: the primary ray missed */
    int prim;       /* the triangle hit (leaf order; < 0: none), for the shadow ray offset */
} Surface;

inline Surface surface_load(const __global GSample* g, int i)
{
    Surface s;
    GSample gs = g[i];
    s.prim = as_int(gs.normal.w);
    s.valid = s.prim >= 0;
    s.x = gs.pos.xyz;
    s.depth = gs.pos.w;
    s.n = gs.normal.xyz;
    s.ng = gs.gnormal.xyz;
    s.brdf = gs.albedo.xyz * RESTIRCL_INV_PI;
    return s;
}

/* p-hat(y) at surface s for light record rec: luminance of the unshadowed contribution f * Le * cos_x * G. Fills *e
 * when > 0. */
inline float target_of_record(const Surface* s, const __global Light* rec, float u, float v, LightEval* e)
{
    if (!s->valid) return 0.0f;
    if (!light_eval(rec, u, v, s->x, s->n, e)) return 0.0f;
    float t = luminance(s->brdf * e->contrib);
    return (t > 0.0f && finite_f(t)) ? t : 0.0f;
}

/* target_of_record of lights[light]; 0 for light < 0 */
inline float target_of(const Surface* s, const __global Light* lights, int light, float u, float v, LightEval* e)
{
    return light < 0 ? 0.0f : target_of_record(s, &lights[light], u, v, e);
}

/* Shadow ray from surface s towards the light sample in e. The origin is moved off the surface by a bound of the
 * rounding error of the hit point p = v0 + u e1 + v e2 (RESTIRCL_OFFSET_ULPS epsilons of the largest magnitude in
 * that sum), the end off an emissive triangle by the same bound for the light sample (e->eps); other lights are not
 * geometry and need no offset (the ray stops 1e-4 short of them). Both ends used to go through offset_ray_origin,
 * whose 256 ulps of p are 2 m at 1e5 from the origin: in a scene offset that far, a light closer than ~2 m to a
 * surface was found shadowed by that surface itself (the stress case offset_1e5). */
inline bool visible(const __global BVHNode* nodes, const __global Tri* tris, const Surface* s, const LightEval* e)
{
    Tri tri = tris[s->prim];
    float err = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(s->x) + max_abs3(tri.e1.xyz) + max_abs3(tri.e2.xyz));
    float3 o = s->x + err * (dot3(s->ng, e->wi) >= 0.0f ? s->ng : -s->ng);
    if (!finite_f(e->dist)) return !trace_any(nodes, tris, o, e->wi, INFINITY);
    float3 t = e->pos + e->eps * e->nl;
    float3 d = t - o;
    float len = len3(d);
    if (!(len > 0.0f)) return true;
    return !trace_any(nodes, tris, o, d / len, len * 0.9999f);
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

inline void guard_count(volatile __global int* guards, int which) { atomic_inc(&guards[which]); }

/* Replace a NaN/Inf colour by 0 and count it. */
inline float3 guard_finite(float3 c, volatile __global int* guards, int which)
{
    if (finite3_f(c)) return c;
    guard_count(guards, which);
    return (float3)(0.0f);
}

#endif
