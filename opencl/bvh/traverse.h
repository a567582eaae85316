/* Ray traversal of the 4-wide BVH built by python/restircl/bvh/build.py (node layout: BVHNode in types.h); the
 * box and triangle tests are in bvh/intersect.h.
 *
 * trace_closest / trace_any take a ray o + t d, 0 < t < tmax (d need not be unit length; t is in units of d).
 * A ray with a NaN/Inf origin or direction, a zero direction, or tmax NaN or <= 0 misses everything.
 *
 * Self-intersection: offset_ray_origin moves a surface point along the geometric normal by an amount that
 * scales with the magnitude of its coordinates (Waechter and Binder, Ray Tracing Gems ch. 6).
 *
 * Traversal: one ray per work-item, scalar control flow; the four children's boxes of a node are tested with
 * float4 operations; leaves are intersected as soon as their box is hit; the inner children that are hit are
 * visited nearest first (closest hit) or in slot order (any hit), the others wait on a small fixed stack.
 *
 * Leaves: with BVH_TRI4 (the host's bvh_packets.ENABLED) a leaf of up to 4 triangles is one packet of lane-wise
 * coordinates appended to the Tri array, tested in one pass of float4 operations (bvh_tri4) with no branch per
 * triangle; the leaf slot's child is ~(packet's first Tri slot) and its count the leaf's first triangle. Without
 * it the leaf's triangles tris[~child .. ~child + count - 1] are tested one by one (bvh_triangle). Both give the
 * same hits bit for bit on the same tree (tests/bvh/test_packets.py). */
#ifndef RESTIRCL_BVH_H
#define RESTIRCL_BVH_H

typedef struct {
    float t;     /* ray parameter of the hit; INFINITY for a miss */
    int prim;    /* index into the leaf-ordered Tri array; -1: miss */
    float u;     /* barycentric weight of v1 (hit point = v0 + u * e1 + v * e2) */
    float v;     /* barycentric weight of v2 */
#ifdef HAS_TRANSPARENCY
    int passed;  /* the transparent surfaces the ray passed before this hit (bvh/transparent.h trace_through) */
#endif
} Hit;

#ifndef BVH_STACK_SIZE
#define BVH_STACK_SIZE 96  /* up to 3 entries per level; the builder keeps the tree within 30 levels */
#endif

#include "bvh/intersect.h"

/* lanes of a vector by a run-time index (PoCL does not inline vstore4) */
typedef union { int4 v; int a[4]; } BvhInt4;
typedef union { float4 v; float a[4]; } BvhFloat4;

/* index of the lowest set bit of a 4-bit mask m != 0 (OpenCL 1.2 has no ctz) */
#define BVH_CTZ4(m) ((0x12131210 >> (2 * (m))) & 3)

#ifdef BVH_TRI4
/* The packet at tris + rec of the leaf whose first triangle is `first`: keeps the nearest hit in *best / *hit
 * (among lanes at the same distance the lowest, as bvh_leaf_closest's loop would). */
static inline void bvh_leaf4_closest(const __global Tri* tris, int rec, int first, const BvhRay* r, float* best,
                                     Hit* hit)
{
    float4 t, inv, V, W;
    int m = bvh_tri4(tris + rec, r, *best, &t, &inv, &V, &W);
    if (!m) return;
    BvhFloat4 tu, iu, vu, wu;
    tu.v = t;
    int k = BVH_CTZ4(m);
    m &= m - 1;
    while (m) {
        int j = BVH_CTZ4(m);
        m &= m - 1;
        if (tu.a[j] < tu.a[k]) k = j;
    }
    iu.v = inv;
    vu.v = V;
    wu.v = W;
    *best = tu.a[k];
    hit->prim = first + k;
    hit->u = vu.a[k] * iu.a[k];
    hit->v = wu.a[k] * iu.a[k];
}
#endif

/* Intersect the triangles tris[first .. first + count - 1]; keeps the nearest hit in *best / *hit. */
static inline void bvh_leaf_closest(const __global Tri* tris, int first, int count, const BvhRay* r, float* best,
                                    Hit* hit)
{
    for (int i = first; i < first + count; ++i) {
        float t, u, v;
        if (bvh_triangle(tris + i, r, *best, &t, &u, &v)) {
            *best = t;
            hit->prim = i;
            hit->u = u;
            hit->v = v;
        }
    }
}

