/* Disk lights (Blender's disk and ellipse area lights): an ellipse sampled uniformly in area by the concentric map.
 * Lanes: planar.h, origin the centre, spans the two semi-axes. */
#ifndef RESTIRCL_LIGHTS_DISK_H
#define RESTIRCL_LIGHTS_DISK_H

#include "lights/planar.h"
#include "lights/warps.h"

#define LIGHT_DISK 2

inline bool disk_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    PlanarLight pl = planar_light(l);
    float3 centre = pl.origin, axis_u = pl.span_u, axis_v = pl.span_v;
    float2 q = concentric_disk(u, v);
    return planar_contrib(l, pl, centre + q.x * axis_u + q.y * axis_v, x, n, e);
}

inline float2 disk_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    return planar_sample(l, r0, r1, pdf);
}

/* The sample (u, v) of l that the ray x + t wi (t > 0) hits; false when it misses the ellipse. */
inline bool disk_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    float2 ab;
    if (!planar_ray_coords(planar_light(l), x, wi, &ab) || !(ab.x * ab.x + ab.y * ab.y <= 1.0f)) return false;
    *uv = concentric_disk_inverse(ab);
    return true;
}

#endif
