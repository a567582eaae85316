/* Whether an area light is sampled by solid angle at a shading point (the host sets the flags from the setting
 * `area_sampling`, python/restircl/lights/area_sampling.py), and the float32 limits of the spherical maps that do it.
 * The choice depends only on the light and the shading point, so light sampling and the MIS density of a point a
 * BSDF ray hit (lights/lights.h light_point_pdf) make the same choice. */
#ifndef RESTIRCL_LIGHTS_SOLID_ANGLE_H
#define RESTIRCL_LIGHTS_SOLID_ANGLE_H

#include "codes.h"

#include "lights/eval.h"
#include "lights/record.h"
#include "numerics.h"

/* `auto`: solid angle where the light's bounding radius exceeds this fraction of its distance; below it cos_l / d^2
 * varies little over the light, so area sampling is about as good and cheaper. */
#define SA_AUTO_RATIO 0.25f
/* The spherical maps lose precision in float32 below this solid angle (sr), and spherical triangles near a
 * hemisphere (a shading point on the triangle's plane, inside it) above SA_MAX_SR: area sampling there. */
#define SA_MIN_SR 5e-4f
#define SA_MAX_SR 6.0f

/* Does the light want solid-angle sampling at squared distance dist2 from its centre, bounding radius^2 extent2? */
inline bool sa_wanted(const __global Light* l, float extent2, float dist2)
{
    int f = light_flags(l);
    if (!(f & LIGHT_FLAG_SOLID_ANGLE)) return false;
    return !(f & LIGHT_FLAG_SA_AUTO) || extent2 > (SA_AUTO_RATIO * SA_AUTO_RATIO) * dist2;
}

/* A solid angle the spherical maps handle. */
inline bool sa_in_range(float S) { return S > SA_MIN_SR && S < SA_MAX_SR && finite_f(S); }

/* The area density of a point at distance dist seen under cos_l by uniform sampling of solid angle S. */
inline float sa_area_pdf(float S, float cos_l, float dist)
{
    return (cos_l > 0.0f && dist > 0.0f) ? cos_l / (dist * dist * S) : 0.0f;
}

/* The density (area measure) with which a light of this area sampled it produces the evaluated point e: uniform in
 * solid angle S where `solid_angle`, else uniform in area; for MIS with BSDF candidates (lights/lights.h). */
inline float sa_point_pdf(bool solid_angle, float S, float area, const LightEval* e)
{
    return solid_angle ? sa_area_pdf(S, abs_f(dot3(e->nl, e->wi)), e->dist) : 1.0f / area;
}

#endif