Hit trace_closest(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d, float tmax)
{
    Hit hit;
    hit.t = INFINITY;
    hit.prim = -1;
    hit.u = 0.0f;
    hit.v = 0.0f;
    BvhRay r;
    if (!bvh_setup_ray(o, d, tmax, &r)) return hit;
    float best = tmax;
    int stack[BVH_STACK_SIZE];
    float stack_t[BVH_STACK_SIZE];
    int sp = 0;
    int ni = 0;
    for (;;) {
        const __global BVHNode* node = nodes + ni;
        float4 tn;
        int mask = bvh_boxes(node, &r, best, &tn);
        int4 child = node->child;
        int leaves = mask & ((child.x >> 31 & 1) | (child.y >> 31 & 2) | (child.z >> 31 & 4) | (child.w >> 31 & 8));
        BvhInt4 cu, cntu;
        BvhFloat4 tu;
        cu.v = child;
        tu.v = tn;
        int* c = cu.a;
        float* t = tu.a;
        if (leaves) {
            cntu.v = node->count;
            int* cnt = cntu.a;
            do {
                int k = BVH_CTZ4(leaves);
                leaves &= leaves - 1;
#ifdef BVH_TRI4
                if (t[k] <= best) bvh_leaf4_closest(tris, ~c[k], cnt[k], &r, &best, &hit);
#else
                if (t[k] <= best) bvh_leaf_closest(tris, ~c[k], cnt[k], &r, &best, &hit);
#endif
            } while (leaves);
            int4 in_range = tn <= (float4)(best);
            mask &= (child.x >= 0 ? in_range.x & 1 : 0) | (child.y >= 0 ? in_range.y & 2 : 0)
                  | (child.z >= 0 ? in_range.z & 4 : 0) | (child.w >= 0 ? in_range.w & 8 : 0);
        }
        if (mask) {
            int k0 = BVH_CTZ4(mask);
            mask &= mask - 1;
            if (!mask) {  /* one inner child hit */
                ni = c[k0];
                continue;
            }
            int k1 = BVH_CTZ4(mask);
            mask &= mask - 1;
            if (!mask) {  /* two: the nearer next, the other on the stack */
                int near_k = k0, far_k = k1;
                if (t[k1] < t[k0]) {
                    near_k = k1;
                    far_k = k0;
                }
                if (sp < BVH_STACK_SIZE) {
                    stack[sp] = c[far_k];
                    stack_t[sp] = t[far_k];
                    ++sp;
                }
                ni = c[near_k];
                continue;
            }
            /* three or four: sort by distance, push the farther ones (farthest first) */
            int ks[4] = {k0, k1, BVH_CTZ4(mask), 0};
            mask &= mask - 1;
            int nk = 3;
            if (mask) ks[nk++] = BVH_CTZ4(mask);
            for (int i = 1; i < nk; ++i) {  /* insertion sort, descending distance */
                int kk = ks[i];
                int j = i - 1;
                while (j >= 0 && t[ks[j]] < t[kk]) {
                    ks[j + 1] = ks[j];
                    --j;
                }
                ks[j + 1] = kk;
            }
            for (int i = 0; i < nk - 1; ++i) {
                if (sp < BVH_STACK_SIZE) {
                    stack[sp] = c[ks[i]];
                    stack_t[sp] = t[ks[i]];
                    ++sp;
                }
            }
            ni = c[ks[nk - 1]];
            continue;
        }
        /* pop the nearest pending node that is still in range */
        for (;;) {
            if (sp == 0) goto done;
            --sp;
            if (stack_t[sp] <= best) break;
        }
        ni = stack[sp];
    }
done:
    if (hit.prim >= 0) hit.t = best;
    return hit;
}

#ifdef HAS_LIGHT_LINKING
/* Does triangle i (leaf order) shadow a light whose blocker sets are `blockers` (lights/linking.h)? */
static inline bool bvh_blocks(const __global Tri* tris, int i, uint2 blockers)
{
    int set = (int)(((uint)as_int(tris[i].e2.w) >> LINK_BLOCKER_SHIFT) & LINK_SET_MASK);
    return (((set < 32) ? (blockers.x >> set) : (blockers.y >> (set - 32))) & 1u) != 0u;
}

