/* Spot lights: a sphere light (sphere.h, the same lanes) whose emission is masked by a cone with Blender 4's
 * smoothstep edge. The cone only masks: it does not concentrate the power. */
#ifndef RESTIRCL_LIGHTS_SPOT_H
#define RESTIRCL_LIGHTS_SPOT_H

#include "lights/sphere.h"

typedef struct {
    float3 axis;         /* a.xyz: unit direction the spot shines along */
    float cos_outer;     /* b.x: cos of half the cone angle */
    float blend_width;   /* b.y: (1 - cos_outer) * blend, the width in cos of the smooth edge */
} SpotCone;

inline SpotCone spot_cone(const __global Light* l)
{
    SpotCone c = {l->a.xyz, l->b.x, l->b.y};
    return c;
}

/* Cone mask at unit direction `out` from the light towards the shading point. */
inline float spot_mask(SpotCone cone, float3 out)
{
    float c = dot3(out, cone.axis);
    if (c <= cone.cos_outer) return 0.0f;
    if (cone.blend_width <= 0.0f) return 1.0f;
    float t = clamp_f((c - cone.cos_outer) / cone.blend_width, 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

inline bool spot_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    SphereLight sp = sphere_light(l);
    float3 out = x - sp.centre;
    float len = len3(out);
    if (!(len > 0.0f)) return false;
    float mask = spot_mask(spot_cone(l), out / len);
    if (!(mask > 0.0f)) return false;
    return sphere_emit(sp, light_radiance(l), mask, u, v, x, n, e);
}

/* The cone does not change where the sphere's points are drawn. */
inline float2 spot_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    return sphere_sample(l, x, r0, r1, pdf);
}

/* Rays meet a spot where they meet its sphere; the cone masks the emission (spot_eval). */
inline bool spot_hit(const __global Light* l, float3 x, float3 wi, float2* uv) { return sphere_hit(l, x, wi, uv); }

inline float spot_point_pdf(const __global Light* l, float3 x, const LightEval* e) { return sphere_point_pdf(l, x, e); }

inline bool spot_hittable(const __global Light* l) { return sphere_hittable(l); }

/* The sphere's radiance masked by the cone towards x: a spot seen from outside its cone is dark. */
inline float3 spot_hit_radiance(const __global Light* l, float3 x, float2 uv)
{
    (void)uv;
    float3 out = x - sphere_light(l).centre;
    float len = len3(out);
    float mask = len > 0.0f ? spot_mask(spot_cone(l), out / len) : 0.0f;
    return light_radiance(l) * mask;
}

#endif
