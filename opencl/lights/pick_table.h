/* A per-pixel light pick for still renders of few lights (python/restircl/lights/pick_table.py, Settings
 * light_proposal "pixel"). The light array picks by power alone, the same everywhere: a sun or a spot that lights
 * a pixel little takes its share of the candidates all the same. Here every pixel of a still has its own
 * probabilities, proportional to each light's estimated unshadowed contribution at the pixel's surface (a few
 * sampled points per light, once per still render: lights/pick_table.cl) mixed with the light array's pdf (a floor:
 * every light that emits keeps a nonzero probability at every pixel, whatever the estimate, so RIS over these
 * candidates stays unbiased; the table is fixed before the frames that use it, so it may depend on the first
 * frame's G-buffer).
 *
 * A row holds the first n - 1 cumulative probabilities of the pixel's n lights in 16-bit fixed point (the last is
 * 65536): a pick inverts the top 16 bits of its word, so a stratified word (the Sobol sampler) stays stratified
 * over the lights, and the pdf is the row's step exactly, the same for the pick and for light_pick_pdf. */
#ifndef RESTIRCL_LIGHT_PICK_TABLE_H
#define RESTIRCL_LIGHT_PICK_TABLE_H

#include "codes.h"

#define PICK_TABLE_ONE 65536u
#define PICK_TABLE_POINTS 4         /* points per light of the estimate (2 x 2 strata) */

/* The probability of light `light` in row `row` of n lights. */
inline float pick_table_pdf(const __global ushort* row, int n, int light)
{
    uint lo = light > 0 ? (uint)row[light - 1] : 0u;
    uint hi = light < n - 1 ? (uint)row[light] : PICK_TABLE_ONE;
    return (float)(hi - lo) * (1.0f / 65536.0f);
}

/* The light of the word `bits` in row `row` of n lights, *pdf its probability: the first light whose cumulative
 * bound exceeds the word's top 16 bits (a bisection: rows are non-decreasing). */
inline int pick_table_light(const __global ushort* row, int n, uint bits, float* pdf)
{
    uint v = bits >> 16;
    int lo = 0, hi = n - 1;  /* the answer lies in [lo, hi]: light n - 1's bound is PICK_TABLE_ONE */
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (v < (uint)row[mid]) hi = mid; else lo = mid + 1;
    }
    *pdf = pick_table_pdf(row, n, lo);
    return lo;
}

#endif