#ifdef BVH_TRI4
/* ... any of the lanes `hits` of the leaf whose first triangle is `first` */
static inline bool bvh_blocks4(const __global Tri* tris, int first, int hits, uint2 blockers)
{
    while (hits) {
        int k = BVH_CTZ4(hits);
        hits &= hits - 1;
        if (bvh_blocks(tris, first + k, blockers)) return true;
    }
    return false;
}
#endif
#endif

/* Is anything on the ray? With light linking only triangles of the blocker sets `blockers` count (a shadow ray of a
 * light with linked shadows passes through the others); without it every triangle does and blockers is unused. */
bool trace_any_of(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d, float tmax,
                  uint2 blockers)
{
#ifndef HAS_LIGHT_LINKING
    (void)blockers;
#endif
    BvhRay r;
    if (!bvh_setup_ray(o, d, tmax, &r)) return false;
    int stack[BVH_STACK_SIZE];
    int sp = 0;
    int ni = 0;
    for (;;) {
        const __global BVHNode* node = nodes + ni;
        float4 tn;
        int mask = bvh_boxes(node, &r, tmax, &tn);
        int4 child = node->child;
        int leaves = mask & ((child.x >> 31 & 1) | (child.y >> 31 & 2) | (child.z >> 31 & 4) | (child.w >> 31 & 8));
        BvhInt4 cu;
        cu.v = child;
        int* c = cu.a;
        if (leaves) {
            BvhInt4 cntu;
            cntu.v = node->count;
            int* cnt = cntu.a;
            do {
                int k = BVH_CTZ4(leaves);
                leaves &= leaves - 1;
#ifdef BVH_TRI4
                float4 t4, inv4, v4, w4;
                int hits = bvh_tri4(tris + ~c[k], &r, tmax, &t4, &inv4, &v4, &w4);
#ifdef HAS_LIGHT_LINKING
                if (hits && bvh_blocks4(tris, cnt[k], hits, blockers)) return true;
#else
                if (hits) return true;
#endif
#else
                int first = ~c[k];
                for (int i = first; i < first + cnt[k]; ++i) {
                    float t, u, v;
#ifdef HAS_LIGHT_LINKING
                    if (bvh_triangle(tris + i, &r, tmax, &t, &u, &v) && bvh_blocks(tris, i, blockers)) return true;
#else
                    if (bvh_triangle(tris + i, &r, tmax, &t, &u, &v)) return true;
#endif
                }
#endif
            } while (leaves);
            mask &= (child.x >= 0 ? 1 : 0) | (child.y >= 0 ? 2 : 0) | (child.z >= 0 ? 4 : 0) | (child.w >= 0 ? 8 : 0);
        }
        if (mask) {
            ni = c[BVH_CTZ4(mask)];
            mask &= mask - 1;
            while (mask) {
                if (sp < BVH_STACK_SIZE) stack[sp++] = c[BVH_CTZ4(mask)];
                mask &= mask - 1;
            }
            continue;
        }
        if (sp == 0) break;
        ni = stack[--sp];
    }
    return false;
}

/* Is anything on the ray (every triangle blocks)? */
bool trace_any(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d, float tmax)
{
    return trace_any_of(nodes, tris, o, d, tmax, (uint2)(0xFFFFFFFFu));
}

/* A ray origin just off the surface at p, on the side of the unit geometric normal ng (pass the normal facing
 * the side the new ray leaves to). The offset is a fixed number of float ulps of p's coordinates (far from the
 * origin) or a small absolute step near it, so it works at any scene scale and offset. */
float3 offset_ray_origin(float3 p, float3 ng)
{
    const float origin = 1.0f / 32.0f;
    const float float_scale = 1.0f / 65536.0f;
    const float int_scale = 256.0f;
    int3 of = convert_int3(int_scale * ng);
    int3 pi = as_int3(p) + select(of, -of, isless(p, (float3)(0.0f)));
    float3 p_i = as_float3(pi);
    float3 p_f = p + float_scale * ng;
    return select(p_i, p_f, isless(fabs(p), (float3)(origin)));
}

#endif
