/* Shadow rays through smooth thin walls (HAS_THIN_SHADOW: some material is a Principled Thin Wall whose transmission
 * is smooth, python/restircl/upload/thin_wall_shadow.py). Cycles 5.3 gives a smooth thin wall a Transparent BSDF
 * for every ray but the camera's, of weight its transmission's (the slab's T at the ray's angle times the closure's
 * weight): a sheet that does not bend light is transparent to a shadow ray, which keeps T of the light. Here the
 * shadow ray's loop (bvh/transparent.h trace_transmittance, which such builds compile: the scene's upload turns
 * HAS_TRANSPARENCY on with it) multiplies that colour in at each such wall, counted against Transparent max bounces
 * as any transparent surface; the wall's record (weight, Base Color, IOR, Specular Tint) follows its coverage
 * record in the Tri array's tail (surface/alpha.h), so shadow rays read it from the BVH's own buffers.
 *
 * Without the flag a shadow ray's transmittance stays the float product of 1 - coverage: Shadow is float there and
 * the code is what it was. */
#ifndef RESTIRCL_BVH_THIN_WALL_SHADOW_H
#define RESTIRCL_BVH_THIN_WALL_SHADOW_H

#ifdef HAS_THIN_SHADOW

#include "bsdf/thin_wall_slab.h"
#include "surface/alpha.h"

typedef float3 Shadow;  /* what a shadow ray keeps of the light, per colour */
#define shadow_any(v) ((v).x > 0.0f || (v).y > 0.0f || (v).z > 0.0f)

/* Whether the record of triangle prim holds a smooth thin wall: its float4 index in the tail, else 0 */
inline int thin_wall_record(const __global Tri* tris, int prim)
{
    int rec = as_int(tris[prim].e1.w);
    if (rec < 0) return 0;
    const __global float4* tail = (const __global float4*)tris;
    int mat = as_int(tail[rec].w);
    return tail[mat].w != 0.0f ? mat + 4 : 0;
}

/* What passes triangle prim at barycentrics (u, v) along unit direction d: 1 - a of a coverage a, plus, on a smooth
 * thin wall, a times its transmission's weight times the slab's T at the angle of d */
inline float3 thin_wall_pass(const __global Tri* tris, int prim, float u, float v, float3 d)
{
    float a = surface_coverage(tris, prim, u, v);
    float3 through = (float3)(1.0f - a);
    int w = thin_wall_record(tris, prim);
    if (w == 0) return through;
    const __global float4* tail = (const __global float4*)tris;
    float4 base = tail[w], tint = tail[w + 1];  /* (Base Color, IOR), (Specular Tint, weight) */
    Tri t = tris[prim];
    float mu = clamp_f(abs_f(dot3(norm3(cross3(t.e1.xyz, t.e2.xyz)), d)), 0.0f, 1.0f);
    float3 R;
    return through + (a * tint.w) * thin_wall_slab(mu, base.w, tint.xyz, base.xyz, &R);
}

#define shadow_pass(tris, h, d) thin_wall_pass(tris, (h).prim, (h).u, (h).v, d)

#else

typedef float Shadow;
#define shadow_any(v) ((v) > 0.0f)
#define shadow_pass(tris, h, d) (1.0f - surface_coverage(tris, (h).prim, (h).u, (h).v))

#endif

#endif
