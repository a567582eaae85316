/* Lights: a sample y = (light, u, v) maps to a point on the light (a direction for the sun) that does not depend on
 * the shading point, so a sample can be re-evaluated at any pixel (ReSTIR reuse). Each light type has one measure:
 * area for triangle, quad, disk and sphere lights, solid angle for the sun and the environment, a delta for points (radius 0) and a
 * sun of angle 0. light_sample() draws (u, v) at a shading point with its pdf in that measure; light_eval() gives
 * the unshadowed contribution Le * cos_x * G in the same measure (the BRDF is applied by the caller).
 * This header only dispatches on the record's type: each type's code, functions and the meaning of its record lanes
 * are in lights/<type>.h (what a ray meets of a light is dispatched by lights/hit.h). Feature flags HAS_<TYPE>_LIGHTS
 * (set by the host from the scene) compile only the types a scene has. */
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

#endif
