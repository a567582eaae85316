/* The sun: directions in a cone of the sun's angular diameter, uniform in solid angle (the measure), or one
 * direction (a delta) for a diameter of 0. L is the radiance inside the cone. */
#ifndef RESTIRCL_LIGHTS_SUN_H
#define RESTIRCL_LIGHTS_SUN_H

#include "lights/eval.h"
#include "lights/record.h"
#include "sampling/warps.h"

typedef struct {
    float3 dir;       /* a.xyz: unit direction towards the sun */
    float cos_half;   /* b.x: cos of half the angular diameter */
    float omc;        /* b.y: 1 - cos_half, exact for tiny angles; 0: a delta direction */
} SunLight;

inline SunLight sun_light(const __global Light* l)
{
    SunLight s = {l->a.xyz, l->b.x, l->b.y};
    return s;
}

inline bool sun_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    SunLight sun = sun_light(l);
    float3 wi = sun.omc > 0.0f ? cone_dir(sun.dir, sun.omc, u, v) : sun.dir;
    float cos_x = dot3(n, wi);
    if (!(cos_x > 0.0f)) return false;
    e->contrib = light_radiance(l) * cos_x;
    e->wi = wi;
    e->pos = x + wi;
    e->nl = -wi;
    e->dist = INFINITY;
    return true;
}

inline float2 sun_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    float omc = sun_light(l).omc;
    *pdf = omc > 0.0f ? 1.0f / (2.0f * RESTIRCL_PI * omc) : 1.0f;
    return (float2)(r0, r1);
}

/* The sample (u, v) of direction wi when it lies in the sun's cone; false outside it and for a delta sun. */
inline bool sun_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    (void)x;
    SunLight sun = sun_light(l);
    if (!(sun.omc > 0.0f) || !(dot3(wi, sun.dir) > 0.0f)) return false;
    *uv = cone_dir_inverse(sun.dir, sun.omc, wi);  /* 1 - cos from the sine: tiny suns are not lost to rounding */
    return uv->x < 1.0f;
}

/* The density of sun_sample, the same for every direction of the cone. */
inline float sun_point_pdf(const __global Light* l, float3 x, const LightEval* e)
{
    (void)e;
    float pdf;
    sun_sample(l, x, 0.0f, 0.0f, &pdf);
    return pdf;
}

/* A sun of angle 0 is a delta direction no ray meets. The host's half of this rule is
 * python/restircl/lights/sun.py has_shape (which lights the camera sees). */
inline bool sun_hittable(const __global Light* l) { return sun_light(l).omc > 0.0f; }

/* Uniform radiance inside the cone. */
inline float3 sun_hit_radiance(const __global Light* l, float3 x, float2 uv)
{
    (void)x;
    (void)uv;
    return light_radiance(l);
}

#endif
