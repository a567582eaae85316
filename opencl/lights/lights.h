/* Lights: a sample y = (light, u, v) maps to a point on the light (a direction for the sun) that does not depend on
 * the shading point, so a sample can be re-evaluated at any pixel (ReSTIR reuse). Each light type has one measure:
 * area for triangle, quad, disk and sphere lights, solid angle for the sun and the environment, a delta for points
 * (radius 0) and a sun of angle 0. light_sample() draws (u, v) at a shading point with its pdf in that measure;
 * light_eval() gives the unshadowed contribution Le * cos_x * G in the same measure (the BRDF is applied by the
 * caller). This header only dispatches on the record's type: each type's code, functions and the meaning of its
 * record lanes are in lights/<type>.h. This is the one place on the device that lists the types: a new type adds its
 * include and one case per switch. Feature flags HAS_<TYPE>_LIGHTS (set by the host from the scene) compile only the
 * types a scene has. */
#ifndef RESTIRCL_LIGHTS_H
#define RESTIRCL_LIGHTS_H

#include "lights/disk.h"
#include "lights/environment.h"
#include "lights/quad.h"
#include "lights/sphere.h"
#include "lights/spot.h"
#include "lights/sun.h"
#include "lights/triangle.h"

/* Unshadowed contribution of sample (u, v) of light l at shading point x with unit normal n. */
inline bool light_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    e->eps = 0.0f;
    switch (light_type(l)) {
#ifdef HAS_TRIANGLE_LIGHTS
    case LIGHT_TRIANGLE: return triangle_eval(l, u, v, x, n, e);
#endif
#ifdef HAS_QUAD_LIGHTS
    case LIGHT_QUAD: return quad_eval(l, u, v, x, n, e);
#endif
#ifdef HAS_DISK_LIGHTS
    case LIGHT_DISK: return disk_eval(l, u, v, x, n, e);
#endif
#ifdef HAS_SPHERE_LIGHTS
    case LIGHT_SPHERE: return sphere_eval(l, u, v, x, n, e);
#endif
#ifdef HAS_SPOT_LIGHTS
    case LIGHT_SPOT: return spot_eval(l, u, v, x, n, e);
#endif
#ifdef HAS_SUN_LIGHTS
    case LIGHT_SUN: return sun_eval(l, u, v, x, n, e);
#endif
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_eval(l, u, v, x, n, e);
#endif
    default: break;  /* a type this build leaves out: the scene has none */
    }
    return false;
}

/* Draw a sample (u, v) of light l of the given type for shading point x; *pdf is the density of the sampled point
 * in the light's measure (0: nothing could be sampled). */
inline float2 light_sample_typed(const __global Light* l, int type, float3 x, float r0, float r1, float* pdf)
{
    switch (type) {
#ifdef HAS_TRIANGLE_LIGHTS
    case LIGHT_TRIANGLE: return triangle_sample(l, x, r0, r1, pdf);
#endif
#ifdef HAS_QUAD_LIGHTS
    case LIGHT_QUAD: return quad_sample(l, x, r0, r1, pdf);
#endif
#ifdef HAS_DISK_LIGHTS
    case LIGHT_DISK: return disk_sample(l, x, r0, r1, pdf);
#endif
#ifdef HAS_SPHERE_LIGHTS
    case LIGHT_SPHERE: return sphere_sample(l, x, r0, r1, pdf);
#endif
#ifdef HAS_SPOT_LIGHTS
    case LIGHT_SPOT: return spot_sample(l, x, r0, r1, pdf);
#endif
#ifdef HAS_SUN_LIGHTS
    case LIGHT_SUN: return sun_sample(l, x, r0, r1, pdf);
#endif
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_sample(l, x, r0, r1, pdf);
#endif
    default: break;
    }
    *pdf = 0.0f;
    return (float2)(r0, r1);
}

/* light_sample with the light's type read here; light_sample_typed takes it from a caller that read it earlier. */
inline float2 light_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    return light_sample_typed(l, light_type(l), x, r0, r1, pdf);
}


/* ---- what a ray meets of a light: for the BSDF-sampled candidates (direct/bsdf_candidates.h) and the lights the
 * camera sees (lights/camera_visible.h). Per type, the sample (u, v) of the point a ray hits (the inverse of the
 * type's map), the density with which light_sample produces that point, whether a ray can hit the light at all (delta
 * lights cannot: points and a sun of angle 0) and the radiance the hit point sends back along the ray. Emissive
 * triangles are geometry: the BVH finds them, and tri_light maps a hit triangle (leaf order) to its light
 * (triangle_hit is never one). */
