/* The combine step of ReSTIR GI reuse, shared by its temporal pass (one input: last frame's reservoir at last
 * frame's visible point) and its spatial pass (the similar neighbours): this pixel's canonical reservoir c and n
 * reused ones are resampled into one at surface s. A reused sample moves to this pixel's visible point with its
 * Jacobian (restir_gi/sample.h): its resampling weight is p-hat_s(y) W_q |J|, and densities of one pixel are
 * compared with another's in the receiving pixel's solid angle (times the Jacobian of the move). With
 *   BIAS_NONE     M-weighted merge, W = w_sum / (M p-hat): no visibility test in the reuse (the shading tests the
 *                 final sample); a neighbour's sample that cannot move here (Jacobian outside the band) is left
 *                 out, its M too;
 *   BIAS_Z_COUNT  1/Z: Z sums the M of the inputs that could have produced the chosen sample: it moves to their
 *                 visible point within the band, p-hat > 0 there, and x_s is visible from there;
 *   BIAS_PAIRWISE pairwise MIS (as restir/pairwise.h, with the Jacobians; the canonical sample's density at a
 *                 neighbour includes visibility from there).
 * In both unbiased modes every stored reservoir keeps the invariant of restir/reuse.h: W > 0 only for a sample
 * visible from its own visible point (the initial sample is: it is the first hit of a ray from there), so a sample
 * taken from an input is shadow-tested here once picked, and the shading traces no ray. */
#ifndef RESTIRCL_RESTIR_GI_REUSE_H
#define RESTIRCL_RESTIR_GI_REUSE_H

/* The inputs of a combine: their reservoirs, and their visible points' surfaces (pixels of a G-buffer). */
typedef struct {
    const GIReservoir* q;
    const int* pixel;
    int n;
    const __global GSample* gbuf;
    const __global GlossySample* glossy;
} GIInputs;

/* q's sample moved to s: its target at s (0: it cannot move here) and the Jacobian d omega_s / d omega_q in *j */
inline float gi_moved_target(const Surface* s, const Surface* sq, const GIReservoir* q, float* j)
{
    float3 contrib;
    float g_s, t = gi_target(s, q, &contrib, &g_s);
    *j = gi_jacobian(g_s, gi_geometry(sq->x, q));
    return (t > 0.0f && gi_jacobian_ok(*j)) ? t : 0.0f;
}

/* Pairwise MIS over the inputs into *r (not finalised); returns the input whose sample r holds (-1: c's or none). */
inline int gi_pairwise(const Surface* s, const GIReservoir* c, const GIInputs* in, const __global BVHNode* nodes,
                       const __global Tri* tris, uint* rng, GIReservoir* r)
{
    float k = (float)in->n, conf_c = c->M / k, m_c = 0.0f;
    bool c_has = gi_has_sample(c);
    float g_c = c_has ? gi_geometry(s->x, c) : 0.0f;  /* c's sample's side at this pixel */
    int src = -1;
    for (int n = 0; n < in->n; ++n) {
        const GIReservoir* q = &in->q[n];
        Surface sq = surface_load(in->gbuf, in->glossy, in->pixel[n]);
        float j, t_c = gi_has_sample(q) ? gi_moved_target(s, &sq, q, &j) : 0.0f;  /* p_c(y_q) */
        if (t_c > 0.0f) {
            float a = q->M * q->target / j, b = conf_c * t_c;  /* q's density in this pixel's measure: / j */
            float mis = a / (a + b) / k;
            if (gi_res_update(r, q, mis * t_c * q->W * gi_jacobian_factor(j), t_c, rng_next(rng), q->M)) src = n;
        } else {
            rng_next(rng);
            r->M += q->M;
        }
        if (c_has) {
            float3 contrib;
            float g_q, t_q = gi_target(&sq, c, &contrib, &g_q);  /* p_q(y_c), in q's measure */
            float jq = gi_jacobian(g_q, g_c);                   /* d omega_q / d omega_s */
            if (!(t_q > 0.0f && gi_jacobian_ok(jq)) || !gi_visible(nodes, tris, &sq, c)) t_q = 0.0f;
            float b = conf_c * c->target, d = b + q->M * t_q * jq;
            m_c += d > 0.0f ? b / d : 0.0f;
        }
    }
    if (gi_res_update(r, c, (m_c / k) * c->target * c->W, c->target, rng_next(rng), c->M)) src = -1;
    gi_res_finalize(r, 1.0f);
    return src;
}

/* The M-weighted merge (BIAS_NONE and BIAS_Z_COUNT) into *r, finalised; returns the input whose sample r holds. */
inline int gi_merge(const Surface* s, const GIReservoir* c, const GIInputs* in, int bias, const __global BVHNode* nodes,
                    const __global Tri* tris, uint* rng, GIReservoir* r)
{
    int src = -1;
    gi_res_update(r, c, c->target * c->W * c->M, c->target, rng_next(rng), c->M);
    for (int n = 0; n < in->n; ++n) {
        const GIReservoir* q = &in->q[n];
        Surface sq = surface_load(in->gbuf, in->glossy, in->pixel[n]);
        float j = 1.0f, t_c = gi_has_sample(q) ? gi_moved_target(s, &sq, q, &j) : 0.0f;
        float rnd = rng_next(rng);
        if (bias == BIAS_NONE && gi_has_sample(q) && !gi_jacobian_ok(j)) continue;  /* cannot move here: left out */
        if (gi_res_update(r, q, t_c * q->W * gi_jacobian_factor(j) * q->M, t_c, rnd, q->M)) src = n;
    }
    float norm = r->M;
    if (bias == BIAS_Z_COUNT && r->target > 0.0f) {
        norm = c->M;
        for (int n = 0; n < in->n; ++n) {
            const GIReservoir* q = &in->q[n];
            if (n == src) {
                norm += gi_has_sample(q) ? q->M : 0.0f;
                continue;
            }
            Surface sq = surface_load(in->gbuf, in->glossy, in->pixel[n]);
            float j;
            if (gi_moved_target(&sq, s, r, &j) > 0.0f && gi_visible(nodes, tris, &sq, r)) norm += q->M;
        }
    }
    gi_res_finalize(r, norm);
    return src;
}

/* Combine c with the inputs at surface s into *r (finalised) by bias correction `bias`; an input's sample picked
 * in an unbiased mode is shadow-tested here (W = 0 where x_s is hidden from s). */
inline void gi_reuse_combine(const Surface* s, const GIReservoir* c, const GIInputs* in, int bias,
                             const __global BVHNode* nodes, const __global Tri* tris, uint* rng, GIReservoir* r)
{
    gi_res_init(r);
    int src = bias == BIAS_PAIRWISE ? gi_pairwise(s, c, in, nodes, tris, rng, r)
                                    : gi_merge(s, c, in, bias, nodes, tris, rng, r);
    if (bias != BIAS_NONE && src >= 0 && r->W > 0.0f && !gi_visible(nodes, tris, s, r)) r->W = 0.0f;
}

#endif
