/* Picking the neighbours of spatial reuse (ReSTIR DI's restir/spatial.cl and ReSTIR GI's restir_gi/spatial.cl):
 * random pixels in a disk around the pixel. */
#ifndef RESTIRCL_RESTIR_NEIGHBOURS_H
#define RESTIRCL_RESTIR_NEIGHBOURS_H

/* the table's limit (settings/table.py) arrives as -DMAX_NEIGHBOURS; this fallback serves builds outside
 * core/program.py */
#ifndef MAX_NEIGHBOURS
#define MAX_NEIGHBOURS 16
#endif

/* round(), inline: |v| is at most the radius (<< 2^22) */
inline int round_i(float v) { return (int)(v + (v >= 0.0f ? 0.5f : -0.5f)); }

/* A point uniform in the disk of radius r, by rejection from the square (accepts pi/4 of the tries): no sqrt, sin
 * or cos, which cost more than the rest of picking a neighbour on a CPU. After 16 rejections (probability 2e-11)
 * it returns the centre, which the caller skips. */
inline float2 disk_offset(float r, uint* rng)
{
    for (int t = 0; t < 16; ++t) {
        float a = 2.0f * rng_next(rng) - 1.0f, b = 2.0f * rng_next(rng) - 1.0f;
        if (a * a + b * b <= 1.0f) return (float2)(a * r, b * r);
    }
    return (float2)(0.0f, 0.0f);
}

#endif
