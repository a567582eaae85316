/* The primary hit's surface attributes (TriAttr, ObjectInfo in types.h): the shading normal of smooth shading,
 * faced like the geometric normal, and the texture coordinates with the footprint of the camera ray's cone, from
 * which the image lookups pick their mip level. Without attributes (a mesh with neither normals nor a textured
 * material) the shading normal is the geometric one, bit for bit. */
#ifndef RESTIRCL_TEXTURE_POINT_H
#define RESTIRCL_TEXTURE_POINT_H

#include "surface/shading_normal.h"

typedef struct {
    float3 ns;        /* shading normal facing the camera (smooth shading, then a normal map's: texture_material) */
    float3 nb;        /* under a normal map: the smooth shading normal it perturbs (bump_shadowing) */
    float3 n_front;   /* the same on the mesh's front side (not flipped towards the camera): the normal map's base */
    float3 ng;        /* geometric normal facing the camera */
    float3 wi;        /* unit direction towards the camera */
    float3 tangent;   /* world-space UV tangent, orthogonal to n_front, unit; 0 without a UV map */
    float3 uv;        /* (u, v, 0) of the UV map */
    float3 obj;       /* object-space position */
    float3 gen;       /* generated coordinates: the object's bounding box mapped to [0, 1]^3 */
    float sign;       /* bitangent = sign * cross(n_front, tangent) */
    float lod_uv;     /* log2 of the ray cone's width at the hit in UV units (footprint / |cos|) */
    float lod_obj;    /* the same in object-space units */
    float lod_gen;    /* the same in generated units */
    int backfacing;   /* 1: the camera sees the mesh's back side */
    int bumped;       /* 1: ns comes from a normal map */
    const __global float4* attrs;  /* the TriAttr buffer as float4s: colour attribute blocks follow the records */
    int attr_off;     /* this triangle's block of attribute colours in attrs (upload/attributes.py); 0: none */
    float3 bary;      /* the hit's barycentric weights of the triangle's corners */
    int prim;         /* its TriAttr record (leaf order); -1: none (textures/bump.h moves the point on it) */
    float3 e1, e2;    /* world-space edges v1 - v0, v2 - v0 of the triangle (surface/hit.h) */
    float3 gen_scale; /* the object's texture space scale (generated = (obj - mid) * gen_scale + 0.5) */
} TexPoint;

/* The attributes at barycentrics (bu, bv) of triangle prim (leaf order) of object obj, seen along unit d; ng faces
 * the camera, backfacing says whether it was flipped; cone_width is the camera ray cone's width at the hit. */
inline TexPoint texture_point(const __global TriAttr* attr, const __global ObjectInfo* objects, int prim, int obj,
                              float bu, float bv, float3 d, float3 ng, int backfacing, float cone_width)
{
    TexPoint tp;
    tp.ns = tp.nb = ng;
    tp.ng = ng;
    tp.n_front = backfacing ? -ng : ng;
    tp.wi = -d;
    tp.tangent = (float3)(0.0f);
    tp.uv = tp.obj = tp.gen = (float3)(0.0f);
    tp.sign = 1.0f;
    tp.lod_uv = tp.lod_obj = tp.lod_gen = 0.0f;
    tp.backfacing = backfacing;
    tp.bumped = 0;
    tp.attrs = (const __global float4*)attr;
    tp.attr_off = 0;
    tp.bary = (float3)(1.0f - bu - bv, bu, bv);
    tp.prim = -1;
    tp.e1 = tp.e2 = tp.gen_scale = (float3)(0.0f);
    ObjectInfo oi = objects[obj];
    int flags = as_int(oi.gen_mid.w);
    if (!(flags & OBJECT_ATTRIBUTES)) return tp;
    TriAttr a = attr[prim];
    float3 b = (float3)(1.0f - bu - bv, bu, bv);
    if (flags & OBJECT_NORMALS) {
        float3 n = b.x * a.n0.xyz + b.y * a.n1.xyz + b.z * a.n2.xyz;
        float l2 = dot3(n, n);
        if (l2 > 0.0f && finite_f(l2)) {
            tp.n_front = n * (1.0f / sqrt(l2));
            tp.ns = tp.nb = shading_normal_guard(backfacing ? -tp.n_front : tp.n_front, ng, tp.wi);
        }
    }
    tp.uv = (float3)(dot3(b, a.u.xyz), dot3(b, a.v.xyz), 0.0f);
    tp.obj = a.o0.xyz + bu * a.oe1.xyz + bv * a.oe2.xyz;
    tp.gen = (tp.obj - oi.gen_mid.xyz) * oi.gen_scale.xyz + 0.5f;
    float3 t = a.tangent.xyz - tp.n_front * dot3(tp.n_front, a.tangent.xyz);
    float t2 = dot3(t, t);
    if ((flags & OBJECT_UVS) && t2 > 0.0f && finite_f(t2)) tp.tangent = t * (1.0f / sqrt(t2));
    tp.sign = a.v.w;
    tp.attr_off = as_int(a.tangent.w);
    tp.prim = prim;
    tp.gen_scale = oi.gen_scale.xyz;
    float base = log2(cone_width / fmax_f(abs_f(dot3(ng, d)), 1e-4f));
    tp.lod_uv = a.u.w + base;
    tp.lod_obj = a.o0.w + base;
    tp.lod_gen = a.oe1.w + base;
    return tp;
}

#endif
