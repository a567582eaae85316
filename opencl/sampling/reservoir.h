/* Weighted reservoir sampling of light samples y = (light, u, v): streaming update, finalisation to the
 * unbiased contribution weight W, and merging of reservoirs (ReSTIR). Reservoirs live in private memory
 * while a kernel works on them and in __global Reservoir buffers between passes and frames. */
#ifndef RESTIRCL_RESERVOIR_H
#define RESTIRCL_RESERVOIR_H

#include "numerics.h"

inline void res_init(Reservoir* r)
{
    r->light = -1;
    r->u = 0.0f;
    r->v = 0.0f;
    r->w_sum = 0.0f;
    r->M = 0.0f;
    r->W = 0.0f;
    r->target = 0.0f;
    r->vis_age = 0;
}

/* Stream one candidate with resampling weight w (= target / source pdf) into r; rnd uniform in [0, 1).
 * A candidate with w <= 0 (or NaN) is counted in M but can never be picked. Returns true if it was picked. */
inline bool res_update(Reservoir* r, int light, float u, float v, float w, float target, float rnd, float count)
{
    r->M += count;
    if (!(w > 0.0f) || !finite_f(w)) return false;
    r->w_sum += w;
    if (rnd * r->w_sum < w) {
        r->light = light;
        r->u = u;
        r->v = v;
        r->target = target;
        return true;
    }
    return false;
}

/* res_update driven by one uniform *u for the whole stream (QMC, sampling/qmc.h): the candidate is picked when *u falls
 * in its share w / w_sum of [0, 1), and *u is remapped to a fresh uniform in [0, 1) within the part it fell in, for
 * the next candidate. The choice has the probabilities of res_update, and a stratified *u stratifies it. */
inline bool res_update_remap(Reservoir* r, int light, float u, float v, float w, float target, float* sel,
                             float count)
{
    r->M += count;
    if (!(w > 0.0f) || !finite_f(w)) return false;
    r->w_sum += w;
    float p = w / r->w_sum, x = *sel;
    bool pick = x < p;
    x = pick ? x / p : (x - p) / (1.0f - p);
    *sel = clamp(x, 0.0f, 0x1.fffffep-1f);  /* below 1: a choice with p = 1 after it must pick */
    if (pick) {
        r->light = light;
        r->u = u;
        r->v = v;
        r->target = target;
    }
    return pick;
}

/* W = w_sum / (norm * target(y)), where norm is M (plain RIS / biased reuse) or Z (unbiased reuse).
 * target = 0 or a non-finite result gives an empty reservoir (W = 0), never a division by zero. */
inline void res_finalize(Reservoir* r, float norm)
{
    float denom = norm * r->target;
    r->W = (r->light >= 0 && denom > 0.0f) ? r->w_sum / denom : 0.0f;
    if (!finite_f(r->W) || !finite_f(r->w_sum)) {
        r->W = 0.0f;
        r->w_sum = 0.0f;
        r->light = -1;
    }
}

/* Merge reservoir q into s: q's sample is one candidate with weight target_s(q.y) * q.W * q.M, and s.M grows by
 * q.M. target_at_s is the target function of s's pixel evaluated at q's sample. */
inline bool res_merge(Reservoir* s, const Reservoir* q, float target_at_s, float rnd)
{
    float w = target_at_s * q->W * q->M;
    return res_update(s, q->light, q->u, q->v, w, target_at_s, rnd, q->M);
}

inline Reservoir res_load(const __global Reservoir* buf, int i) { return buf[i]; }

#endif
