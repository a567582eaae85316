/* Quad lights (Blender's square and rectangle area lights): a parallelogram sampled uniformly in area, or, where
 * the host flags it (a rectangle, area_sampling), uniformly in the solid angle it subtends (spherical_rect.h).
 * Lanes: planar.h, origin a corner, spans the two edges from it. */
#ifndef RESTIRCL_LIGHTS_QUAD_H
#define RESTIRCL_LIGHTS_QUAD_H

#include "lights/planar.h"
#include "lights/solid_angle.h"
#include "lights/spherical_rect.h"

inline bool quad_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    PlanarLight pl = planar_light(l);
    float3 corner = pl.origin, edge_u = pl.span_u, edge_v = pl.span_v;
    return planar_contrib(l, pl, corner + u * edge_u + v * edge_v, x, n, e);
}

/* How quad pl is sampled at x (solid_angle.h SA_*), and its spherical rectangle there when it is by solid angle. */
inline int quad_solid_angle(const __global Light* l, PlanarLight pl, float3 x, SphRect* r)
{
    float3 dc = pl.origin + 0.5f * (pl.span_u + pl.span_v) - x;
    float extent2 = 0.25f * (dot3(pl.span_u, pl.span_u) + dot3(pl.span_v, pl.span_v));
    if (!sa_wanted(l, extent2, dot3(dc, dc)) || !sph_rect_setup(pl.origin, pl.span_u, pl.span_v, x, r)) return SA_AREA;
    return sa_choice(r->S);
}

inline float2 quad_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    PlanarLight pl = planar_light(l);
    SphRect r;
    int how = quad_solid_angle(l, pl, x, &r);
    if (how == SA_AREA) return planar_sample(l, r0, r1, pdf);
    float2 st;
    if (how == SA_MAP) {
        st = sph_rect_sample(&r, r0, r1);
    } else if (!planar_hemisphere_ab(pl, x, r0, r1, &st) || !(st.x >= 0.0f && st.x < 1.0f && st.y >= 0.0f && st.y < 1.0f)) {
        *pdf = 0.0f;
        return (float2)(r0, r1);
    }
    *pdf = planar_sa_pdf(pl, st, x, sa_sampled_sr(how, r.S));
    return st;
}

/* quad_sample's density (area measure) of the evaluated point e at x. */
inline float quad_point_pdf(const __global Light* l, float3 x, const LightEval* e)
{
    PlanarLight pl = planar_light(l);
    SphRect r;
    int how = quad_solid_angle(l, pl, x, &r);
    return sa_point_pdf(how, how == SA_AREA ? 0.0f : r.S, pl.area, e);
}

/* The sample (u, v) of l that the ray x + t wi (t > 0) hits; false when it misses the quad. */
inline bool quad_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    float2 ab;
    if (!planar_ray_coords(planar_light(l), x, wi, &ab)) return false;
    *uv = ab;
    return ab.x >= 0.0f && ab.x < 1.0f && ab.y >= 0.0f && ab.y < 1.0f;
}

inline bool quad_hittable(const __global Light* l) { return planar_hittable(l); }

inline float3 quad_hit_radiance(const __global Light* l, float3 x, float2 uv) { return planar_hit_radiance(l, x, uv); }

#endif
