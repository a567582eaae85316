/* Rays through transparent and alpha-masked surfaces (HAS_TRANSPARENCY: some material's coverage is below 1,
 * python/restircl/materials/alpha.py). Included right after bvh/traverse.h: in such builds every later call of
 * trace_closest and trace_any goes through the functions below, so camera, shadow and bounce rays all pass through
 * them; scenes without a transparent material compile none of it.
 *
 * Stochastic, with the coverage a as the probability: a ray meeting a surface stops there with probability a and
 * passes straight through otherwise, unchanged. A surface of coverage a is a times its material plus (1 - a) times
 * a white Transparent BSDF, so this estimates it without a weight; and it keeps one surface per ray, which the
 * G-buffer (one surface per pixel, as ReSTIR DI, TAA and the motion vectors read it) and the shadow tests of the
 * reuse (a yes or no per sample) need. Over many samples a shadow ray through surfaces of coverages a_i is
 * unblocked with probability prod(1 - a_i): the product of their transparencies, as Cycles multiplies them into
 * its shadow rays. The choice is a hash of the ray's origin and direction and the triangle, so it needs no random
 * stream: rays of other samples start elsewhere or point elsewhere (jitter, another light sample, another BSDF
 * direction), and each surface met along one ray draws its own number. A still's camera rays instead stop at every
 * surface of coverage above 0 (LAYER_STOPS) and weight it (camera/layers.h).
 *
 * Cycles' Light Paths > Max Bounces > Transparent (TRANSPARENT_MAX_BOUNCES, Settings.transparent_max_bounces)
 * bounds how many surfaces a ray passes: a camera ray that has passed that many ends at the next surface it meets,
 * black (trace_camera: Cycles ends the path there); a bounce ray takes the next surface as opaque. The bound is
 * the path's: a shadow ray from a surface that the camera ray (or the path) reached by passing b surfaces may pass
 * TRANSPARENT_MAX_BOUNCES - b more (its allowance, Surface.passed: direct/visibility.h shadow_allowance), and one
 * that would pass more is blocked, as Cycles counts its shadow rays' transparent hits against the path's. */
#ifndef RESTIRCL_BVH_TRANSPARENT_H
#define RESTIRCL_BVH_TRANSPARENT_H

/* The w of a frame's sample (the shading kernels write it): 1 where the camera ray stopped at a surface or a light,
 * 0 where it went on to the world. A still render's mean of it is the pixel's coverage, Film > Transparent's alpha:
 * seen through a surface of coverage a to the world, a. Without transparent surfaces it stays 1 (the film's alpha
 * then comes from the depth). */
#ifdef HAS_TRANSPARENCY
#define film_coverage(g) ((g).pos.w < INFINITY ? 1.0f : 0.0f)
#else
#define film_coverage(g) 1.0f
#endif

#include "bvh/thin_wall_shadow.h"  /* Shadow: a shadow ray's transmittance, float or, past smooth thin walls, rgb */

#ifdef HAS_TRANSPARENCY

#include "surface/alpha.h"

#ifndef TRANSPARENT_MAX_BOUNCES
#define TRANSPARENT_MAX_BOUNCES 8
#endif

/* hit.prim of a camera ray that ended at the transparent bound (trace_camera) */
#define TRANSPARENT_ENDED (-2)

/* uniform in [0, 1) for the k-th surface (prim) met by the ray o + t d */
inline float transparent_uniform(float3 o, float3 d, int prim, int k)
{
    uint h = pcg_hash(as_uint(o.x) ^ pcg_hash(as_uint(o.y) ^ pcg_hash(as_uint(o.z) ^ pcg_hash((uint)prim + (uint)k))));
    h = pcg_hash(h ^ as_uint(d.x)) ^ pcg_hash(as_uint(d.y) ^ pcg_hash(as_uint(d.z)));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Does the ray stop at hit h, the k-th surface it met? u0 in [0, 1): the number of the first surface (k = 0), or
 * negative to hash it as the others'; LAYER_STOPS: every surface whose coverage is above 0 stops it (the weighted
 * layers of a still, camera/layers.h) */
#define LAYER_STOPS 2.0f
inline bool transparent_stops(const __global Tri* tris, Hit h, float3 o, float3 d, int k, float u0)
{
    float a = surface_coverage(tris, h.prim, h.u, h.v);
    if (u0 == LAYER_STOPS) return a > 0.0f;
    /* a camera ray's surfaces behind the first salt their hash with its number: without pixel jitter the ray and
     * its segments are the same in every frame, and an unsalted hash would make the same choice in all of them */
    int salt = u0 >= 0.0f ? (int)(as_uint(u0) & 0x7fffffffu) : 0;
    float u = k == 0 && u0 >= 0.0f ? u0 : transparent_uniform(o, d, h.prim, k ^ salt);
    return a >= 1.0f || u < a;
}

/* The origin that continues a ray past hit h at t along d: just off the triangle on the far side. */
inline float3 transparent_continue(const __global Tri* tris, Hit h, float3 o, float3 d)
{
    Tri t = tris[h.prim];
    float3 ng = cross3(t.e1.xyz, t.e2.xyz);
    if (dot3(ng, d) < 0.0f) ng = -ng;
    return offset_ray_origin(o + h.t * d, norm3(ng));
}

