/* The combine step of ReSTIR reuse, shared by the temporal pass (one input: last frame's reservoir) and the spatial
 * pass (the similar neighbours): this pixel's canonical reservoir c and n reused reservoirs are resampled into one,
 * with the bias correction bias_correction:
 *   BIAS_NONE     M-weighted merge, W = w_sum / (Z p-hat), Z the M of the inputs whose target holds the chosen sample
 *                 (1/Z by the targets alone, no shadow ray: biased where visibility differs, darker at contact
 *                 shadows); normalised by every input's M instead, an input that cannot produce the sample (a spot's
 *                 cone, a sphere's other side) would still count and darken the pixel by its share of M, largest
 *                 for a pixel without history that merges the boost's neighbours or a permuted neighbour's history;
 *   BIAS_Z_COUNT  1/Z: W normalised by the M of the inputs whose support holds the chosen sample;
 *   BIAS_PAIRWISE pairwise MIS (restir/pairwise.h; for n = 1 the balance heuristic of the two inputs).
 * Every stored reservoir keeps one invariant: with visibility reuse, W > 0 only for a sample visible at its pixel.
 * A sample taken from an input is therefore shadow-tested here once picked; the canonical one is known visible. */
#ifndef RESTIRCL_RESTIR_REUSE_H
#define RESTIRCL_RESTIR_REUSE_H

/* The visibility shortcut (temporal pass, static scene): with visibility reuse W > 0 says visible at the
 * reservoir's own point, and where the input's point is this pixel's (same_point, within a tolerance) a sample
 * visible at one is taken as visible at the other instead of tracing a ray. Exact at the same point, biased by the
 * distance at shadow edges; a sample whose visibility was taken so max_age times in a row (Reservoir.vis_age) is
 * traced again. */
typedef struct {
    int same_point;
    int max_age;
} VisKnown;

inline VisKnown vis_known_none(void)
{
    VisKnown k;
    k.same_point = 0;
    k.max_age = 0;
    return k;
}

/* Combine c with qs[0 .. n-1] at surface s into *r (finalised). Input k's surface is pixel input_pixel[k] of
 * input_gbuf and input_glossy, and qs[k].target its target at its own sample there, evaluated with this frame's
 * lights (read by BIAS_PAIRWISE only). One random number per input, drawn in input order (the canonical one first,
 * except for BIAS_PAIRWISE where it is last). Returns the input whose sample *r holds: -1 the canonical reservoir
 * (or none), k the input qs[k]. */
inline int reuse_combine(const Surface* s, const Reservoir* c, const Reservoir* qs, int n,
                         const __global GSample* input_gbuf, const __global GlossySample* input_glossy,
                         const int* input_pixel, const __global BVHNode* nodes,
                         const __global Tri* tris, const __global Light* lights, int bias_correction, int visibility,
                         const VisKnown* known, uint* rng, Reservoir* r)
{
    res_init(r);
    LightEval e, chosen;  /* chosen: the evaluation at s of the sample picked from an input */
    int src = -1;
    if (bias_correction == BIAS_PAIRWISE) {
        PairwiseMis mis = pairwise_begin(c, (float)n);
        for (int k = 0; k < n; ++k) {
            Surface sn = surface_load(input_gbuf, input_glossy, input_pixel[k]);
            bool c_known = known->same_point && c->vis_age < known->max_age;
            if (pairwise_neighbour(&mis, r, s, &sn, c, &qs[k], qs[k].target, nodes, tris, lights, visibility,
                                   c_known, rng_next(rng), &chosen))
                src = k;
        }
        if (pairwise_canonical(&mis, r, c, rng_next(rng))) src = -1;
        res_finalize(r, 1.0f);
    } else {
        res_update(r, c->light, c->u, c->v, c->target * c->W * c->M, c->target, rng_next(rng), c->M);
        for (int k = 0; k < n; ++k) {
            float tq = qs[k].light >= 0 ? target_of(s, lights, qs[k].light, qs[k].u, qs[k].v, &e) : 0.0f;
            if (res_merge(r, &qs[k], tq, rng_next(rng))) {
                src = k;
                chosen = e;
            }
        }
        float norm = r->M;
#ifdef PROBE_BIASED_M_OF_REACHING  /* tools/experiments/biased_fresh.py: M only of the inputs whose own sample
                                    * reaches s (target > 0 here), the canonical's always; not a support test */
        if (bias_correction == BIAS_NONE) {
            norm = c->M;
            for (int k = 0; k < n; ++k)
                if (qs[k].light >= 0 && target_of(s, lights, qs[k].light, qs[k].u, qs[k].v, &e) > 0.0f)
                    norm += qs[k].M;
        }
#else
#ifdef TEST_BIASED_PLAIN_M  /* negative control (tests/bias_controls.py): the biased merge normalised by all M */
        if (bias_correction == BIAS_Z_COUNT && r->light >= 0) {
#else
        if (bias_correction != BIAS_PAIRWISE && r->light >= 0) {
#endif
            /* 1/Z; the biased merge tests the target alone (no shadow ray), which leaves it biased by visibility */
            const int vis = bias_correction == BIAS_Z_COUNT && visibility;
            norm = c->M;
            for (int k = 0; k < n; ++k) {
                /* the input that supplied the sample has it in its support (W > 0 there: p-hat > 0 and, with
                 * visibility reuse, visible); any other input is tested at its own surface */
                Surface sn = surface_load(input_gbuf, input_glossy, input_pixel[k]);
                if ((k == src && qs[k].W > 0.0f) || in_support(&sn, nodes, tris, lights, r->light, r->u, r->v, vis))
                    norm += qs[k].M;
            }
        }
#endif
        res_finalize(r, norm);
    }
    /* r->W > 0 with src < 0 means the canonical sample was picked (an input of weight 0 never is); a sample from an
     * input was picked with target > 0 at s, evaluated in chosen */
    r->vis_age = c->vis_age;
    if (visibility && bias_correction != BIAS_NONE && r->W > 0.0f && src >= 0) {
        const Reservoir* q = &qs[src];
        if (known->same_point && q->vis_age < known->max_age) {
            r->vis_age = q->vis_age + 1;
        } else {
            r->vis_age = 0;
            if (!visible(nodes, tris, s, &chosen)) r->W = 0.0f;
        }
    }
    return src;
}

#endif
