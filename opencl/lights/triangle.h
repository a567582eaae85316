/* Emissive triangles (mesh lights): the lights that are also geometry, sampled uniformly in area or, where the host
 * flags them (area_sampling), uniformly in the solid angle they subtend (spherical_tri.h) where float32 allows, or
 * over the hemisphere towards them where they fill nearly all of it (solid_angle.h SA_HEMISPHERE). The
 * host makes them two-sided, as Cycles' emission shader is. Lanes: planar.h, origin v0, spans e1 = v1 - v0,
 * e2 = v2 - v0. */
#ifndef RESTIRCL_LIGHTS_TRIANGLE_H
#define RESTIRCL_LIGHTS_TRIANGLE_H

#include "lights/planar.h"
#include "lights/solid_angle.h"
#include "lights/spherical_tri.h"
#include "lights/textured_emission.h"

/* (u, v) -> barycentrics (sqrt(u) (1 - v), sqrt(u) v): uniform in area. */
inline bool triangle_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    PlanarLight pl = planar_light(l);
    float3 v0 = pl.origin, e1 = pl.span_u, e2 = pl.span_v;
    float su = sqrt(u);
    float3 y = v0 + e1 * (su * (1.0f - v)) + e2 * (su * v);
    /* the bound the shading point gets (direct/visibility.h visible): y is the same kind of sum */
    e->eps = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(v0) + max_abs3(e1) + max_abs3(e2));
    if (light_textured(l)) {
        float3 le = triangle_textured_radiance(l, su * (1.0f - v), su * v);
        return area_contrib(y, planar_normal(pl), le, light_two_sided(l), x, n, e);
    }
    return planar_contrib(l, pl, y, x, n, e);
}

/* The sample (u, v) of the point with barycentric weights b1 (of v1) and b2 (of v2): the inverse of
 * triangle_eval's map, for a ray that hit the triangle (bvh/traverse.h Hit.u, Hit.v). */
inline float2 triangle_uv(float b1, float b2)
{
    float su = b1 + b2;
    if (!(su > 0.0f)) return (float2)(0.0f, 0.0f);
    return (float2)(clamp_f(su * su, 0.0f, 0.99999994f), clamp_f(b2 / su, 0.0f, 0.99999994f));
}

/* How pl is sampled at x (solid_angle.h SA_*), and its spherical triangle there when it is by solid angle. */
inline int triangle_solid_angle(const __global Light* l, PlanarLight pl, float3 x, SphTri* t)
{
    float3 e1 = pl.span_u, e2 = pl.span_v;
    float3 dc = pl.origin + (e1 + e2) * (1.0f / 3.0f) - x;
    float3 m0 = e1 + e2, m1 = 2.0f * e1 - e2, m2 = 2.0f * e2 - e1;  /* 3 x (centroid -> vertex) */
    float extent2 = fmax_f(dot3(m0, m0), fmax_f(dot3(m1, m1), dot3(m2, m2))) * (1.0f / 9.0f);
    if (!sa_wanted(l, extent2, dot3(dc, dc)) || !sph_tri_setup(pl.origin, pl.origin + e1, pl.origin + e2, x, t))
        return SA_AREA;
    return sa_choice(t->S);
}

inline float2 triangle_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    PlanarLight pl = planar_light(l);
    SphTri t;
    int how = triangle_solid_angle(l, pl, x, &t);
    if (how == SA_AREA) return planar_sample(l, r0, r1, pdf);
    float2 b;
    bool hit = how == SA_MAP ? planar_ray_coords(pl, x, sph_tri_sample(&t, r0, r1), &b)
                             : planar_hemisphere_ab(pl, x, r0, r1, &b) && b.x >= 0.0f && b.y >= 0.0f && b.x + b.y <= 1.0f;
    if (!hit) { *pdf = 0.0f; return (float2)(r0, r1); }
    b = (float2)(fmax_f(b.x, 0.0f), fmax_f(b.y, 0.0f));
    float sum = b.x + b.y;
    if (sum > 1.0f) b /= sum;  /* rounding put it just outside */
    float2 uv = triangle_uv(b.x, b.y);
    float su = sqrt(uv.x);  /* the point triangle_eval will evaluate */
    *pdf = planar_sa_pdf(pl, (float2)(su * (1.0f - uv.y), su * uv.y), x, sa_sampled_sr(how, t.S));
    return uv;
}

/* triangle_sample's density (area measure) of the evaluated point e at x. */
inline float triangle_point_pdf(const __global Light* l, float3 x, const LightEval* e)
{
    PlanarLight pl = planar_light(l);
    SphTri t;
    int how = triangle_solid_angle(l, pl, x, &t);
    return sa_point_pdf(how, how == SA_AREA ? 0.0f : t.S, pl.area, e);
}

/* Triangles are geometry: the BVH finds the one a ray meets (direct/bsdf_candidates.h bsdf_ray_triangle_light,
 * triangle_uv), not a test of each light, so this ray test is never one. */
inline bool triangle_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    (void)l; (void)x; (void)wi; (void)uv;
    return false;
}

inline bool triangle_hittable(const __global Light* l) { return planar_hittable(l); }

inline float3 triangle_hit_radiance(const __global Light* l, float3 x, float2 uv)
{
    return planar_hit_radiance(l, x, uv);
}

#endif
