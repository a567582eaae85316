/* Ray set-up and the intersection tests of the BVH traversal (bvh/traverse.h): a node's four child boxes at once,
 * one triangle, and with BVH_TRI4 the four triangles of a leaf packet at once.
 *
 * Robustness:
 * - Triangle test: Woop, Benthin and Wald's watertight test (JCGT 2013): the vertices are sheared into a space
 *   where the ray runs along +z through (0, 0); the 2D edge functions are evaluated without FMA contraction, so
 *   the two triangles sharing an edge compute exactly opposite values for it and a ray cannot slip between
 *   them. Both winding orders are accepted (all edge functions >= 0 or all <= 0).
 *   make_tris stores e1, e2 as differences of the float32 vertices, so v0 + e1, v0 + e2 give back the vertices
 *   exactly, and a vertex shared by several triangles has one value in all of them, unless the coordinates of
 *   a triangle differ in magnitude (then the difference is rounded, by at most one float32 step of the
 *   triangle's coordinates); the edge test accepts -BVH_EDGE_TOL of the edge functions' sum to close that.
 * - Box test: the slab distances are computed as (b - o) * (1/d) and the far distance is enlarged by a few ulps
 *   (pbrt's 1 + 2 gamma(3) argument), so a box is never missed by rounding, at any scene offset. */
#ifndef RESTIRCL_BVH_INTERSECT_H
#define RESTIRCL_BVH_INTERSECT_H

#ifndef BVH_EDGE_TOL
#define BVH_EDGE_TOL 2e-6f  /* relative tolerance of the edge test (barycentric units) */
#endif

/* 1 + 8 ulp: enlargement of the far slab distance that covers the rounding of (b - o) * (1 / d). */
#define BVH_FAR_SCALE 1.00000048f

/* max / min that return b when a is NaN (b must not be NaN); one maxps / minps on x86 */
#define BVH_MAX4(a, b) ((a) > (b) ? (a) : (b))
#define BVH_MIN4(a, b) ((a) < (b) ? (a) : (b))

/* Ray data prepared once per ray. */
typedef struct {
    float4 o4;            /* origin */
    float4 ox, oy, oz;    /* origin components, broadcast */
    float4 ix, iy, iz;    /* 1/d per axis, broadcast; +-inf for d = 0 */
    float4 fx, fy, fz;    /* 1/d * BVH_FAR_SCALE: for the far planes */
    int sx, sy, sz;       /* 1: the direction component is negative (the near plane is the max plane) */
    float4 shx, shy, shz; /* shear rows: vertex p -> (dot(shx, p - o), dot(shy, p - o), dot(shz, p - o)) */
} BvhRay;

