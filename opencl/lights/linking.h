/* Light linking and shadow linking (HAS_LIGHT_LINKING; python/restircl/lights/linking.py packs them). A surface's
 * object belongs to one receiver set (Surface.receiver, from the object bits the G-buffer carries) and, as an
 * occluder, to one blocker set (Tri.e2.w); a light's link record, found through its flags, holds the 64-bit masks
 * of the receiver sets it lights and of the blocker sets that shadow it. Every place that evaluates a light at a
 * surface asks light_links, which also hands the shadow ray the light's blocker mask (LightEval.blockers, read by
 * direct/visibility.h); a light that does not light the surface has target and contribution 0 there. Builds
 * without the flag compile none of it: light_links is `true`. */
#ifndef RESTIRCL_LIGHTS_LINKING_H
#define RESTIRCL_LIGHTS_LINKING_H

#include "lights/eval.h"
#include "lights/record.h"
#include "surface/surface.h"

#ifdef HAS_LIGHT_LINKING
/* bit `set` (0..63) of a 64-bit mask held as (low word, high word) */
inline bool link_mask_has(uint2 m, int set)
{
    return (((set < 32) ? (m.x >> set) : (m.y >> (set - 32))) & 1u) != 0u;
}

/* The receiver mask (xy) and the blocker mask (zw) of light record rec; its link record lies in the light buffer
 * `lights` (index 0: none, every set) */
inline uint4 light_link_masks(const __global Light* lights, const __global Light* rec)
{
    uint k = (uint)light_flags(rec) >> LINK_SHIFT;
    return k ? as_uint4(lights[k].p) : (uint4)(0xFFFFFFFFu);
}

/* Does light rec light surface s? *e gets the light's blocker mask for the shadow ray. */
inline bool light_links(const __global Light* lights, const __global Light* rec, const Surface* s, LightEval* e)
{
    uint4 m = light_link_masks(lights, rec);
    e->blockers = m.zw;
#ifdef TEST_LINKING_WITHOUT_BLOCKERS  /* negative control (tests/lights/test_linking_cycles.py): shadows unlinked */
    e->blockers = (uint2)(0xFFFFFFFFu);
#endif
#ifdef TEST_LINKING_WITHOUT_RECEIVERS  /* negative control: every light lights every object */
    return true;
#endif
    return link_mask_has(m.xy, s->receiver);
}
#else
inline bool light_links(const __global Light* lights, const __global Light* rec, const Surface* s, LightEval* e)
{
    (void)lights;
    (void)rec;
    (void)s;
    (void)e;
    return true;
}
#endif

#endif
