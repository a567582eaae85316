/* Ray traversal of the child-pair BVH2 built by python/restircl/bvh.py (node layout: BVHNode in types.h).
 *
 * trace_closest / trace_any take a ray o + t d, 0 < t < tmax (d need not be unit length; t is in units of d).
 * A ray with a NaN/Inf origin or direction, a zero direction, or tmax NaN or <= 0 misses everything.
 *
 * Robustness:
 * - Triangle test: Woop, Benthin and Wald's watertight test (JCGT 2013): the vertices are sheared into a space
 *   where the ray runs along +z through (0, 0); the 2D edge functions are evaluated without FMA contraction, so
 *   the two triangles sharing an edge compute exactly opposite values for it and a ray cannot slip between
 *   them. Both winding orders are accepted (all edge functions >= 0 or all <= 0).
 *   make_tris stores e1, e2 such that v0 + e1, v0 + e2 give back the float32 vertices exactly, so a vertex
 *   shared by several triangles has one value in all of them.
 * - Box test: the slab distances are computed as (b - o) * (1/d) and the far distance is enlarged by a few ulps
 *   (pbrt's 1 + 2 gamma(3) argument), so a box is never missed by rounding, at any scene offset.
 * - Self-intersection: offset_ray_origin moves a surface point along the geometric normal by an amount that
 *   scales with the magnitude of its coordinates (Waechter and Binder, Ray Tracing Gems ch. 6).
 *
 * Traversal: one ray per work-item, scalar control flow; both children's boxes are tested with float4
 * operations (per axis: left min, right min, left max, right max), nearer child first, small fixed stack;
 * leaves are intersected as soon as their box is hit. */
#ifndef RESTIRCL_BVH_H
#define RESTIRCL_BVH_H

typedef struct {
    float t;     /* ray parameter of the hit; INFINITY for a miss */
    int prim;    /* index into the leaf-ordered Tri array; -1: miss */
    float u;     /* barycentric weight of v1 (hit point = v0 + u * e1 + v * e2) */
    float v;     /* barycentric weight of v2 */
} Hit;

#ifndef BVH_STACK_SIZE
#define BVH_STACK_SIZE 64  /* the builder keeps the tree depth below this */
#endif

#ifndef BVH_EDGE_TOL
#define BVH_EDGE_TOL 2e-6f  /* relative tolerance of the edge test (barycentric units) */
#endif

/* 1 + 8 ulp: enlargement of the far slab distance that covers the rounding of (b - o) * (1 / d). */
#define BVH_FAR_SCALE 1.00000048f

/* max(a, b) that returns b when a is NaN (b must not be NaN); one maxps on x86 */
#define BVH_MAX4(a, b) ((a) > (b) ? (a) : (b))

/* Ray data prepared once per ray. */
typedef struct {
    float4 o4;     /* origin */
    float4 ox, oy, oz;   /* origin components, broadcast */
    float4 ix, iy, iz;   /* (1/d, 1/d, -1/d * far scale, -1/d * far scale) per axis; +-inf for d = 0 */
    int sx, sy, sz;      /* 1: the direction component is negative (the near plane is the max plane) */
    float4 shx, shy, shz; /* shear rows: vertex p -> (dot(shx, p - o), dot(shy, p - o), dot(shz, p - o)) */
} BvhRay;

