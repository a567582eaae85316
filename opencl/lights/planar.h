/* The record lanes of the planar emitters (triangle, quad, disk): a point and two vectors that span the shape, its
 * area, and uniform sampling in area; each type maps (u, v) to its shape. */
#ifndef RESTIRCL_LIGHTS_PLANAR_H
#define RESTIRCL_LIGHTS_PLANAR_H

#include "lights/eval.h"
#include "lights/record.h"
#include "sampling/warps.h"

typedef struct {
    float3 origin;   /* p.xyz: triangle v0, quad corner, disk centre */
    float3 span_u;   /* a.xyz: triangle v1 - v0, quad edge, disk semi-axis */
    float3 span_v;   /* b.xyz: triangle v2 - v0, quad edge, disk semi-axis */
    float area;      /* b.w */
} PlanarLight;

inline PlanarLight planar_light(const __global Light* l)
{
    PlanarLight pl = {l->p.xyz, l->a.xyz, l->b.xyz, l->b.w};
    return pl;
}

/* The emitting side: along cross(span_u, span_v), and the other side too where the record is two-sided. */
inline float3 planar_normal(PlanarLight pl) { return norm3(cross3(pl.span_u, pl.span_v)); }

/* Point y of a planar light l: its contribution at x with normal n. */
inline bool planar_contrib(const __global Light* l, PlanarLight pl, float3 y, float3 x, float3 n, LightEval* e)
{
    return area_contrib(y, planar_normal(pl), light_radiance(l), light_two_sided(l), x, n, e);
}

inline float2 planar_sample(const __global Light* l, float r0, float r1, float* pdf)
{
    *pdf = 1.0f / planar_light(l).area;
    return (float2)(r0, r1);
}

/* The area density, under uniform sampling of solid angle S from x, of the point origin + ab.x span_u + ab.y span_v
 * of pl (solid_angle.h sa_area_pdf, written out: this header comes first). */
inline float planar_sa_pdf(PlanarLight pl, float2 ab, float3 x, float S)
{
    float3 d = pl.origin + ab.x * pl.span_u + ab.y * pl.span_v - x;
    float dist = len3(d);
    float cos_l = abs_f(dot3(planar_normal(pl), d)) / dist;
    return (cos_l > 0.0f && dist > 0.0f) ? cos_l / (dist * dist * S) : 0.0f;
}

/* Every planar shape has an area that rays meet (a triangle's through the BVH). */
inline bool planar_hittable(const __global Light* l)
{
    (void)l;
    return true;
}

/* Uniform radiance over the emitting side (the type's eval rejects the other side of a one-sided shape). */
inline float3 planar_hit_radiance(const __global Light* l, float3 x, float2 uv)
{
    (void)x;
    (void)uv;
    return light_radiance(l);
}

/* Where the ray x + t wi (t > 0) meets the plane of pl: the point's coordinates (a, b) with
 * point = origin + a span_u + b span_v; false when the ray is parallel to the plane or the plane is behind x. */
inline bool planar_ray_coords(PlanarLight pl, float3 x, float3 wi, float2* ab)
{
    float3 n = cross3(pl.span_u, pl.span_v);
    float denom = dot3(n, wi);
    float nn = dot3(n, n);
    if (!(abs_f(denom) > 0.0f) || !(nn > 0.0f)) return false;
    float t = dot3(n, pl.origin - x) / denom;
    if (!(t > 0.0f) || !finite_f(t)) return false;
    float3 q = x + t * wi - pl.origin;
    *ab = (float2)(dot3(cross3(q, pl.span_v), n), dot3(cross3(pl.span_u, q), n)) / nn;
    return true;
}

/* The coordinates (a, b) on the plane of pl of the direction (r0, r1) uniform over the hemisphere at x towards the
 * plane (solid_angle.h SA_HEMISPHERE; the caller tests whether the point is on its shape). Its area density there is
 * planar_sa_pdf with S = 2 pi. */
inline bool planar_hemisphere_ab(PlanarLight pl, float3 x, float r0, float r1, float2* ab)
{
    float3 n = planar_normal(pl);
    float3 towards_plane = dot3(n, pl.origin - x) >= 0.0f ? n : -n;
    return planar_ray_coords(pl, x, cone_dir(towards_plane, 1.0f, r0, r1), ab);
}

#endif
