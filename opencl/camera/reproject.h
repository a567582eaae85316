/* Reprojection, shared by ReSTIR's temporal reuse and TAA: where was the surface of pixel (x, y) last frame,
 * and is the history found there the same surface (off-screen, disocclusion and miss tests)? */
#ifndef RESTIRCL_REPROJECT_H
#define RESTIRCL_REPROJECT_H

#include "numerics.h"

/* Continuous previous-frame pixel position of the surface at pixel (x, y); false when there is none. */
inline bool reproject_position(const __global GSample* gbuf, int x, int y, int width, float2* prev)
{
    float4 m = gbuf[y * width + x].motion;
    if (m.z == 0.0f) return false;
    *prev = (float2)((float)x + 0.5f, (float)y + 0.5f) + m.xy;
    return finite_f(prev->x) && finite_f(prev->y);
}

/* Is previous-frame G-sample `prev` the same surface as current G-sample `cur`? Misses (prim -1) match misses;
 * lights the camera sees (prim below -1, lights/camera_visible.h) are tested like surfaces. */
inline bool reproject_same_surface(const GSample* cur, const GSample* prev, float depth_tol, float normal_cos)
{
    int cur_prim = as_int(cur->normal.w), prev_prim = as_int(prev->normal.w);
    bool cur_hit = cur_prim != -1, prev_hit = prev_prim != -1;
    if (cur_hit != prev_hit || (cur_prim < -1) != (prev_prim < -1)) return false;  /* a light is no surface */
    if (!cur_hit) return true;
    float expected = cur->motion.w;  /* depth of the surface point in the previous camera */
    if (!(abs_f(prev->pos.w - expected) <= depth_tol * abs_f(expected))) return false;
    return dot3(cur->normal.xyz, prev->normal.xyz) >= normal_cos;
}

/* Permutation sampling (RTXDI's): move the reprojected pixel within its 4x4 block by a bijection that is the
 * same for every pixel of a frame and changes from frame to frame (`permutation`: 16 | a 4-bit key; 0: off). Each
 * pixel then reuses a neighbour's history, not its own, so consecutive frames of a pixel are less correlated (what
 * a denoiser and the eye see as crawling patterns); the surface test below still applies to the pixel taken. */
inline void permute_pixel(int* px, int* py, uint permutation)
{
    if (permutation == 0u) return;
    int ox = (int)(permutation & 3u), oy = (int)((permutation >> 2) & 3u);
    *px = ((*px + ox) ^ 3) - ox;
    *py = ((*py + oy) ^ 3) - oy;
}

/* Previous-frame pixel (px, py) if it holds the surface of current G-sample `cur`, else -1. */
inline int reproject_test(const GSample* cur, const __global GSample* prev_gbuf, int px, int py, int width,
                          int height, float depth_tol, float normal_cos)
{
    if (px < 0 || py < 0 || px >= width || py >= height) return -1;
    int j = py * width + px;
    GSample prev = prev_gbuf[j];
    return reproject_same_surface(cur, &prev, depth_tol, normal_cos) ? j : -1;
}

/* The block's second bijection: every offset of `permutation`'s key moved by 2 (so the pixel it names is neither the
 * pixel itself, as with any key, nor the one the first key names). */
inline uint permutation_second(uint permutation)
{
    uint ox = (permutation + 2u) & 3u, oy = ((permutation >> 2) + 2u) & 3u;
    return 16u | ox | (oy << 2);
}

/* The previous-frame pixel index holding the surface of pixel (x, y), or -1 (off-screen or disoccluded). With
 * permutation sampling the permuted pixel is tried, then, where it fails the surface test (an edge within the 4x4
 * block), the pixel the block's second bijection names; where both fail the pixel has no history this frame and
 * takes the spatial pass's fresh-pixel work (disocclusion boost, extra candidates). Neither is the pixel's own
 * history, so the chains stay broken; the second try gives a history to about two thirds of the pixels the first
 * left without one (garden_orbit 13 -> 4 %, market_orbit 23 -> 9 % of the pixels), which costs less than their
 * fresh-pixel work and lowers the error through TAA a little (docs/measurements/temporal-stability.md, "Where
 * ReSTIR's error through TAA is left"). Which pixel is taken depends on the G-buffers alone, so the merge stays
 * unbiased. Falling back to the pixel's own history instead (the probe below) keeps the chains at the edges, where
 * they cost TAA most ("Why permutation sampling costs CPU"). */
inline int reproject_pixel(const __global GSample* gbuf, const __global GSample* prev_gbuf, int x, int y,
                           int width, int height, float depth_tol, float normal_cos, uint permutation)
{
    float2 p;
    if (!reproject_position(gbuf, x, y, width, &p)) return -1;
    int px = (int)floor(p.x), py = (int)floor(p.y);
    GSample cur = gbuf[y * width + x];
    if (permutation != 0u) {
        int qx = px, qy = py;
        permute_pixel(&qx, &qy, permutation);
        int j = reproject_test(&cur, prev_gbuf, qx, qy, width, height, depth_tol, normal_cos);
#ifndef PROBE_PERMUTATION_ONE_TRY  /* a probe (--define): the first bijection alone, as before the second try */
        if (j >= 0) return j;
        qx = px;
        qy = py;
        permute_pixel(&qx, &qy, permutation_second(permutation));
        j = reproject_test(&cur, prev_gbuf, qx, qy, width, height, depth_tol, normal_cos);
#endif
#ifdef PROBE_PERMUTATION_FALLBACK  /* tools/experiments/restir_motion.py --define: the own history on a failure */
        if (j >= 0) return j;
#else
        return j;
#endif
    }
    return reproject_test(&cur, prev_gbuf, px, py, width, height, depth_tol, normal_cos);
}

#endif