static inline bool bvh_setup_ray(float3 o, float3 d, float tmax, BvhRay* r)
{
    if (!(all(isfinite(o)) && all(isfinite(d)) && tmax > 0.0f)) return false;  /* tmax NaN: false */
    float3 ad = fabs(d);
    if (!(ad.x > 0.0f || ad.y > 0.0f || ad.z > 0.0f)) return false;
    /* 1/d: a zero component gives +-inf; a box plane through the origin then gives 0 * inf = NaN in that lane,
     * which the max chain of bvh_boxes ignores (the ray runs inside the slab: no limit from that axis). */
    float3 inv = 1.0f / d;
    r->o4 = (float4)(o, 0.0f);
    r->ox = (float4)(o.x);
    r->oy = (float4)(o.y);
    r->oz = (float4)(o.z);
    r->ix = (float4)(inv.x, inv.x, -inv.x * BVH_FAR_SCALE, -inv.x * BVH_FAR_SCALE);
    r->iy = (float4)(inv.y, inv.y, -inv.y * BVH_FAR_SCALE, -inv.y * BVH_FAR_SCALE);
    r->iz = (float4)(inv.z, inv.z, -inv.z * BVH_FAR_SCALE, -inv.z * BVH_FAR_SCALE);
    r->sx = inv.x < 0.0f;
    r->sy = inv.y < 0.0f;
    r->sz = inv.z < 0.0f;
    /* Shear: kz = the dominant axis of d, (kx, ky) the other two. */
    float4 shx, shy, shz;
    if (ad.x >= ad.y && ad.x >= ad.z) {        /* kz = x, kx = y, ky = z */
        float iz = 1.0f / d.x;
        shx = (float4)(-d.y * iz, 1.0f, 0.0f, 0.0f);
        shy = (float4)(-d.z * iz, 0.0f, 1.0f, 0.0f);
        shz = (float4)(iz, 0.0f, 0.0f, 0.0f);
    } else if (ad.y >= ad.z) {                  /* kz = y, kx = z, ky = x */
        float iz = 1.0f / d.y;
        shx = (float4)(0.0f, -d.z * iz, 1.0f, 0.0f);
        shy = (float4)(1.0f, -d.x * iz, 0.0f, 0.0f);
        shz = (float4)(0.0f, iz, 0.0f, 0.0f);
    } else {                                    /* kz = z, kx = x, ky = y */
        float iz = 1.0f / d.z;
        shx = (float4)(1.0f, 0.0f, -d.x * iz, 0.0f);
        shy = (float4)(0.0f, 1.0f, -d.y * iz, 0.0f);
        shz = (float4)(0.0f, 0.0f, iz, 0.0f);
    }
    r->shx = shx;
    r->shy = shy;
    r->shz = shz;
    return true;
}

/* Both children's slab test. clip = (0, 0, -tmax, -tmax). Returns the entry distances in .xy and a hit mask:
 * bit 0 left, bit 1 right. */
static inline int bvh_boxes(const __global BVHNode* node, const BvhRay* r, float4 clip, float2* tnear)
{
    float4 bx = node->bx, by = node->by, bz = node->bz;
    bx = r->sx ? bx.zwxy : bx;
    by = r->sy ? by.zwxy : by;
    bz = r->sz ? bz.zwxy : bz;
    /* lanes: near left, near right, -far left, -far right */
    float4 tx = (bx - r->ox) * r->ix;
    float4 ty = (by - r->oy) * r->iy;
    float4 tz = (bz - r->oz) * r->iz;
    float4 t = BVH_MAX4(tx, BVH_MAX4(ty, BVH_MAX4(tz, clip)));  /* NaN lanes of tx, ty, tz drop out */
    *tnear = t.xy;
    int2 h = t.xy <= -t.zw;
    return (h.x & 1) | (h.y & 2);
}

