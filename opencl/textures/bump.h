/* Blender's Bump node (materials/textures.py Bump): the shading normal tilted by the surface gradient of a height,
 * from the height at the point and at two neighbours on its triangle, BUMP_STEP along each edge from the first
 * corner (Cycles steps along the ray differentials; the gradient is the same where the height is smooth over both
 * steps), with the gradient written as Mikkelsen's surface gradient of the two steps: a normal of
 * |det| N - distance sign(det) (dh_1 R_1 + dh_2 R_2), R_1 = dp_2 x N, R_2 = N x dp_1, det = dp_1 . R_1, blended
 * with N by Strength. */
#ifndef RESTIRCL_TEXTURE_BUMP_H
#define RESTIRCL_TEXTURE_BUMP_H

#include "textures/nodes.h"

#define BUMP_STEP 1e-3f

/* tp moved on its triangle to barycentric weights b: its UV, object and generated coordinates and attributes */
inline TexPoint tex_point_moved(const TexPoint* tp, float3 b)
{
    TexPoint q = *tp;
    TriAttr a = ((const __global TriAttr*)tp->attrs)[tp->prim];
    q.bary = b;
    q.uv = (float3)(dot3(b, a.u.xyz), dot3(b, a.v.xyz), 0.0f);
    q.obj = a.o0.xyz + b.y * a.oe1.xyz + b.z * a.oe2.xyz;
    q.gen = tp->gen + (q.obj - tp->obj) * tp->gen_scale;
    return q;
}

/* The normal the program ending at node root gives at tp: a Bump's, or what the program evaluates to (a Normal
 * Map's normal). */
inline float3 texture_normal(const __global TexNode* nodes, const __global TexImage* images,
                             const __global float4* texels, int root, const TexPoint* tp)
{
    TexNode n = nodes[root];
    if (n.op.x != TEXNODE_BUMP) return texture_eval(nodes, images, texels, root, tp).xyz;
    float3 N = tp->ns;
    if (n.in.x < 0 || tp->prim < 0) return N;  /* a constant height, or no triangle to step on */
    float h0 = tex_number(nodes, n.in.x, texture_eval(nodes, images, texels, n.in.x, tp));
    TexPoint q1 = tex_point_moved(tp, tp->bary + (float3)(-BUMP_STEP, BUMP_STEP, 0.0f));
    TexPoint q2 = tex_point_moved(tp, tp->bary + (float3)(-BUMP_STEP, 0.0f, BUMP_STEP));
    float dh1 = tex_number(nodes, n.in.x, texture_eval(nodes, images, texels, n.in.x, &q1)) - h0;
    float dh2 = tex_number(nodes, n.in.x, texture_eval(nodes, images, texels, n.in.x, &q2)) - h0;
    float3 dp1 = BUMP_STEP * tp->e1, dp2 = BUMP_STEP * tp->e2;
    float3 r1 = cross3(dp2, N), r2 = cross3(N, dp1);
    float det = dot3(dp1, r1);
    float3 m = fabs(det) * N - n.p.z * (det < 0.0f ? -1.0f : 1.0f) * (dh1 * r1 + dh2 * r2);
    float l2 = dot3(m, m);
    if (!(l2 > 0.0f) || !finite_f(l2)) return N;
    float s = fmax_f(n.p.x, 0.0f);
    m = s * (m * (1.0f / sqrt(l2))) + (1.0f - s) * N;
    l2 = dot3(m, m);
    return (l2 > 0.0f && finite_f(l2)) ? m * (1.0f / sqrt(l2)) : N;
}

#endif
