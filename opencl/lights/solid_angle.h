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
#include "sampling/warps.h"

/* `auto`: solid angle where the light's bounding radius exceeds this fraction of its distance; below it cos_l / d^2
 * varies little over the light, so area sampling is about as good and cheaper. */
#define SA_AUTO_RATIO 0.25f
/* `area`: solid angle where the bounding radius exceeds this fraction of the distance, i.e. within twice the radius
 * of the light's centre. Beyond it every point of the light is at least one radius from the shading point, so the
 * weight of a point sampled uniformly in area, Le cos_x cos_l A / d^2, stays below Le A / radius^2 (at most pi Le:
 * a disk fills its circle best); within it that weight grows as 1 / d^2 without bound, and where a receiver touches
 * the light (a surface an emitter stands on) its second moment diverges: fireflies that no number of samples
 * averages out. Sampled by solid angle there, the weight is Le cos_x S (S <= 2 pi). */
#define SA_NEAR_RATIO 0.5f
/* The spherical maps lose precision in float32 below this solid angle (sr): area sampling there (a light seen
 * edge-on, whose weight cos_l A / d^2 is then small too). Above SA_MAX_SR (a shading point close to the light's
 * plane, inside its outline: spherical triangles near a hemisphere lose precision too) the directions are drawn
 * uniformly over the hemisphere towards the plane instead, a direction that misses the light being no sample (at
 * most 1 - 6 / 2 pi, 5 %, of them): a receiver face to face with an emitter would otherwise be area-sampled with a
 * weight that grows as 1 / d^2 (planar.h planar_hemisphere_ab). */
#define SA_MIN_SR 5e-4f
#define SA_MAX_SR 6.0f

/* Does the light want solid-angle sampling at squared distance dist2 from its centre, bounding radius^2 extent2? */
inline bool sa_wanted(const __global Light* l, float extent2, float dist2)
{
    int f = light_flags(l);
    if (!(f & LIGHT_FLAG_SOLID_ANGLE)) return false;
    if (f & LIGHT_FLAG_SA_AUTO) return extent2 > (SA_AUTO_RATIO * SA_AUTO_RATIO) * dist2;
    if (f & LIGHT_FLAG_SA_NEAR) return extent2 > (SA_NEAR_RATIO * SA_NEAR_RATIO) * dist2;
    return true;
}

/* How a light wanted by solid angle is sampled, from the solid angle S it subtends (sa_choice). */
#define SA_AREA 0        /* uniformly in area */
#define SA_MAP 1         /* uniformly in the solid angle S, by the type's spherical map */
#define SA_HEMISPHERE 2  /* uniformly in the hemisphere towards the light's plane, misses discarded */

inline int sa_choice(float S)
{
    if (!(S > SA_MIN_SR) || !finite_f(S)) return SA_AREA;
    return S < SA_MAX_SR ? SA_MAP : SA_HEMISPHERE;
}

/* The solid angle over which a choice other than SA_AREA draws its directions uniformly. */
inline float sa_sampled_sr(int how, float S) { return how == SA_MAP ? S : 2.0f * RESTIRCL_PI; }

/* The area density of a point at distance dist seen under cos_l by uniform sampling of solid angle S. */
inline float sa_area_pdf(float S, float cos_l, float dist)
{
    return (cos_l > 0.0f && dist > 0.0f) ? cos_l / (dist * dist * S) : 0.0f;
}

/* The density (area measure) with which a light of this area, sampled as `how` says (S: its solid angle), produces
 * the evaluated point e; for MIS with BSDF candidates (lights/lights.h). */
inline float sa_point_pdf(int how, float S, float area, const LightEval* e)
{
    if (how == SA_AREA) return 1.0f / area;
    return sa_area_pdf(sa_sampled_sr(how, S), abs_f(dot3(e->nl, e->wi)), e->dist);
}

#endif
