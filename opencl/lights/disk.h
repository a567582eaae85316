/* Disk lights (Blender's disk and ellipse area lights): an ellipse sampled uniformly in area by the concentric map,
 * or, where the host flags it (orthogonal semi-axes, area_sampling), uniformly in the solid angle of its bounding
 * rectangle (spherical_rect.h): a point of the rectangle outside the ellipse is no sample (pdf 0), so the density on
 * the ellipse is the rectangle's, and the candidates lost are a quarter or fewer (less for close lights, whose
 * corners are far and small in solid angle); where that rectangle fills nearly the whole hemisphere, over the
 * hemisphere towards it (solid_angle.h SA_HEMISPHERE). Lanes: planar.h, origin the centre, spans the two
 * semi-axes. */
#ifndef RESTIRCL_LIGHTS_DISK_H
#define RESTIRCL_LIGHTS_DISK_H

#include "lights/planar.h"
#include "lights/solid_angle.h"
#include "lights/spherical_rect.h"
#include "sampling/warps.h"

inline bool disk_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    PlanarLight pl = planar_light(l);
    float3 centre = pl.origin, axis_u = pl.span_u, axis_v = pl.span_v;
    float2 q = concentric_disk(u, v);
    return planar_contrib(l, pl, centre + q.x * axis_u + q.y * axis_v, x, n, e);
}

/* How disk pl is sampled at x (solid_angle.h SA_*), and the spherical rectangle bounding it there when it is by
 * solid angle. */
inline int disk_solid_angle(const __global Light* l, PlanarLight pl, float3 x, SphRect* r)
{
    float3 dc = pl.origin - x;
    float extent2 = fmax_f(dot3(pl.span_u, pl.span_u), dot3(pl.span_v, pl.span_v));
    if (!sa_wanted(l, extent2, dot3(dc, dc)) ||
        !sph_rect_setup(pl.origin - pl.span_u - pl.span_v, 2.0f * pl.span_u, 2.0f * pl.span_v, x, r))
        return SA_AREA;
    return sa_choice(r->S);
}

inline float2 disk_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    PlanarLight pl = planar_light(l);
    SphRect r;
    int how = disk_solid_angle(l, pl, x, &r);
    if (how == SA_AREA) return planar_sample(l, r0, r1, pdf);
    float2 ab;  /* in semi-axes */
    if (how == SA_MAP) {
        ab = 2.0f * sph_rect_sample(&r, r0, r1) - 1.0f;
    } else if (!planar_hemisphere_ab(pl, x, r0, r1, &ab)) {
        *pdf = 0.0f;
        return (float2)(0.5f, 0.5f);
    }
    if (!(ab.x * ab.x + ab.y * ab.y <= 1.0f)) { *pdf = 0.0f; return (float2)(0.5f, 0.5f); }
    float2 uv = concentric_disk_inverse(ab);
    float2 q = concentric_disk(uv.x, uv.y);  /* the point disk_eval will evaluate */
    *pdf = planar_sa_pdf(pl, q, x, sa_sampled_sr(how, r.S));
    return uv;
}

/* disk_sample's density (area measure) of the evaluated point e at x. */
inline float disk_point_pdf(const __global Light* l, float3 x, const LightEval* e)
{
    PlanarLight pl = planar_light(l);
    SphRect r;
    int how = disk_solid_angle(l, pl, x, &r);
    return sa_point_pdf(how, how == SA_AREA ? 0.0f : r.S, pl.area, e);
}

/* The sample (u, v) of l that the ray x + t wi (t > 0) hits; false when it misses the ellipse. */
inline bool disk_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    float2 ab;
    if (!planar_ray_coords(planar_light(l), x, wi, &ab) || !(ab.x * ab.x + ab.y * ab.y <= 1.0f)) return false;
    *uv = concentric_disk_inverse(ab);
    return true;
}

inline bool disk_hittable(const __global Light* l) { return planar_hittable(l); }

inline float3 disk_hit_radiance(const __global Light* l, float3 x, float2 uv) { return planar_hit_radiance(l, x, uv); }

#endif
