/* What a ray from a shading point meets of the lights, for the BSDF-sampled candidates (direct/bsdf_candidates.h) and
 * the lights the camera sees (lights/camera_visible.h): per type, the sample (u, v) of the point a ray hits (the
 * inverse of the type's map), the density with which light sampling (light_sample) produces that point, whether a
 * ray can hit the light at all (delta lights cannot: points and a sun of angle 0) and the radiance the hit point
 * sends back along the ray. Each is the type's own function in lights/<type>.h; this header only dispatches on the
 * type, each case behind the type's feature flag. Emissive triangles are geometry: the BVH finds them, and
 * tri_light maps a hit triangle (leaf order) to its light (triangle_hit is never one). */
#ifndef RESTIRCL_LIGHT_HIT_H
#define RESTIRCL_LIGHT_HIT_H

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

/* Can a ray hit light `index` (of type `type`)? Triangles when the BSDF candidates look for them (triangles: 1);
 * analytic lights when their index is below `analytic` (the BSDF candidates test that many, the scene's lights
 * coming first in the light array); then as the type says (not a delta, emits). */
inline bool light_hittable(const __global Light* l, int type, int index, int analytic, int triangles)
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
