/* Uniform sampling of the solid angle a triangle subtends (Arvo, "Stratified sampling of spherical triangles",
 * SIGGRAPH 1995): the sub-triangle A B' C' of area u S is found by the spherical law of cosines, then the point is
 * drawn on the arc from B to C' (uniform in the cosine of its distance from B). The solid angle itself comes from
 * Van Oosterom and Strackee's formula, which has no cancellation for small triangles; the map still loses
 * precision there (1 - q^2 of a q near 1), hence the fallback to area sampling below SA_MIN_SR (solid_angle.h). The
 * angle at A enters only through its cosine and sine, from the planes' normals: with sin and cos of u S and the
 * atan2 of S, three transcendentals (trig.h). */
#ifndef RESTIRCL_LIGHTS_SPHERICAL_TRI_H
#define RESTIRCL_LIGHTS_SPHERICAL_TRI_H

#include "lights/trig.h"
#include "sampling/warps.h"

typedef struct {
    float3 A, B, C;      /* unit directions from the shading point to the vertices */
    float cos_alpha, sin_alpha;  /* of the spherical triangle's angle at A */
    float S;             /* solid angle */
} SphTri;

/* The spherical triangle of (v0, v1, v2) seen from x; false when it is degenerate (x on its plane, or on a vertex). */
inline bool sph_tri_setup(float3 v0, float3 v1, float3 v2, float3 x, SphTri* t)
{
    float3 a = v0 - x, b = v1 - x, c = v2 - x;
    float la = len3(a), lb = len3(b), lc = len3(c);
    if (!(la > 0.0f) || !(lb > 0.0f) || !(lc > 0.0f)) return false;
    t->A = a / la;
    t->B = b / lb;
    t->C = c / lc;
    float3 nab = cross3(t->A, t->B), nca = cross3(t->C, t->A);
    float lab = len3(nab), lca = len3(nca);
    if (!(lab > 0.0f) || !(lca > 0.0f)) return false;
    /* the angle at A, between the planes A B and A C: its cosine and (from the cross product, exact near 0) sine */
    float3 na = nab / lab, nc = -nca / lca;
    t->cos_alpha = dot3(na, nc);
    t->sin_alpha = len3(cross3(na, nc));
    float triple = abs_f(dot3(t->A, cross3(t->B, t->C)));
    float denom = 1.0f + dot3(t->A, t->B) + dot3(t->B, t->C) + dot3(t->C, t->A);
    t->S = 2.0f * atan2_f(triple, denom);
    return t->S > 0.0f && t->sin_alpha > 0.0f;
}

/* A unit direction inside the spherical triangle for (u, v) in [0,1)^2, uniform in solid angle. */
inline float3 sph_tri_sample(const SphTri* t, float u, float v)
{
    float area = u * t->S;
    float2 sc = sincos_f(area);
    float s_area = sc.x, c_area = sc.y;
    float ca = t->cos_alpha, sa = t->sin_alpha;
    float s = s_area * ca - c_area * sa, c = c_area * ca + s_area * sa;  /* sin, cos of (area - alpha) */
    float cos_ab = dot3(t->A, t->B);
    float p = c - ca, q = s + sa * cos_ab;
    float cos_b = ((q * c - p * s) * ca - q) / ((q * s + p * c) * sa);  /* cos of the arc A C' */
    cos_b = clamp_f(cos_b, -1.0f, 1.0f);
    float3 perp_c = t->C - dot3(t->C, t->A) * t->A;
    float lpc = len3(perp_c);
    float3 c1 = lpc > 0.0f ? cos_b * t->A + sqrt(fmax_f(0.0f, 1.0f - cos_b * cos_b)) * (perp_c / lpc) : t->C;
    float z = 1.0f - v * (1.0f - dot3(c1, t->B));
    z = clamp_f(z, -1.0f, 1.0f);
    float3 perp_b = c1 - dot3(c1, t->B) * t->B;
    float lpb = len3(perp_b);
    float3 w = lpb > 0.0f ? z * t->B + sqrt(fmax_f(0.0f, 1.0f - z * z)) * (perp_b / lpb) : t->B;
    return norm3(w);
}

#endif