/* The first surface the ray stops at (t in units of d from o), or a miss; h.passed: the surfaces it passed. A ray
 * that has passed k surfaces meets the next one: with k >= bound (shadow: the pass would exceed the bound) or, for
 * a camera ray, k >= bound and k > 0 (Cycles counts passes: it ends the path at the surface after the pass that
 * reached the bound), that surface is returned and *ended set. */
inline Hit trace_through(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d, float tmax,
                         bool camera, int bound, float u0, bool* ended)
{
    float3 oo = o;
    float travelled = 0.0f;
    *ended = false;
    for (int k = 0;; ++k) {
        Hit h = trace_closest(nodes, tris, oo, d, tmax - travelled);
        h.passed = k;
        if (h.prim < 0) return h;
        bool at_bound = camera ? k > 0 && k >= bound : k >= bound;
        if (at_bound || transparent_stops(tris, h, oo, d, k, u0)) {
            *ended = at_bound;
            if (k > 0) h.t = dot3(oo + h.t * d - o, d) / dot3(d, d);
            return h;
        }
        travelled += h.t;
        oo = transparent_continue(tris, h, oo, d);
        if (!(travelled < tmax)) {
            h.prim = -1;
            h.t = INFINITY;
            h.passed = k + 1;
            return h;
        }
    }
}

/* A bounce or BSDF ray: the first surface it stops at; the surface where it ends (Cycles ends the path there)
 * is taken as opaque: its light counts and the path goes on. */
inline Hit trace_closest_transparent(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d,
                                     float tmax)
{
    bool ended;
    return trace_through(nodes, tris, o, d, tmax, true, TRANSPARENT_MAX_BOUNCES, -1.0f, &ended);
}

/* A camera ray: as trace_closest_transparent, but a ray that reached the bound ends: prim TRANSPARENT_ENDED at the
 * surface where it ended. Its choice at the first surface takes the number u0 in [0, 1) (camera/coverage_number.h:
 * stratified over the samples, so that a pixel behind a half-transparent pane sees pane and floor in even turns, as
 * Cycles' stratified numbers make it; pure coins left 2-4x its error on the alpha scene); the surfaces behind draw
 * hashed numbers (a second number of the same sequence would be tied to the first). */
inline Hit trace_camera(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d, float tmax,
                        float u0)
{
    bool ended;
    Hit h = trace_through(nodes, tris, o, d, tmax, true, TRANSPARENT_MAX_BOUNCES, u0, &ended);
    if (ended) h.prim = TRANSPARENT_ENDED;
    return h;
}

/* A shadow ray: blocked by a surface it stops at, or by more than `allowance` surfaces that it passes. */
inline bool trace_any_transparent(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d,
                                  float tmax, int allowance)
{
    if (!trace_any(nodes, tris, o, d, tmax)) return false;  /* nothing on the way: the common case, cheaply */
    bool ended;
    Hit h = trace_through(nodes, tris, o, d, tmax, false, allowance, -1.0f, &ended);
    return h.prim >= 0;
}

/* The fraction of the light along a shadow ray that passes: the product of 1 - a over the surfaces it meets, 0 at
 * an opaque one or past `allowance` surfaces (Cycles' transparent shadows, deterministic: direct/visibility.h
 * transmittance).
 * With light linking only the light's blockers (bvh/traverse.h bvh_blocks) shadow it: the others are passed as if
 * fully transparent. */
inline Shadow trace_transmittance(const __global BVHNode* nodes, const __global Tri* tris, float3 o, float3 d,
                                  float tmax, uint2 blockers, int allowance)
{
#ifdef TEST_OPAQUE_SHADOWS
    (void)allowance;
    return trace_any_of(nodes, tris, o, d, tmax, blockers) ? 0.0f : 1.0f;
#else
    if (!trace_any_of(nodes, tris, o, d, tmax, blockers)) return 1.0f;
    float3 oo = o;
    float travelled = 0.0f;
    Shadow through = 1.0f;
    for (int k = 0; k <= allowance; ++k) {
        Hit h = trace_closest(nodes, tris, oo, d, tmax - travelled);
        if (h.prim < 0) return through;
#ifdef HAS_LIGHT_LINKING
        if (bvh_blocks(tris, h.prim, blockers)) {
#endif
        if (k == allowance) return 0.0f;
        through *= shadow_pass(tris, h, d);  /* 1 - coverage; a smooth thin wall's colour (bvh/thin_wall_shadow.h) */
#ifdef HAS_LIGHT_LINKING
        }
#endif
        if (!shadow_any(through)) return 0.0f;
        travelled += h.t;
        if (!(travelled < tmax)) return through;
        oo = transparent_continue(tris, h, oo, d);
    }
    return 0.0f;
#endif
}

#define trace_closest(nodes, tris, o, d, tmax) trace_closest_transparent(nodes, tris, o, d, tmax)
#ifndef TEST_OPAQUE_SHADOWS  /* negative control of the tests only (tests/bias_controls.py): shadows ignore alpha */
#define trace_any(nodes, tris, o, d, tmax) trace_any_transparent(nodes, tris, o, d, tmax, TRANSPARENT_MAX_BOUNCES)
#endif

#endif

#endif
