/* The light array (the lecture's O(1) pick): M slots, each light owning a number of consecutive slots
 * proportional to its coarse importance (at least one for every light that emits). A uniformly random slot
 * gives a light with probability slots / M, stored per light in light_pdf. Built on the host (lights/array.py). */
#ifndef RESTIRCL_LIGHT_ARRAY_H
#define RESTIRCL_LIGHT_ARRAY_H

#include "codes.h"

/* The lights in n slots and their pick probabilities slots / M: every slot is read first, then every pdf, so that
 * with a million lights (each read a cache miss) the misses of a batch overlap instead of each waiting behind the
 * last. light_array_pick is this for one slot; direct/ris.h runs it for a batch of candidates. */
inline void light_array_lights(const __global int* slots, const __global float* light_pdf, const uint* slot, int n,
                               int* light, float* pdf)
{
    for (int k = 0; k < n; ++k) light[k] = slots[slot[k]];
    for (int k = 0; k < n; ++k) pdf[k] = light_pdf[light[k]];
}

/* Pick a light from the array: a uniformly random slot (32-bit integer draw, so that arrays of millions of slots
 * stay uniform); *pdf = slots / M. */
inline int light_array_pick(const __global int* slots, int slot_count, const __global float* light_pdf, uint* rng,
                            float* pdf)
{
    uint slot = rng_below(rng, (uint)slot_count);
    int light;
    light_array_lights(slots, light_pdf, &slot, 1, &light, pdf);
    return light;
}

/* Pick a light uniformly among n; *pdf = 1 / n. */
inline int light_uniform_pick(int n, uint* rng, float* pdf)
{
    *pdf = 1.0f / (float)n;
    return (int)rng_below(rng, (uint)n);
}

/* Draw one light (uniformly or from the array) and a point on it for shading point x: returns the light and the
 * sample's uv; *pdf is the joint source pdf (light pick times the point's density in the light's measure). */
inline int light_draw(bool uniform, const __global Light* lights, int light_count, const __global int* slots,
                      int slot_count, const __global float* light_pdf, float3 x, uint* rng, float2* uv, float* pdf)
{
    float pl;
    int light = uniform ? light_uniform_pick(light_count, rng, &pl)
                        : light_array_pick(slots, slot_count, light_pdf, rng, &pl);
    float r0 = rng_next(rng), r1 = rng_next(rng);
    float py;
    *uv = light_sample(&lights[light], x, r0, r1, &py);
    *pdf = pl * py;
    return light;
}

#endif