/* The sample (u, v) of light l that the unit ray x + t wi, t > 0, hits. */
inline bool light_hit(const __global Light* l, int type, float3 x, float3 wi, float2* uv)
{
    switch (type) {
#ifdef HAS_TRIANGLE_LIGHTS
    case LIGHT_TRIANGLE: return triangle_hit(l, x, wi, uv);
#endif
#ifdef HAS_QUAD_LIGHTS
    case LIGHT_QUAD: return quad_hit(l, x, wi, uv);
#endif
#ifdef HAS_DISK_LIGHTS
    case LIGHT_DISK: return disk_hit(l, x, wi, uv);
#endif
#ifdef HAS_SPHERE_LIGHTS
    case LIGHT_SPHERE: return sphere_hit(l, x, wi, uv);
#endif
#ifdef HAS_SPOT_LIGHTS
    case LIGHT_SPOT: return spot_hit(l, x, wi, uv);
#endif
#ifdef HAS_SUN_LIGHTS
    case LIGHT_SUN: return sun_hit(l, x, wi, uv);
#endif
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_hit(l, x, wi, uv);
#endif
    default: break;  /* a type this build leaves out: the scene has none */
    }
    return false;
}

/* light_sample's density (in the light's measure) of the point e that sample (u, v) of l evaluated to at x. */
inline float light_point_pdf(const __global Light* l, int type, float3 x, const LightEval* e)
{
    switch (type) {
#ifdef HAS_TRIANGLE_LIGHTS
    case LIGHT_TRIANGLE: return triangle_point_pdf(l, x, e);
#endif
#ifdef HAS_QUAD_LIGHTS
    case LIGHT_QUAD: return quad_point_pdf(l, x, e);
#endif
#ifdef HAS_DISK_LIGHTS
    case LIGHT_DISK: return disk_point_pdf(l, x, e);
#endif
#ifdef HAS_SPHERE_LIGHTS
    case LIGHT_SPHERE: return sphere_point_pdf(l, x, e);
#endif
#ifdef HAS_SPOT_LIGHTS
    case LIGHT_SPOT: return spot_point_pdf(l, x, e);
#endif
#ifdef HAS_SUN_LIGHTS
    case LIGHT_SUN: return sun_point_pdf(l, x, e);
#endif
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_point_pdf(l, x, e);
#endif
    default: break;
    }
    return 0.0f;
}

/* Can a ray meet light `index` (of type `type`), blockers aside? Triangles when the BSDF candidates look for them
 * (triangles: 1); analytic lights when their index is below `analytic` (the BSDF candidates test that many, the
 * scene's lights coming first in the light array); then as the type says (not a delta, emits). */
inline bool light_type_hittable(const __global Light* l, int type, int index, int analytic, int triangles)
{
    if (type == LIGHT_TRIANGLE ? triangles == 0 : index >= analytic) return false;
    switch (type) {
#ifdef HAS_TRIANGLE_LIGHTS
    case LIGHT_TRIANGLE: return triangle_hittable(l);
#endif
#ifdef HAS_QUAD_LIGHTS
    case LIGHT_QUAD: return quad_hittable(l);
#endif
#ifdef HAS_DISK_LIGHTS
    case LIGHT_DISK: return disk_hittable(l);
#endif
#ifdef HAS_SPHERE_LIGHTS
    case LIGHT_SPHERE: return sphere_hittable(l);
#endif
#ifdef HAS_SPOT_LIGHTS
    case LIGHT_SPOT: return spot_hittable(l);
#endif
#ifdef HAS_SUN_LIGHTS
    case LIGHT_SUN: return sun_hittable(l);
#endif
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_hittable(l);
#endif
    default: break;
    }
    return false;
}

/* Can a BSDF ray that stops at the first surface it meets find light `index`? As light_type_hittable, but never a
 * light whose shadows are linked (lights/record.h light_ray_findable). */
inline bool light_hittable(const __global Light* l, int type, int index, int analytic, int triangles)
{
    return light_ray_findable(l) && light_type_hittable(l, type, index, analytic, triangles);
}

/* The radiance that reaches x from the point (u, v) of l that a ray from x hit (light_hit): what a camera ray sees
 * there. */
inline float3 light_hit_radiance(const __global Light* l, int type, float3 x, float2 uv)
{
    switch (type) {
#ifdef HAS_TRIANGLE_LIGHTS
    case LIGHT_TRIANGLE: return triangle_hit_radiance(l, x, uv);
#endif
#ifdef HAS_QUAD_LIGHTS
    case LIGHT_QUAD: return quad_hit_radiance(l, x, uv);
#endif
#ifdef HAS_DISK_LIGHTS
    case LIGHT_DISK: return disk_hit_radiance(l, x, uv);
#endif
#ifdef HAS_SPHERE_LIGHTS
    case LIGHT_SPHERE: return sphere_hit_radiance(l, x, uv);
#endif
#ifdef HAS_SPOT_LIGHTS
    case LIGHT_SPOT: return spot_hit_radiance(l, x, uv);
#endif
#ifdef HAS_SUN_LIGHTS
    case LIGHT_SUN: return sun_hit_radiance(l, x, uv);
#endif
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_hit_radiance(l, x, uv);
#endif
    default: break;
    }
    return (float3)(0.0f);
}

#endif
