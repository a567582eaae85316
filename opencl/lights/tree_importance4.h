/* light_tree_importance (lights/tree.h) of four nodes at once, node k in lane k: the same operations lane by lane, so
 * each lane is the scalar function's value (bit for bit on PoCL: tests/lights/test_tree_importance4.py), with four
 * lights' square roots and divisions in one vector instruction each. The exact pick (lights/tree_exact.h) sums the
 * importances of up to LIGHT_TREE_EXACT leaves at a point: one at a time they made its pick 1.5x a branching
 * descent's CPU on interior's surfaces (docs/measurements/error-vs-time.md, "The exact pick's CPU"). Written with bit
 * tests and ?: instead of fabs, fmax and select: PoCL calls those builtins out of line (numerics.h). */
#ifndef RESTIRCL_LIGHT_TREE_IMPORTANCE4_H
#define RESTIRCL_LIGHT_TREE_IMPORTANCE4_H

inline float4 light_tree_abs4(float4 v) { return as_float4(as_uint4(v) & (uint4)(0x7fffffffu)); }

/* fmax_f lane by lane (a NaN a gives b; b is never NaN here) */
inline float4 light_tree_max4(float4 a, float4 b) { return a >= b ? a : b; }

/* light_tree_cos_sub(...).x and .y lane by lane: cos and sin of max(0, a - b) */
inline float4 light_tree_cos_sub4(float4 cos_a, float4 sin_a, float4 cos_b, float4 sin_b, float4* sin_out)
{
    int4 none = cos_a >= cos_b;
    *sin_out = none ? (float4)(0.0f) : sin_a * cos_b - cos_a * sin_b;
    return none ? (float4)(1.0f) : cos_a * cos_b + sin_a * sin_b;
}

/* The near (*near) and far (*far) importances of nodes nd[0..3] at x, normal n (light_tree_importance's .x and .y). */
inline void light_tree_importance4(const __global LightTreeNode* nd, float3 x, float3 n, float4* near, float4* far)
{
    float4 l0 = nd[0].lo, l1 = nd[1].lo, l2 = nd[2].lo, l3 = nd[3].lo;
    float4 h0 = nd[0].hi, h1 = nd[1].hi, h2 = nd[2].hi, h3 = nd[3].hi;
    float4 a0 = nd[0].axis, a1 = nd[1].axis, a2 = nd[2].axis, a3 = nd[3].axis;
    int4 flags = (int4)(nd[0].meta.y, nd[1].meta.y, nd[2].meta.y, nd[3].meta.y);
    float4 sin_o = as_float4((int4)(nd[0].meta.z, nd[1].meta.z, nd[2].meta.z, nd[3].meta.z));
    float4 lox = (float4)(l0.x, l1.x, l2.x, l3.x), loy = (float4)(l0.y, l1.y, l2.y, l3.y);
    float4 loz = (float4)(l0.z, l1.z, l2.z, l3.z), phi = (float4)(l0.w, l1.w, l2.w, l3.w);
    float4 hix = (float4)(h0.x, h1.x, h2.x, h3.x), hiy = (float4)(h0.y, h1.y, h2.y, h3.y);
    float4 hiz = (float4)(h0.z, h1.z, h2.z, h3.z), cos_o = (float4)(h0.w, h1.w, h2.w, h3.w);
    float4 axx = (float4)(a0.x, a1.x, a2.x, a3.x), axy = (float4)(a0.y, a1.y, a2.y, a3.y);
    float4 axz = (float4)(a0.z, a1.z, a2.z, a3.z), cos_e = (float4)(a0.w, a1.w, a2.w, a3.w);
    float4 dx = x.x - 0.5f * (lox + hix), dy = x.y - 0.5f * (loy + hiy), dz = x.z - 0.5f * (loz + hiz);
    float4 ex = 0.5f * (hix - lox), ey = 0.5f * (hiy - loy), ez = 0.5f * (hiz - loz);
    float4 d2 = dx * dx + dy * dy + dz * dz, r2 = ex * ex + ey * ey + ez * ez;
    /* the orientation bound where x is outside the box's bounding sphere (lanes inside keep the power alone) */
    float4 inv_d = 1.0f / sqrt(d2);
    float4 wx = dx * inv_d, wy = dy * inv_d, wz = dz * inv_d;
    float4 sin2_b = r2 * inv_d * inv_d;
    float4 cos_b = sqrt(light_tree_max4(1.0f - sin2_b, (float4)(0.0f))), sin_b = sqrt(sin2_b);
    float4 cos_i = -(n.x * wx + n.y * wy + n.z * wz);
#if defined(HAS_TRANSMISSION) && !defined(LIGHT_TREE_ONE_SIDED)
    if (dot3(n, n) > 2.0f) cos_i = light_tree_abs4(0.5f * cos_i);
#endif
    float4 sin_i = sqrt(light_tree_max4(1.0f - cos_i * cos_i, (float4)(0.0f)));
    float4 cos_ip = cos_i >= cos_b ? (float4)(1.0f) : cos_i * cos_b + sin_i * sin_b;
    float4 cos_w = axx * wx + axy * wy + axz * wz;
    cos_w = (flags & LIGHT_TREE_TWO_SIDED) != 0 ? light_tree_abs4(cos_w) : cos_w;
    float4 sin_w = sqrt(light_tree_max4(1.0f - cos_w * cos_w, (float4)(0.0f))), wo_sin;
    float4 wo_cos = light_tree_cos_sub4(cos_w, sin_w, cos_o, sin_o, &wo_sin), unused;
    int4 cone = cos_o > -1.0f;
    float4 cos_p = cone ? light_tree_cos_sub4(wo_cos, wo_sin, cos_b, sin_b, &unused) : (float4)(1.0f);
    int4 outside = d2 > r2;
    int4 none = outside & (!(cos_ip > 0.0f) | (cone & (cos_p < cos_e)));
    float4 bound = outside ? phi * (cos_ip * cos_p) : phi;
    /* x's distance per axis from the box's near face (0 between the faces) and from its far face */
    float4 adx = light_tree_abs4(dx), ady = light_tree_abs4(dy), adz = light_tree_abs4(dz);
    float4 nx = light_tree_max4(adx - ex, (float4)(0.0f)), ny = light_tree_max4(ady - ey, (float4)(0.0f));
    float4 nz = light_tree_max4(adz - ez, (float4)(0.0f));
    float4 fx = adx + ex, fy = ady + ey, fz = adz + ez;
    float4 nn = nx * nx + ny * ny + nz * nz, ff = fx * fx + fy * fy + fz * fz;
    *near = none ? (float4)(0.0f) : bound / light_tree_max4(nn, (float4)(1e-12f));
    *far = none ? (float4)(0.0f) : bound / light_tree_max4(ff, (float4)(1e-12f));
}

#endif
