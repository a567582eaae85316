/* Pairwise MIS weights for ReSTIR reuse (bias_correction "pairwise", the default unbiased mode).
 *
 * The canonical input c (this pixel's own reservoir) is paired with each of the k neighbour inputs q (spatial
 * reuse: the similar pixels; temporal reuse: last frame's reservoir, k = 1). With confidences M and targets p-hat
 * at each input's own surface, a sample y gets the weights
 *
 *     m_q(y) = 1/k * M_q p_q(y) / (M_q p_q(y) + M_c/k p_c(y))
 *     m_c(y) = 1/k * sum_q (M_c/k p_c(y)) / (M_q p_q(y) + M_c/k p_c(y))
 *
 * which sum to 1 for every y with p_c(y) > 0, and are the balance heuristic over all inputs when the targets are
 * equal. An input's resampling weight is m(y) p_c(y) W, and the result W = w_sum / p_c(y). Unlike 1/Z (which counts
 * samples only), a neighbour whose target at y is tiny gets a tiny weight: next to a light that touches a surface,
 * or a light of 1e-8 m^2, 1/Z gave rare huge weights (estimates 20-30 % dark at practical sample counts, the stress
 * cases `touching` and `area_extremes`).
 *
 * Supports: with visibility reuse every stored reservoir has W > 0 only for samples visible at its pixel, so p_q
 * includes the visibility at q: the canonical sample is shadow-tested from each neighbour (k shadow rays), a
 * neighbour's own sample is known visible there. The canonical's p_c needs no visibility: a y occluded here has
 * integrand 0, and the chosen sample is tested afterwards (restir/reuse.h). Where the canonical sample is known
 * visible at q (c_known_at_q: restir/reuse.h's VisKnown) its ray is left out. */
#ifndef RESTIRCL_RESTIR_PAIRWISE_H
#define RESTIRCL_RESTIR_PAIRWISE_H

#include "codes.h"

typedef struct {
    float k;         /* number of neighbour inputs */
    float conf_c;    /* M_c / k */
    float m_c;       /* the canonical sample's weight, summed over the pairs */
} PairwiseMis;

inline PairwiseMis pairwise_begin(const Reservoir* c, float k)
{
    PairwiseMis m;
    m.k = k;
    m.conf_c = c->M / k;
    m.m_c = 0.0f;
    return m;
}

/* Stream neighbour q (whose target at its own sample is target_q_own) into r and add its pair's share of the
 * canonical weight. s, sn: this pixel's and the neighbour's surfaces. Returns true if q's sample was picked, and
 * then its evaluation at s in *picked (for the caller's shadow ray). */
inline bool pairwise_neighbour(PairwiseMis* m, Reservoir* r, const Surface* s, const Surface* sn, const Reservoir* c,
                               const Reservoir* q, float target_q_own, const __global BVHNode* nodes,
                               const __global Tri* tris, const __global Light* lights, int visibility,
                               bool c_known_at_q, float rnd, LightEval* picked_eval)
{
    LightEval e;
    bool picked = false;
    float t_c = 0.0f;  /* p_c(y_q) */
    if (q->light >= 0 && q->W > 0.0f) t_c = target_of(s, lights, q->light, q->u, q->v, &e);
    if (t_c > 0.0f) {
        float a = q->M * target_q_own, b = m->conf_c * t_c;
        float mis = a / (a + b) / m->k;  /* a + b >= b > 0 */
        picked = res_update(r, q->light, q->u, q->v, mis * t_c * q->W, t_c, rnd, q->M);
        if (picked) *picked_eval = e;
    } else {
        r->M += q->M;
    }
    if (c->light >= 0 && c->W > 0.0f) {
        float b = m->conf_c * c->target;
        float t_q = target_of(sn, lights, c->light, c->u, c->v, &e);  /* p_q(y_c) */
        if (t_q > 0.0f && visibility && !c_known_at_q && !visible(nodes, tris, sn, &e)) t_q = 0.0f;
        float d = b + q->M * t_q;
        m->m_c += d > 0.0f ? b / d : 0.0f;
    }
    return picked;
}

/* Stream the canonical input with its accumulated weight; call after every neighbour. */
inline bool pairwise_canonical(const PairwiseMis* m, Reservoir* r, const Reservoir* c, float rnd)
{
    float w = (m->m_c / m->k) * c->target * c->W;
    return res_update(r, c->light, c->u, c->v, w, c->target, rnd, c->M);
}

#endif
