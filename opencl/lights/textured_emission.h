/* Emissive triangles whose emission is an image (lights/textured_emission.py): the radiance at the sampled point
 * itself, the image read there times Emission Strength, while the light's pick and its pdf stay by the triangle's
 * mean (its power), so the estimate is unbiased for an image that varies within a triangle. Such a record has
 * LIGHT_FLAG_TEXTURED and, in a.w, the offset in floats from the record to its block in the light buffer:
 * the image coordinates of its three corners (6 floats, the node's Mapping applied), the strength, then as ints the
 * offset of its image from the block, the image's width and height, interpolation and extension (TEXINTERP_*,
 * TEXEXT_*); the image is linear RGB triples, bottom row first, read as textures/image.h reads level 0. */
#ifndef RESTIRCL_LIGHTS_TEXTURED_EMISSION_H
#define RESTIRCL_LIGHTS_TEXTURED_EMISSION_H

#include "lights/record.h"
#include "textures/image.h"

/* the decode step: where the record's block is */
typedef struct {
    const __global float* block;  /* a.w: its offset in floats from the record */
} EmissionBlock;

inline bool light_textured(const __global Light* l) { return (light_flags(l) & LIGHT_FLAG_TEXTURED) != 0; }

inline float3 emission_texel(const __global float* img, int w, int h, int x, int y, int ext)
{
    bool outside = false;
    x = tex_wrap(x, w, ext, &outside);
    y = tex_wrap(y, h, ext, &outside);
    if (outside) return (float3)(0.0f);
    const __global float* t = img + 3 * (y * w + x);
    return (float3)(t[0], t[1], t[2]);
}

/* The emitted radiance of textured triangle l at the point of barycentric weights b1 (of v1) and b2 (of v2). */
inline float3 triangle_textured_radiance(const __global Light* l, float b1, float b2)
{
    EmissionBlock eb = {(const __global float*)l + as_int(l->a.w)};
    const __global float* blk = eb.block;
    float b0 = 1.0f - b1 - b2;
    float2 st = (float2)(b0 * blk[0] + b1 * blk[2] + b2 * blk[4], b0 * blk[1] + b1 * blk[3] + b2 * blk[5]);
    const __global float* img = blk + as_int(blk[7]);
    int w = as_int(blk[8]), h = as_int(blk[9]), interp = as_int(blk[10]), ext = as_int(blk[11]);
    if (interp == TEXINTERP_CLOSEST)
        return blk[6] * emission_texel(img, w, h, tex_floor(st.x * (float)w), tex_floor(st.y * (float)h), ext);
    float fx = st.x * (float)w - 0.5f, fy = st.y * (float)h - 0.5f;
    int x0 = tex_floor(fx), y0 = tex_floor(fy);
    float ax = finite_f(fx) ? fx - floor(fx) : 0.0f, ay = finite_f(fy) ? fy - floor(fy) : 0.0f;
    float3 c = (1.0f - ay) * ((1.0f - ax) * emission_texel(img, w, h, x0, y0, ext)
                              + ax * emission_texel(img, w, h, x0 + 1, y0, ext))
               + ay * ((1.0f - ax) * emission_texel(img, w, h, x0, y0 + 1, ext)
                       + ax * emission_texel(img, w, h, x0 + 1, y0 + 1, ext));
    return blk[6] * c;
}

#endif
