/* BSDF rays that find lights through smooth thin walls (HAS_THIN_SHADOW, bvh/thin_wall_shadow.h). Cycles gives such
 * a wall a Transparent BSDF for every ray but the camera's: a BSDF ray from a surface passes it as a transparent
 * bounce and the light it then meets is weighed by MIS against that surface's light samples, whose shadow rays now
 * pass the wall too. The BSDF-side searches for lights (direct/bsdf_candidates.h, path/thin_wall_emitters.h) look
 * past the wall with these; the wall's own transmission then finds nothing new (path/walk.h). */
#ifndef RESTIRCL_DIRECT_THIN_WALL_RAYS_H
#define RESTIRCL_DIRECT_THIN_WALL_RAYS_H

#ifdef HAS_THIN_SHADOW

/* The first surface past the smooth thin walls from hit h on along the ray o + t d (unit d), and in *pass what of the
 * light gets through those walls (0 where more than `allowance` of them stand in the way: the allowance of the
 * surface the ray left, direct/visibility.h shadow_allowance, as its light samples' shadow rays have it). */
inline Hit thin_wall_next(const __global BVHNode* nodes, const __global Tri* tris, Hit h, float3 o, float3 d,
                          int allowance, float3* pass)
{
    *pass = (float3)(1.0f);
    for (int k = 0; h.prim >= 0 && thin_wall_record(tris, h.prim) != 0; ++k) {
        if (k >= allowance) {
            *pass = (float3)(0.0f);
            return h;
        }
        *pass *= thin_wall_pass(tris, h.prim, h.u, h.v, d);
        o = transparent_continue(tris, h, o, d);
        h = trace_closest(nodes, tris, o, d, INFINITY);
    }
    return h;
}

/* What of light sample e, seen from the origin o of a ray in unit direction wi that met the smooth thin wall h,
 * passes that wall and whatever stands between it and the light (every object shadows it: a light with linked
 * shadows is met through its own blockers elsewhere, path/emitters.h); the wall and what follows count against
 * `allowance`, the surface's (direct/visibility.h shadow_allowance), as for its light samples' shadow rays */
inline float3 thin_wall_beyond(const __global BVHNode* nodes, const __global Tri* tris, Hit h, float3 o, float3 wi,
                               const LightEval* e, int allowance)
{
    if (allowance < 1) return (float3)(0.0f);  /* no surface may be passed: not even the wall */
    float3 pass = thin_wall_pass(tris, h.prim, h.u, h.v, wi);
    float3 o2 = transparent_continue(tris, h, o, wi);
    float3 d = e->wi;
    float tmax = INFINITY;
    if (finite_f(e->dist)) {
        float3 v = e->pos + e->eps * e->nl - o2;
        float len = len3(v);
        if (!(len > 0.0f)) return pass;
        d = v / len;
        tmax = len * 0.9999f;
    }
    return pass * trace_transmittance(nodes, tris, o2, d, tmax, (uint2)(0xFFFFFFFFu), allowance - 1);
}

#endif

#endif
