/* The lanes of the 64-byte Light record (types.h) that every light type reads the same way: the type code in p.w,
 * the emitted radiance (or intensity, for points) in L.xyz and the flag bits in L.w. What the other lanes mean
 * depends on the type: each lights/<type>.h decodes them into named fields. */
#ifndef RESTIRCL_LIGHTS_RECORD_H
#define RESTIRCL_LIGHTS_RECORD_H

#include "types.h"

/* Any area emitter (triangle, quad, disk) emits on both sides; the host sets it for emissive triangles. */

inline int light_type(const __global Light* l) { return as_int(l->p.w); }

inline float3 light_radiance(const __global Light* l) { return l->L.xyz; }

inline int light_flags(const __global Light* l) { return as_int(l->L.w); }

inline bool light_two_sided(const __global Light* l) { return (light_flags(l) & LIGHT_FLAG_TWO_SIDED) != 0; }

/* Can a BSDF ray find light l? Not one whose shadows are linked (lights/linking.h): the ray stops at the first
 * object it meets, which may be one that does not shadow the light, so such a light is found by light sampling
 * alone (MIS weight 1). Every light can without light linking. */
#ifdef HAS_LIGHT_LINKING
inline bool light_ray_findable(const __global Light* l) { return (light_flags(l) & LIGHT_FLAG_SHADOW_LINKED) == 0; }
#else
inline bool light_ray_findable(const __global Light* l)
{
    (void)l;
    return true;
}
#endif

#endif
