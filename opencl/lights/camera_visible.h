/* Lights the camera sees (HAS_CAMERA_LIGHTS), as Cycles shows them with Ray Visibility > Camera on: area lights as
 * their shape, from the emitting side only; points and spots with a radius as a disk of that radius facing the
 * camera (Cycles draws the sphere so: its radiance is uniform out to the silhouette); a spot only from inside its
 * cone, masked by it; a sun with an angle as a disk of directions where the ray meets no geometry.
 *
 * Which lights is the host's decision alone (python/restircl/lights/camera_visible.py: those visible to the camera
 * whose type has a shape, SceneLightType.has_shape): the table lists them, and this header has no rule of its own
 * and no per-type code. What a ray sees of a listed light is its type's: where the ray hits it (light_hit), whether
 * that point faces the ray (light_eval) and the radiance it sends back (light_hit_radiance: a spot's is masked by its
 * cone), all in lights/<type>.h through lights/lights.h.
 *
 * The table (python/restircl/lights/camera_visible.py), float4 rows: row 0 x = the entry count (int bits); then per
 * entry 7 rows: x of the first = the light's index (int bits), then 3 rows of M_prev M_cur^-1 and 3 of
 * M_next M_cur^-1 of the light's transform (its own motion, for the motion vectors).
 *
 * A pixel that sees a light is written like a surface (position, depth, normal facing the camera, motion) with the
 * light's radiance as its emission, no albedo and prim = CAMERA_LIGHT_PRIM(light) (below -1: not shaded, but
 * reprojected and tested like a surface by TAA and ReSTIR, camera/reproject.h). */
#ifndef RESTIRCL_CAMERA_LIGHTS_H
#define RESTIRCL_CAMERA_LIGHTS_H

#include "codes.h"

#define CAMERA_LIGHT_PRIM(light) (-2 - (light))

/* The radiance the unit ray o + t d sees of light l where it meets it, at distance *dist (INFINITY for the sun),
 * with the light's normal there facing o in *nl; false where the ray misses it or sees its back. */
inline bool camera_light_radiance(const __global Light* l, float3 o, float3 d, float* dist, float3* nl, float3* Le)
{
    int type = light_type(l);
    float2 uv;
    if (!light_hit(l, type, o, d, &uv)) return false;
    LightEval e;
    /* the point of the hit and whether it faces o (one-sided shapes; a spot's cone); the normal d makes cos_x > 0 */
    if (!light_eval(l, uv.x, uv.y, o, d, &e)) return false;
    *Le = light_hit_radiance(l, type, o, uv);
    *dist = e.dist;
    *nl = e.nl;
    return true;
}

inline float3 camera_light_motion(const __global float4* m, float3 p)
{
    float4 p4 = (float4)(p, 1.0f);
    return (float3)(dot(m[0], p4), dot(m[1], p4), dot(m[2], p4));
}

/* The nearest light in the table that the camera ray o + t d meets before tmax (a shape: *dist finite) and, where
 * it meets none, the radiance of the suns it sees (*sun, added to what a miss shows). The entry of the shape hit,
 * or -1. */
inline int camera_light_nearest(const __global Light* lights, const __global float4* table, float3 o, float3 d,
                                float tmax, float* dist, float3* nl, float3* Le, float3* sun)
{
    int count = as_int(table[0].x);
    int best = -1;
    *sun = (float3)(0.0f);
    *dist = tmax;
    for (int k = 0; k < count; ++k) {
        const __global Light* l = lights + as_int(table[1 + CAMERA_LIGHT_ROWS * k].x);
        float t;
        float3 n, c;
        if (!camera_light_radiance(l, o, d, &t, &n, &c)) continue;
        if (!finite_f(t)) { *sun += c; continue; }
        if (t < *dist) { *dist = t; *nl = n; *Le = c; best = k; }
    }
    return best;
}

/* Pixel i of the primary pass: if the camera ray o + t d meets a visible light before the geometry (tmax, INFINITY
 * for a miss), write its G-sample and Vector entry and return true. Otherwise the suns the ray sees, if it
 * misses the geometry, go to *sun for the miss to add. */
inline bool camera_light_pixel(const __global Light* lights, const __global float4* table,
                               const __global Camera* cam, const __global Camera* prev_cam,
                               const __global Camera* next_cam, float3 o, float3 d, float tmax,
                               __global GSample* gbuf, __global GlossySample* glossy, __global float4* vector,
                               float3* sun)
{
    float dist;
    float3 nl, Le, seen_sun;
    int k = camera_light_nearest(lights, table, o, d, tmax, &dist, &nl, &Le, &seen_sun);
    *sun = finite_f(tmax) ? (float3)(0.0f) : seen_sun;
    if (k < 0) return false;
    const __global float4* entry = table + 1 + CAMERA_LIGHT_ROWS * k;
    int light = as_int(entry[0].x);
    float3 p = o + dist * d;
    GSample g;
    g.pos = (float4)(p, camera_depth(cam, p));
    g.normal = (float4)(nl, as_float(CAMERA_LIGHT_PRIM(light)));
    g.gnormal = (float4)(nl, as_float(-1));
    g.albedo = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
    g.emission = (float4)(Le, 0.0f);
    g.motion = (float4)(0.0f, 0.0f, 1.0f, g.pos.w);
    g.layer = (float4)(0.0f);
    float4 vec = (float4)(0.0f);
#ifdef HAS_MOTION
    float3 pp = camera_light_motion(entry + 1, p), pn = camera_light_motion(entry + 4, p);
    float2 cur_px, prev_px, next_px;
    bool cur_ok = camera_project(cam, p, &cur_px);
    if (cur_ok && camera_project(prev_cam, pp, &prev_px))
        g.motion = (float4)(prev_px - cur_px, 1.0f, camera_depth(prev_cam, pp));
    else
        g.motion = (float4)(0.0f);
    vec.xy = g.motion.xy;
    if (cur_ok && camera_project(next_cam, pn, &next_px)) vec.zw = next_px - cur_px;
#else
    (void)prev_cam;
    (void)next_cam;
#endif
    *gbuf = g;
    *vector = vec;
#ifdef HAS_GLOSSY
    glossy->wo = (float4)(-d, as_float(0));  /* no lobes: not shaded */
#else
    (void)glossy;
#endif
    return true;
}

#endif
