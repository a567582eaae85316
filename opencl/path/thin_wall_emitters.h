/* The emitters a path's BSDF ray meets beyond a smooth thin wall (HAS_THIN_SHADOW, direct/thin_wall_rays.h): counted
 * at the vertex the ray left, times what passes the wall, with that vertex's MIS weights (its NEE's shadow rays pass
 * the wall as well); the wall's own smooth transmission, which goes on along the same line, then counts none
 * (path/walk.h), so each light behind the wall is counted once. */
#ifndef RESTIRCL_PATH_THIN_WALL_EMITTERS_H
#define RESTIRCL_PATH_THIN_WALL_EMITTERS_H

#ifdef HAS_THIN_SHADOW

/* What of analytic light rec's sample uv passes to s along the ray in direction wi beyond the smooth thin wall h
 * (its term is path_emitter_term's as if the ray met nothing, times this); 0 for a light before the wall
 * (path_emitter_term has it) and one with linked shadows (it is met through whatever the ray stops at) */
inline float3 thin_wall_emitter_pass(const Surface* s, const __global BVHNode* nodes, const __global Tri* tris,
                                     const __global Light* rec, float2 uv, Hit h, float3 wi)
{
    LightEval e;
    if (!light_ray_findable(rec) || !surface_light_eval(s, rec, uv.x, uv.y, &e)) return (float3)(0.0f);
    if (finite_f(e.dist) && e.dist < h.t) return (float3)(0.0f);
    return thin_wall_beyond(nodes, tris, h, path_ray_origin(tris, s, wi), wi, &e, shadow_allowance(s));
}

#ifdef HAS_TRIANGLE_LIGHTS
/* The term of the emissive triangle that the ray from s in direction wi meets first past the smooth thin walls
 * from h on */
inline float3 thin_wall_triangle_term(const Surface* s, const __global BVHNode* nodes, const __global Tri* tris,
                                      const __global Light* lights, const __global int* tri_light,
                                      const LightPick* lp, BsdfSource hits, Hit h, float3 wi, int* light)
{
    float3 pass;
    Hit past = thin_wall_next(nodes, tris, h, path_ray_origin(tris, s, wi), wi, shadow_allowance(s), &pass);
    *light = past.prim >= 0 ? tri_light[past.prim] : -1;
    if (*light < 0 || !shadow_any(pass)) return (float3)(0.0f);
    return pass * path_emitter_term(s, nodes, tris, lights, &lights[*light], LIGHT_TRIANGLE, *light,
                                    triangle_uv(past.u, past.v), lp, hits, INFINITY, true);
}
#endif

/* Does the path, scattered at s by part `part` into wi, go on through a smooth thin wall, whose light the vertex
 * before it counted? */
inline bool thin_wall_passed(const __global Tri* tris, const Surface* s, int part, float3 wi)
{
#ifdef HAS_TRANSMISSION  /* a thin wall transmits (the upload sets both flags; without it there is no such lobe) */
    if (part < 0 || !(dot3(s->ng, wi) * dot3(s->ng, s->wo) < 0.0f)) return false;
    const Lobe* l = &s->mat.lobe[part];
    return lobe_kind(l) == LOBE_THIN_DIELECTRIC && thin_dielectric(l).smooth != 0.0f
           && thin_wall_record(tris, s->prim) != 0;
#else
    (void)tris; (void)s; (void)part; (void)wi;
    return false;
#endif
}

#endif

#endif