static inline bool bvh_setup_ray(float3 o, float3 d, float tmax, BvhRay* r)
{
    /* |o|, |d| by clearing the sign bits: PoCL 3.0 calls isfinite / fabs out of line here */
    float3 ao = as_float3(as_uint3(o) & (uint3)(0x7fffffffu));
    float3 ad = as_float3(as_uint3(d) & (uint3)(0x7fffffffu));
    if (!(ao.x < INFINITY && ao.y < INFINITY && ao.z < INFINITY && ad.x < INFINITY && ad.y < INFINITY
          && ad.z < INFINITY && tmax > 0.0f)) return false;  /* NaN compares false */
    if (!(ad.x > 0.0f || ad.y > 0.0f || ad.z > 0.0f)) return false;
    /* 1/d: a zero component gives +-inf; a box plane through the origin then gives 0 * inf = NaN in that lane,
     * which the max / min chains of bvh_boxes ignore (the ray runs inside the slab: no limit from that axis). */
    float3 inv = 1.0f / d;
    r->o4 = (float4)(o, 0.0f);
    r->ox = (float4)(o.x);
    r->oy = (float4)(o.y);
    r->oz = (float4)(o.z);
    r->ix = (float4)(inv.x);
    r->iy = (float4)(inv.y);
    r->iz = (float4)(inv.z);
    r->fx = (float4)(inv.x * BVH_FAR_SCALE);
    r->fy = (float4)(inv.y * BVH_FAR_SCALE);
    r->fz = (float4)(inv.z * BVH_FAR_SCALE);
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

/* Slab test of a node's four child boxes against [0, tmax]. Returns a mask of the boxes hit (bit k: slot k) and
 * their entry distances in *tnear. */
static inline int bvh_boxes(const __global BVHNode* n, const BvhRay* r, float tmax, float4* tnear)
{
    float4 minx = n->minx, maxx = n->maxx, miny = n->miny, maxy = n->maxy, minz = n->minz, maxz = n->maxz;
    float4 tnx = ((r->sx ? maxx : minx) - r->ox) * r->ix;
    float4 tfx = ((r->sx ? minx : maxx) - r->ox) * r->fx;
    float4 tny = ((r->sy ? maxy : miny) - r->oy) * r->iy;
    float4 tfy = ((r->sy ? miny : maxy) - r->oy) * r->fy;
    float4 tnz = ((r->sz ? maxz : minz) - r->oz) * r->iz;
    float4 tfz = ((r->sz ? minz : maxz) - r->oz) * r->fz;
    /* NaN lanes (0 * inf) of the per-axis distances drop out of the chains */
    float4 tn = BVH_MAX4(tnx, BVH_MAX4(tny, BVH_MAX4(tnz, (float4)(0.0f))));
    float4 tf = BVH_MIN4(tfx, BVH_MIN4(tfy, BVH_MIN4(tfz, (float4)(tmax))));
    *tnear = tn;
    int4 h = tn <= tf;
    return (h.x & 1) | (h.y & 2) | (h.z & 4) | (h.w & 8);
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

#ifdef BVH_TRI4
/* The watertight test of bvh_triangle on the four triangles of a leaf packet at p (python/restircl/bvh/packets.py),
 * one per lane, with the same operations in the same order per lane, so each lane's t, u, v are bit for bit those
 * of bvh_triangle. Returns the mask of the lanes hit with 0 < t < tmax (NaN lanes of a short leaf never are). */
static inline int bvh_tri4(const __global Tri* p, const BvhRay* r, float tmax, float4* t_out, float4* inv_out,
                           float4* v_out, float4* w_out)
{
    float4 ox = r->ox, oy = r->oy, oz = r->oz;
    float4 ax = p[0].v0 - ox, ay = p[0].e1 - oy, az = p[0].e2 - oz;
    float4 bx = (p[0].v0 + p[1].v0) - ox, by = (p[0].e1 + p[1].e1) - oy, bz = (p[0].e2 + p[1].e2) - oz;
    float4 cx = (p[0].v0 + p[2].v0) - ox, cy = (p[0].e1 + p[2].e1) - oy, cz = (p[0].e2 + p[2].e2) - oz;
    float4 s0 = r->shx, s1 = r->shy, s2 = r->shz;
    float4 pxa = ax * s0.x + ay * s0.y + az * s0.z, pya = ax * s1.x + ay * s1.y + az * s1.z;
    float4 pxb = bx * s0.x + by * s0.y + bz * s0.z, pyb = bx * s1.x + by * s1.y + bz * s1.z;
    float4 pxc = cx * s0.x + cy * s0.y + cz * s0.z, pyc = cx * s1.x + cy * s1.y + cz * s1.z;
    float4 pza = ax * s2.x + ay * s2.y + az * s2.z;
    float4 pzb = bx * s2.x + by * s2.y + bz * s2.z;
    float4 pzc = cx * s2.x + cy * s2.y + cz * s2.z;
    float4 U, V, W;
    {
#pragma OPENCL FP_CONTRACT OFF
        U = pxc * pyb - pyc * pxb;
        V = pxa * pyc - pya * pxc;
        W = pxb * pya - pyb * pxa;
    }
    uint4 sign = (uint4)(0x7fffffffu);
    float4 tol = BVH_EDGE_TOL * ((as_float4(as_uint4(U) & sign) + as_float4(as_uint4(V) & sign))
                                 + as_float4(as_uint4(W) & sign));
    float4 ntol = -tol;
    int4 below = (U < ntol) | (V < ntol) | (W < ntol);
    int4 above = (U > tol) | (V > tol) | (W > tol);
    float4 det = U + V + W;
    float4 T = U * pza + V * pzb + W * pzc;
    float4 inv = 1.0f / det;
    float4 t = T * inv;
    int4 ok = ~(below & above) & (det != (float4)(0.0f)) & (t > (float4)(0.0f)) & (t < (float4)(tmax));
    *t_out = t;
    *inv_out = inv;
    *v_out = V;
    *w_out = W;
    return (ok.x & 1) | (ok.y & 2) | (ok.z & 4) | (ok.w & 8);
}
#endif

#endif
