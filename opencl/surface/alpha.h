/* The coverage of the triangle a ray met: the fraction of the light meeting it that its material takes, the rest
 * passing straight through (python/restircl/materials/alpha.py). Read from the records appended to the Tri array
 * (python/restircl/upload/alpha.py: the triangle's e1.w, -1 for an opaque one), so that every ray, camera, shadow or
 * bounce, evaluates it from the BVH's own buffers and all of them agree. An image is read at full resolution, as
 * the still renders read images: bilinear or closest, with the node's extension (Clip: alpha 0 outside). */
#ifndef RESTIRCL_SURFACE_ALPHA_H
#define RESTIRCL_SURFACE_ALPHA_H

#include "textures/image.h"

/* scalar texel (x, y) of the image whose texels start at float4 `first` of the tail, four to a float4 */
inline float alpha_texel(const __global float4* tail, int first, int w, int h, int x, int y, int ext)
{
    bool outside = false;
    x = tex_wrap(x, w, ext, &outside);
    y = tex_wrap(y, h, ext, &outside);
    if (outside) return 0.0f;
    int k = y * w + x;
    float4 q = tail[first + (k >> 2)];
    int lane = k & 3;
    return lane == 0 ? q.x : lane == 1 ? q.y : lane == 2 ? q.z : q.w;
}

/* the image of material record m at texture coordinate (s, t) ([0, 1]^2 is the image, t = 0 its bottom row) */
inline float alpha_image(const __global float4* tail, int4 info, float s, float t)
{
    int w = info.y, h = info.z, interp = info.w & 15, ext = info.w >> 4;
    if (interp == TEXINTERP_CLOSEST)
        return alpha_texel(tail, info.x, w, h, tex_floor(s * (float)w), tex_floor(t * (float)h), ext);
    float fx = s * (float)w - 0.5f, fy = t * (float)h - 0.5f;
    int x0 = tex_floor(fx), y0 = tex_floor(fy);
    float ax = finite_f(fx) ? fx - floor(fx) : 0.0f, ay = finite_f(fy) ? fy - floor(fy) : 0.0f;
    float c00 = alpha_texel(tail, info.x, w, h, x0, y0, ext), c10 = alpha_texel(tail, info.x, w, h, x0 + 1, y0, ext);
    float c01 = alpha_texel(tail, info.x, w, h, x0, y0 + 1, ext);
    float c11 = alpha_texel(tail, info.x, w, h, x0 + 1, y0 + 1, ext);
    return (1.0f - ay) * ((1.0f - ax) * c00 + ax * c10) + ay * ((1.0f - ax) * c01 + ax * c11);
}

/* Coverage in [0, 1] of triangle prim at barycentrics (u, v) of its vertices 1 and 2: 1 for an opaque triangle. */
inline float surface_coverage(const __global Tri* tris, int prim, float u, float v)
{
    int rec = as_int(tris[prim].e1.w);
    if (rec < 0) return 1.0f;
    const __global float4* tail = (const __global float4*)tris;
    float4 tu = tail[rec], tv = tail[rec + 1];
    int mat = as_int(tu.w);
    float4 m = tail[mat];
    float a = m.x;
    if (m.z != 0.0f) {
        float w0 = 1.0f - u - v;
        float uu = w0 * tu.x + u * tu.y + v * tu.z, vv = w0 * tv.x + u * tv.y + v * tv.z;
        float4 r0 = tail[mat + 2], r1 = tail[mat + 3];
        a = alpha_image(tail, as_int4(tail[mat + 1]), r0.x * uu + r0.y * vv + r0.z, r1.x * uu + r1.y * vv + r1.z);
    }
    a = finite_f(a) ? clamp_f(a, 0.0f, 1.0f) : 1.0f;
    return m.y != 0.0f ? 1.0f - a : a;
}

#endif
