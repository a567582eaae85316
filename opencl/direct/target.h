/* The target function p-hat of a light sample at a surface: the luminance of its unshadowed contribution
 * f * Le * cos_x * G, which RIS and ReSTIR resample towards (f from bsdf/bsdf.h, the rest from light_eval). */
#ifndef RESTIRCL_TARGET_H
#define RESTIRCL_TARGET_H

#include "direct/light_side.h"
#include "lights/linking.h"

/* f * Le * cos_x * G at s for an evaluated light sample e: what a sample adds to the pixel before its weight and
 * visibility. Every shading site multiplies this by the sample's weight. */
inline float3 unshadowed_contrib(const Surface* s, const LightEval* e)
{
    return bsdf_eval(s, s->wo, e->wi) * e->contrib;
}

/* p-hat(y) at surface s for light record rec (of the light buffer `lights`, or a copy: lights holds its link record);
 * 0 where the light is not linked to s (lights/linking.h). Fills *e when > 0. */
inline float target_of_record(const Surface* s, const __global Light* lights, const __global Light* rec, float u,
                              float v, LightEval* e)
{
    if (!s->valid) return 0.0f;
    if (!surface_light_eval(s, rec, u, v, e) || !light_links(lights, rec, s, e)) return 0.0f;
    float t = luminance(unshadowed_contrib(s, e));
    return (t > 0.0f && finite_f(t)) ? t : 0.0f;
}

/* target_of_record of lights[light]; 0 for light < 0 */
inline float target_of(const Surface* s, const __global Light* lights, int light, float u, float v, LightEval* e)
{
    return light < 0 ? 0.0f : target_of_record(s, lights, &lights[light], u, v, e);
}

#endif
