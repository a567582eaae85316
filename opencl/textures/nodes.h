/* Texture programs (TexNode, types.h; built by python/restircl/upload/textures.py): the nodes of one material input
 * stored in evaluation order, each reading its inputs from constants or from earlier nodes' registers, so a node
 * graph is evaluated in one loop (no recursion in OpenCL C). Checker and Mix follow Blender's definitions
 * (Cycles' kernel/svm/checker.h and mix.h); the Normal Map node its tangent-space rule with Strength; the converter
 * nodes (Separate / Combine Color, Math, Vector Math, Invert, Hue/Saturation/Value) are textures/converters.h;
 * Color Ramp reads its stops from the texel buffer, RGB Curves its table; Attribute the corner colours of the
 * triangle's block (textures/point.h). */
#ifndef RESTIRCL_TEXTURE_NODES_H
#define RESTIRCL_TEXTURE_NODES_H

#include "textures/converters.h"

/* a colour read by a value input (roughness, metallic, a factor), as Blender converts it: Rec.709 luminance */
inline float tex_gray(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/* the number a value input reads from the output v of node k: a node that gives a number (blk.w) holds it in every
 * component and is read exactly; a colour is read as its grey */
inline float tex_number(const __global TexNode* nodes, int k, float4 v)
{
    return nodes[k].blk.w ? v.x : tex_gray(v.xyz);
}

/* Blender's checker: 1 (color1) where the parity of floor(x) + floor(y) + floor(z) is odd, the coordinate nudged
 * off the integer lattice first as Blender does */
inline float tex_checker(float3 p)
{
    p = (p + 0.000001f) * 0.999999f;
    int xi = (int)floor(clamp_f(p.x, -1073741824.0f, 1073741824.0f));
    int yi = (int)floor(clamp_f(p.y, -1073741824.0f, 1073741824.0f));
    int zi = (int)floor(clamp_f(p.z, -1073741824.0f, 1073741824.0f));
    return ((xi ^ yi ^ zi) & 1) ? 1.0f : 0.0f;
}

inline float tex_overlay(float t, float a, float b)
{
    float tm = 1.0f - t;
    return a < 0.5f ? a * (tm + 2.0f * t * b) : 1.0f - (tm + 2.0f * t * (1.0f - b)) * (1.0f - a);
}

/* Blender's Mix (Color) blend modes: each blends a towards its combination with b by t */
inline float3 tex_mix(int blend, float t, float3 a, float3 b)
{
    float3 c;
    switch (blend) {
    case TEXMIX_MULTIPLY: c = a * b; break;
    case TEXMIX_ADD: c = a + b; break;
    case TEXMIX_SUBTRACT: c = a - b; break;
    case TEXMIX_SCREEN: return 1.0f - ((1.0f - t) + t * (1.0f - b)) * (1.0f - a);
    case TEXMIX_DIFFERENCE: c = fabs(a - b); break;
    case TEXMIX_DARKEN: c = (float3)(fmin_f(a.x, b.x), fmin_f(a.y, b.y), fmin_f(a.z, b.z)); break;
    case TEXMIX_LIGHTEN: c = (float3)(fmax_f(a.x, b.x), fmax_f(a.y, b.y), fmax_f(a.z, b.z)); break;
    case TEXMIX_OVERLAY: return (float3)(tex_overlay(t, a.x, b.x), tex_overlay(t, a.y, b.y), tex_overlay(t, a.z, b.z));
    case TEXMIX_MIX: c = b; break;
    default: return tex_mix_more(blend, t, a, b);
    }
    return a + t * (c - a);
}

/* The node's texture coordinate (its Mapping applied) and the footprint width there (log2, coordinate units). */
inline float3 tex_coords(const TexNode* n, const TexPoint* tp, float* lod)
{
    float3 c = tp->uv;
    *lod = tp->lod_uv;
    if (n->op.w == TEXCOORD_GENERATED) { c = tp->gen; *lod = tp->lod_gen; }
    if (n->op.w == TEXCOORD_OBJECT) { c = tp->obj; *lod = tp->lod_obj; }
    *lod += n->p.y;
    float4 c4 = (float4)(c, 1.0f);
    return (float3)(dot(n->m0, c4), dot(n->m1, c4), dot(n->m2, c4));
}

/* Blender's Normal Map node in tangent space: color in [0, 1]^3 -> a world-space shading normal on the camera's side
 * of the surface, unbent (surface/shading_normal.h: the specular lobes bend it, the diffuse part does not). Without
 * a UV tangent the surface's own shading normal stays. */
inline float3 tex_normal_map(float3 color, float strength, const TexPoint* tp)
{
    if (dot3(tp->tangent, tp->tangent) == 0.0f) return tp->ns;
    float3 c = 2.0f * (color - 0.5f);
    c.x *= strength;
    c.y *= strength;
    c.z = 1.0f + clamp_f(strength, 0.0f, 1.0f) * (c.z - 1.0f);
    float3 n = tp->n_front, t = tp->tangent;
    float3 b = tp->sign * cross3(n, t);
    float3 m = c.x * t + c.y * b + c.z * n;
    float l2 = dot3(m, m);
    if (!(l2 > 0.0f) || !finite_f(l2)) return tp->ns;
    m *= 1.0f / sqrt(l2);
    return tp->backfacing ? -m : m;
}

/* Color Ramp: t among the stops of image-table entry img (textures.py _ramp: colours in its first row, positions
 * in the second), clamped to the first and last; interp: TEXRAMP_* */
inline float4 tex_color_ramp(const __global TexImage* images, const __global float4* texels, int img, int interp,
                             float t)
{
    TexImage im = images[img];
    const __global float4* col = texels + im.offset;
    const __global float4* pos = col + im.width;
    int n = im.width;
    if (!(t > pos[0].x)) return col[0];
    if (t >= pos[n - 1].x) return col[n - 1];
    int k = 0;
    while (k + 2 < n && t >= pos[k + 1].x) ++k;  /* pos[k] <= t < pos[k + 1] */
    if (interp == TEXRAMP_CONSTANT) return col[k];
    float f = (t - pos[k].x) / (pos[k + 1].x - pos[k].x);
    if (interp == TEXRAMP_EASE) f = f * f * (3.0f - 2.0f * f);
    return col[k] + f * (col[k + 1] - col[k]);
}

/* one channel of RGB Curves: x looked up in column ch of the n-row table (rows evenly over [lo, hi]), linearly
 * between rows; past either end the end rows' slope goes on (extrapolate) or the end row holds */
inline float tex_curve(const __global float4* rows, int n, int ch, float lo, float hi, int extrapolate, float x)
{
    float s = (x - lo) / (hi - lo) * (float)(n - 1);
    if (!(s == s)) s = 0.0f; /* NaN: the first row, not an index out of the table */
    int k = s <= 0.0f ? 0 : (s >= (float)(n - 1) ? n - 2 : (int)s);
    if (!extrapolate) s = clamp_f(s, 0.0f, (float)(n - 1));
    float y0 = ch == 0 ? rows[k].x : (ch == 1 ? rows[k].y : rows[k].z);
    float y1 = ch == 0 ? rows[k + 1].x : (ch == 1 ? rows[k + 1].y : rows[k + 1].z);
    return y0 + (s - (float)k) * (y1 - y0);
}

/* RGB Curves: each channel of c through its column of the table (image-table entry img), blended with c by f */
inline float3 tex_rgb_curves(const __global TexImage* images, const __global float4* texels, const TexNode* n,
                             float3 c, float f)
{
    TexImage im = images[n->in.w];
    const __global float4* rows = texels + im.offset;
    float lo = n->p.y, hi = n->p.z;
    float3 v = (float3)(tex_curve(rows, im.width, 0, lo, hi, n->blk.y, c.x),
                        tex_curve(rows, im.width, 1, lo, hi, n->blk.y, c.y),
                        tex_curve(rows, im.width, 2, lo, hi, n->blk.y, c.z));
    return c + f * (v - c);
}

/* Attribute: colour attribute k of the hit's triangle blended by its barycentrics (0 without a block); out: the
 * colour, or as a number its alpha or the mean of r, g and b (TEXATTR_*) */
inline float4 tex_attribute(const TexPoint* tp, int k, int out)
{
    if (tp->attr_off <= 0) return (float4)(0.0f);
    const __global float4* c = tp->attrs + tp->attr_off + 3 * k;
    float4 v = tp->bary.x * c[0] + tp->bary.y * c[1] + tp->bary.z * c[2];
    if (out == TEXATTR_ALPHA) return (float4)(v.w);
    if (out == TEXATTR_FAC) return (float4)((v.x + v.y + v.z) * (1.0f / 3.0f));
    return v;
}

/* The value of node `root` at tp: its program (nodes blk.x .. root) evaluated in order into registers. */
inline float4 texture_eval(const __global TexNode* nodes, const __global TexImage* images,
                           const __global float4* texels, int root, const TexPoint* tp)
{
    float4 reg[MAX_TEX_PROGRAM];
    int first = nodes[root].blk.x;
    int last = min(root, first + MAX_TEX_PROGRAM - 1);
    for (int k = first; k <= last; ++k) {
        TexNode n = nodes[k];
        float4 a = n.in.x >= 0 ? reg[n.in.x - first] : n.a;
        float4 b = n.in.y >= 0 ? reg[n.in.y - first] : n.b;
        float f = n.in.z >= 0 ? tex_number(nodes, n.in.z, reg[n.in.z - first]) : n.p.x;
        /* a and b read as numbers (Combine Color, Math) */
        float sa = n.in.x >= 0 ? tex_number(nodes, n.in.x, a) : a.x;
        float sb = n.in.y >= 0 ? tex_number(nodes, n.in.y, b) : b.x;
        float lod;
        float4 out = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
        switch (n.op.x) {
        case TEXNODE_IMAGE: {
            float3 c = tex_coords(&n, tp, &lod);
            out = texture_image(images, texels, n.in.w, c.xy, lod, n.op.y, n.op.z);
            if (n.blk.z) out.xyz = (float3)(tex_srgb_decode(out.x), tex_srgb_decode(out.y), tex_srgb_decode(out.z));
            if (n.blk.w) out.xyz = (float3)(out.w);  /* the Alpha output */
            break;
        }
        case TEXNODE_CHECKER: {
            float3 c = tex_coords(&n, tp, &lod);
            out = tex_checker(c * n.p.x) == 1.0f ? a : b;
            break;
        }
        case TEXNODE_MIX:
            out.xyz = tex_mix(n.op.y, n.blk.y ? clamp_f(f, 0.0f, 1.0f) : f, a.xyz, b.xyz);
            if (n.blk.z) out.xyz = clamp(out.xyz, 0.0f, 1.0f);
            break;
        case TEXNODE_SEPARATE_COLOR:
            out.xyz = (float3)(tex_separate(n.op.y, n.op.z, a.xyz));
            break;
        case TEXNODE_COMBINE_COLOR:
            out.xyz = tex_combine(n.op.y, (float3)(sa, sb, f));
            break;
        case TEXNODE_MATH: {
            float v = tex_math(n.op.y, sa, sb, f);
            out.xyz = (float3)(n.blk.y ? clamp_f(v, 0.0f, 1.0f) : v);
            break;
        }
        case TEXNODE_VECTOR_MATH:
            out.xyz = tex_vector_math(n.op.y, a.xyz, b.xyz, f);
            break;
        case TEXNODE_INVERT:
            out.xyz = a.xyz + f * (1.0f - 2.0f * a.xyz);
            break;
        case TEXNODE_HSV:
            out.xyz = tex_hsv_adjust(a.xyz, b.xyz, f);
            break;
        case TEXNODE_COLOR_RAMP:
            out = tex_color_ramp(images, texels, n.in.w, n.op.y, f);
            if (n.blk.w) out.xyz = (float3)(out.w);
            break;
        case TEXNODE_ATTRIBUTE:
            out = tex_attribute(tp, n.op.y, n.op.z);
            break;
        case TEXNODE_RGB_CURVES:
            out.xyz = tex_rgb_curves(images, texels, &n, a.xyz, f);
            break;
        case TEXNODE_NORMAL_MAP:
            out.xyz = tex_normal_map(a.xyz, n.p.x, tp);
            break;
        default:
            break;
        }
        reg[k - first] = out;
    }
    return reg[last - first];
}

#endif
