/* What a path's BSDF ray from vertex s meets of the emitters before (or, for the world and suns, instead of) the
 * surface hit h: its emissive triangle (the BVH's hit; tri_light maps it to its light), every analytic light on the
 * ray's line closer than the hit (lights are not geometry: they do not block each other, as for shadow rays), and,
 * where the ray escapes, the world and the suns. Each adds f * Le * cos * G / p_bsdf in the light's measure times
 * its BSDF weight (path/mis.h), which with the path's throughput before this scatter is the ray's share of that
 * light: the same integrand NEE at s estimates with the complementary weight. */
#ifndef RESTIRCL_PATH_EMITTERS_H
#define RESTIRCL_PATH_EMITTERS_H

/* The BSDF-ray term of light `index` (record rec, sample uv) met from s. A light whose shadows are linked is met
 * through what does not shadow it: its term takes the transmittance of the light's own blockers between s and the
 * light (direct/visibility.h, NEE's shadow ray), whatever surface the ray stopped at. */
inline float3 path_emitter_term(const Surface* s, const __global BVHNode* nodes, const __global Tri* tris,
                                const __global Light* lights, const __global Light* rec, int type, int index,
                                float2 uv, const LightPick* lp, BsdfSource hits, float hit_t, bool escaped)
{
    LightEval e;
    if (!surface_light_eval(s, rec, uv.x, uv.y, &e) || !light_links(lights, rec, s, &e)) return (float3)(0.0f);
    const bool linked = !light_ray_findable(rec);
    /* met before the surface the ray hit, or, at infinity, only by a ray that escaped */
    if (!linked && (finite_f(e.dist) ? !(e.dist < hit_t) : !escaped)) return (float3)(0.0f);
    float p_bsdf = path_bsdf_pdf(s, rec, type, index, hits, &e);
    if (!(p_bsdf > 0.0f)) return (float3)(0.0f);
    float p_light = light_pick_pdf(lp, index, s->x, light_pick_normal(s)) * light_point_pdf(rec, type, s->x, &e);
#ifdef HAS_TRANSMISSION  /* NEE skipped s (smooth glass, path/walk.h): the BSDF ray is the only way */
    if (surface_is_singular(s)) p_light = 0.0f;
#endif
    float3 c = unshadowed_contrib(s, &e) * (path_mis_weight(p_bsdf, p_light) / p_bsdf);
    if (linked && luminance(c) > 0.0f) c *= transmittance(nodes, tris, s, &e);
    return c;
}

#include "path/thin_wall_emitters.h"  /* HAS_THIN_SHADOW: the emitters beyond a smooth thin wall */

/* The emitters the ray from s in direction wi meets before its hit h (h.prim < 0: it escaped); each light's term
 * also to *groups (film/light_groups.h). */
inline float3 path_emitters(const Surface* s, float3 wi, Hit h, const __global BVHNode* nodes,
                            const __global Tri* tris, const __global Light* lights, const __global int* tri_light,
                            const LightPick* lp, BsdfSource hits, GroupLight* groups)
{
    float3 c = (float3)(0.0f);
    bool escaped = h.prim < 0;
    float hit_t = escaped ? INFINITY : h.t;
#ifdef HAS_THIN_SHADOW  /* the ray met a smooth thin wall: the emitters beyond it count too, through it */
    const bool thin = !escaped && thin_wall_record(tris, h.prim) != 0;
#endif
    for (int l = 0; l < hits.analytic; ++l) {
        const __global Light* rec = &lights[l];
        int type = light_type(rec);
        float2 uv;
        if (path_light_hittable(rec, type, l, hits) && light_hit(rec, type, s->x, wi, &uv)) {
            float3 t = path_emitter_term(s, nodes, tris, lights, rec, type, l, uv, lp, hits, hit_t, escaped);
#ifdef HAS_THIN_SHADOW
            float3 pass = thin ? thin_wall_emitter_pass(s, nodes, tris, rec, uv, h, wi) : (float3)(0.0f);
            if (shadow_any(pass))
                t += pass * path_emitter_term(s, nodes, tris, lights, rec, type, l, uv, lp, hits, INFINITY, true);
#endif
            c += t;
            GROUP_ADD(groups, lights, rec, t);
        }
    }
#ifdef HAS_TRIANGLE_LIGHTS
    if (hits.triangles && !escaped) {
        int l = tri_light[h.prim];
        /* the triangle itself is the hit: no distance test (its own point, rounded, may lie a hair beyond h.t) */
        if (l >= 0) {
            float3 t = path_emitter_term(s, nodes, tris, lights, &lights[l], LIGHT_TRIANGLE, l,
                                         triangle_uv(h.u, h.v), lp, hits, INFINITY, true);
            c += t;
            GROUP_ADD(groups, lights, &lights[l], t);
        }
#ifdef HAS_THIN_SHADOW
        if (thin) {
            float3 t = thin_wall_triangle_term(s, nodes, tris, lights, tri_light, lp, hits, h, wi, &l);
            c += t;
            if (l >= 0) GROUP_ADD(groups, lights, &lights[l], t);
        }
#endif
    }
#else
    (void)tri_light;
#endif
    (void)groups;
    return c;
}

#endif
