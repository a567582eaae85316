/* What a ray from a shading point meets of the lights, for the BSDF-sampled candidates (direct/bsdf_candidates.h): per
 * type, the sample (u, v) of the point a ray hits (the inverse of the type's map, lights/<type>.h), the density
 * with which light sampling (light_sample) produces that point, and whether a ray can hit the light at all (delta
 * lights cannot: points and a sun of angle 0). Emissive triangles are geometry: the BVH finds them, and
 * tri_light maps a hit triangle (leaf order) to its light. */
#ifndef RESTIRCL_LIGHT_HIT_H
#define RESTIRCL_LIGHT_HIT_H

/* The sample (u, v) of analytic light l (not a triangle) that the unit ray x + t wi, t > 0, hits. */
inline bool light_hit(const __global Light* l, int type, float3 x, float3 wi, float2* uv)
{
    switch (type) {
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
    default: break;
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
    case LIGHT_SPHERE:
    case LIGHT_SPOT: return sphere_point_pdf(l, x, e);
    case LIGHT_SUN: { float pdf; sun_sample(l, x, 0.0f, 0.0f, &pdf); return pdf; }
#ifdef HAS_ENVIRONMENT
    case LIGHT_ENVIRONMENT: return environment_point_pdf(l, e);
#endif
    default: break;
    }
    return 0.0f;
}

/* Can a ray hit light `index` (of type `type`)? Triangles when the BSDF candidates look for them (triangles: 1);
 * analytic lights when their index is below `analytic` (the BSDF candidates test that many, the scene's lights
 * coming first in the light array) and they are not a delta. */
inline bool light_hittable(const __global Light* l, int type, int index, int analytic, int triangles)
{
    if (type == LIGHT_TRIANGLE) return triangles != 0;
    if (index >= analytic) return false;
    if (type == LIGHT_SPHERE || type == LIGHT_SPOT) return sphere_light(l).radius > 0.0f;
    if (type == LIGHT_SUN) return sun_light(l).omc > 0.0f;
    if (type == LIGHT_ENVIRONMENT) return environment_emits(l);
    return true;
}

#endif
