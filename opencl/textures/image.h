/* Image lookups in the one texel buffer (float4 texels, TexImage offsets and mip chains, types.h): Blender's
 * Linear (bilinear) and Closest interpolation, its Repeat / Extend / Clip extensions, and trilinear filtering
 * between the two mip levels around the ray cone's footprint. */
#ifndef RESTIRCL_TEXTURE_IMAGE_H
#define RESTIRCL_TEXTURE_IMAGE_H

/* Texel index i of a row or column of n under the extension; *outside is set where Clip leaves the image. */
inline int tex_wrap(int i, int n, int ext, bool* outside)
{
    if (ext == TEXEXT_REPEAT) {
        int r = i % n;
        return r < 0 ? r + n : r;
    }
    if (i < 0 || i >= n) {
        if (ext == TEXEXT_CLIP) *outside = true;
        return i < 0 ? 0 : n - 1;
    }
    return i;
}

inline float4 tex_texel(const __global float4* texels, int offset, int w, int h, int x, int y, int ext)
{
    bool outside = false;
    x = tex_wrap(x, w, ext, &outside);
    y = tex_wrap(y, h, ext, &outside);
    return outside ? (float4)(0.0f) : texels[offset + y * w + x];
}

/* floor of a coordinate in texels, kept in int range (a huge or non-finite UV reads some texel, never UB) */
inline int tex_floor(float x)
{
    return finite_f(x) ? (int)floor(clamp_f(x, -1073741824.0f, 1073741824.0f)) : 0;
}

/* One mip level: st in image units ([0, 1]^2 is the image, t = 0 its bottom row). */
inline float4 tex_level(const __global float4* texels, TexImage im, int level, float2 st, int interp, int ext)
{
    int offset = im.offset, w = im.width, h = im.height;
    for (int l = 0; l < level; ++l) {
        offset += w * h;
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    if (interp == TEXINTERP_CLOSEST)
        return tex_texel(texels, offset, w, h, tex_floor(st.x * (float)w), tex_floor(st.y * (float)h), ext);
    float fx = st.x * (float)w - 0.5f, fy = st.y * (float)h - 0.5f;
    int x0 = tex_floor(fx), y0 = tex_floor(fy);
    float ax = finite_f(fx) ? fx - floor(fx) : 0.0f, ay = finite_f(fy) ? fy - floor(fy) : 0.0f;
    float4 c00 = tex_texel(texels, offset, w, h, x0, y0, ext), c10 = tex_texel(texels, offset, w, h, x0 + 1, y0, ext);
    float4 c01 = tex_texel(texels, offset, w, h, x0, y0 + 1, ext);
    float4 c11 = tex_texel(texels, offset, w, h, x0 + 1, y0 + 1, ext);
    return (1.0f - ay) * ((1.0f - ax) * c00 + ax * c10) + ay * ((1.0f - ax) * c01 + ax * c11);
}

/* sRGB-encoded -> linear (IEC 61966-2-1), for 8-bit sRGB images that Cycles keeps encoded and filters as they
 * are (its bilinear blend of two texels is the decoded blend of their codes, darker than the blend of the decoded
 * texels); every other image is linear in the texel buffer. */
inline float tex_srgb_decode(float c)
{
    return c <= 0.04045f ? c * (1.0f / 12.92f) : pow((fmax_f(c, 0.0f) + 0.055f) * (1.0f / 1.055f), 2.4f);
}

/* The mip level of a footprint: lod is log2 of the footprint's width in image units (textures/point.h); a footprint
 * of one texel is level 0. Clamped to the chain; NaN reads level 0. */
inline float tex_mip_level(TexImage im, float lod)
{
    float lambda = lod + 0.5f * log2((float)im.width * (float)im.height);
    return clamp_f(lambda > 0.0f ? lambda : 0.0f, 0.0f, (float)(im.levels - 1));
}

/* Image `index` at st with footprint lod: Closest reads the nearest level, Linear blends the two around it. */
inline float4 texture_image(const __global TexImage* images, const __global float4* texels, int index, float2 st,
                            float lod, int interp, int ext)
{
    TexImage im = images[index];
    float lambda = tex_mip_level(im, lod);
    if (interp == TEXINTERP_CLOSEST) return tex_level(texels, im, (int)(lambda + 0.5f), st, interp, ext);
    int l0 = (int)lambda;
    float f = lambda - (float)l0;
    float4 c = tex_level(texels, im, l0, st, interp, ext);
    if (f > 0.0f && l0 + 1 < im.levels) c = (1.0f - f) * c + f * tex_level(texels, im, l0 + 1, st, interp, ext);
    return c;
}

#endif