/* Watertight test of one triangle; on a hit with 0 < t < tmax, writes t and the barycentrics of v1, v2. */
static inline bool bvh_triangle(const __global Tri* tri, const BvhRay* r, float tmax, float* t_out, float* u_out,
                                float* v_out)
{
    float4 p0 = tri->v0, e1 = tri->e1, e2 = tri->e2;
    float4 a = (float4)(p0.xyz, 0.0f) - r->o4;
    float4 b = (float4)(p0.xyz + e1.xyz, 0.0f) - r->o4;
    float4 c = (float4)(p0.xyz + e2.xyz, 0.0f) - r->o4;
    /* x, y, z of the three sheared vertices, one vertex per lane */
    float4 X = (float4)(a.x, b.x, c.x, 0.0f);
    float4 Y = (float4)(a.y, b.y, c.y, 0.0f);
    float4 Z = (float4)(a.z, b.z, c.z, 0.0f);
    float4 px = X * r->shx.x + Y * r->shx.y + Z * r->shx.z;
    float4 py = X * r->shy.x + Y * r->shy.y + Z * r->shy.z;
    float4 pz = X * r->shz.x + Y * r->shz.y + Z * r->shz.z;
    float4 e;
    {
#pragma OPENCL FP_CONTRACT OFF
        /* e.x = U (edge b-c, weight of a), e.y = V (edge c-a, weight of b), e.z = W (edge a-b, weight of c) */
        e = px.zxyw * py.yzxw - py.zxyw * px.yzxw;
    }
    /* Accept edge functions down to -BVH_EDGE_TOL of their sum: this closes the gaps left where v0 + e1 cannot
     * reproduce a float32 vertex exactly (a difference of coordinates of unlike magnitude is rounded), at
     * most one float32 step of the triangle's coordinates. */
    float4 ae = as_float4(as_uint4(e) & (uint4)(0x7fffffffu));  /* |e| (PoCL does not inline fabs here) */
    float tol = BVH_EDGE_TOL * (ae.x + ae.y + ae.z);
    int4 below = e < (float4)(-tol), above = e > (float4)(tol);
    if ((below.x | below.y | below.z) & (above.x | above.y | above.z)) return false;
    float det = e.x + e.y + e.z;
    if (det == 0.0f) return false;
    float T = e.x * pz.x + e.y * pz.y + e.z * pz.z;
    float inv = 1.0f / det;
    float t = T * inv;
    if (!(t > 0.0f && t < tmax)) return false;
    *t_out = t;
    *u_out = e.y * inv;
    *v_out = e.z * inv;
    return true;
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
    float4 clip = (float4)(0.0f, 0.0f, -best, -best);
    int stack[BVH_STACK_SIZE];
    float stack_t[BVH_STACK_SIZE];
    int sp = 0;
    int ni = 0;
    for (;;) {
        const __global BVHNode* node = nodes + ni;
        float2 tn;
        int mask = bvh_boxes(node, &r, clip, &tn);
        int4 meta = node->meta;
        /* leaves first: their hits shorten the ray before the inner children are ordered */
        if ((mask & 1) && meta.x < 0) {
            int first = ~meta.x, end = ~meta.x + meta.z;
            for (int i = first; i < end; ++i) {
                float t, u, v;
                if (bvh_triangle(tris + i, &r, best, &t, &u, &v)) {
                    best = t;
                    hit.prim = i;
                    hit.u = u;
                    hit.v = v;
                }
            }
            clip.zw = (float2)(-best);
            mask &= ~1;
        }
        if ((mask & 2) && meta.y < 0) {
            if (tn.y <= best) {
                int first = ~meta.y, end = ~meta.y + meta.w;
                for (int i = first; i < end; ++i) {
                    float t, u, v;
                    if (bvh_triangle(tris + i, &r, best, &t, &u, &v)) {
                        best = t;
                        hit.prim = i;
                        hit.u = u;
                        hit.v = v;
                    }
                }
                clip.zw = (float2)(-best);
            }
            mask &= ~2;
        }
        if (mask == 3) {
            int near_c = meta.x, far_c = meta.y;
            float far_t = tn.y;
            if (tn.y < tn.x) {
                near_c = meta.y;
                far_c = meta.x;
                far_t = tn.x;
            }
            if (sp < BVH_STACK_SIZE) {
                stack[sp] = far_c;
                stack_t[sp] = far_t;
                ++sp;
            }
            ni = near_c;
            continue;
        }
        if (mask == 1 && tn.x <= best) {
            ni = meta.x;
            continue;
        }
        if (mask == 2 && tn.y <= best) {
            ni = meta.y;
            continue;
        }
        /* pop the nearest pending node that is still in range */
        ni = -1;
        while (sp > 0) {
            --sp;
            if (stack_t[sp] <= best) {
                ni = stack[sp];
                break;
            }
        }
        if (ni < 0) break;
    }
    if (hit.prim >= 0) hit.t = best;
    return hit;
}

bool trace_any(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d, float tmax)
{
    BvhRay r;
    if (!bvh_setup_ray(o, d, tmax, &r)) return false;
    float4 clip = (float4)(0.0f, 0.0f, -tmax, -tmax);
    int stack[BVH_STACK_SIZE];
    int sp = 0;
    int ni = 0;
    for (;;) {
        const __global BVHNode* node = nodes + ni;
        float2 tn;
        int mask = bvh_boxes(node, &r, clip, &tn);
        int4 meta = node->meta;
        if ((mask & 1) && meta.x < 0) {
            int first = ~meta.x, end = ~meta.x + meta.z;
            for (int i = first; i < end; ++i) {
                float t, u, v;
                if (bvh_triangle(tris + i, &r, tmax, &t, &u, &v)) return true;
            }
            mask &= ~1;
        }
        if ((mask & 2) && meta.y < 0) {
            int first = ~meta.y, end = ~meta.y + meta.w;
            for (int i = first; i < end; ++i) {
                float t, u, v;
                if (bvh_triangle(tris + i, &r, tmax, &t, &u, &v)) return true;
            }
            mask &= ~2;
        }
        if (mask == 3) {
            int near_c = meta.x, far_c = meta.y;
            if (tn.y < tn.x) {
                near_c = meta.y;
                far_c = meta.x;
            }
            if (sp < BVH_STACK_SIZE) stack[sp++] = far_c;
            ni = near_c;
            continue;
        }
        if (mask) {
            ni = (mask & 1) ? meta.x : meta.y;
            continue;
        }
        if (sp == 0) break;
        ni = stack[--sp];
    }
    return false;
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
