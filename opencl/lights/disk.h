/* Disk lights (Blender's disk and ellipse area lights): an ellipse given by two semi-axes, sampled uniformly in
 * area by the concentric map, emitting along cross(axis_u, axis_v). */
#ifndef RESTIRCL_LIGHTS_DISK_H
#define RESTIRCL_LIGHTS_DISK_H

#include "lights/eval.h"
#include "lights/record.h"
#include "lights/warps.h"

#define LIGHT_DISK 2

typedef struct {
    float3 centre;   /* p.xyz */
    float3 axis_u;   /* a.xyz: semi-axis */
    float3 axis_v;   /* b.xyz: semi-axis */
    float area;      /* b.w */
} DiskLight;

inline DiskLight disk_light(const __global Light* l)
{
    DiskLight d = {l->p.xyz, l->a.xyz, l->b.xyz, l->b.w};
    return d;
}

inline bool disk_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    DiskLight d = disk_light(l);
    float2 q = concentric_disk(u, v);
    float3 ny = norm3(cross3(d.axis_u, d.axis_v));
    float3 y = d.centre + q.x * d.axis_u + q.y * d.axis_v;
    return area_contrib(y, ny, light_radiance(l), light_two_sided(l), x, n, e);
}

inline float2 disk_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    *pdf = 1.0f / disk_light(l).area;
    return (float2)(r0, r1);
}

#endif
