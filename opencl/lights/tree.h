/* The light tree: a spatial proposal for RIS candidates (built on the host by lights/tree.py, which says how it is
 * laid out). A pick descends from the root, at each node taking a child with probability
 *     p = (1 - F) (N_c / (N_0 + N_1) + R_c / (R_0 + R_1)) / 2 + F phi_c / (phi_0 + phi_1),
 * N and R the children's importances at the shading point (power x orientation bound / squared distance, as pbrt-v4's
 * LightBounds::Importance, but at the distance of the box's nearest point and of its farthest corner instead of its
 * centre's: light_tree_importance), phi their power, F = LIGHT_TREE_FLOOR. The power term is the floor: every
 * light of power > 0 keeps a nonzero probability everywhere, so RIS over tree candidates stays unbiased even where
 * a bound is wrong (a shading normal, a normal map); no branch goes below LIGHT_TREE_MIN_BRANCH. The pick's pdf
 * is the product of the branch probabilities; light_pick_pdf recomputes it for a given light from its leaf index
 * (its trail: the binary digits of leaf + 1), with the same arithmetic, for the MIS weights of BSDF candidates.
 * At a node of at most LIGHT_TREE_EXACT lights near x the descent stops branching and picks one of them by each
 * light's own importance (lights/tree_exact.h): there the pdf's last factor is that light's share.
 * Lights without a position (suns, the world) are outside the tree: a pick takes one of them instead by their
 * fixed shares and the tree's weighed at the point by what can reach it (lights/distant_pick.h).
 *
 * Presampled light tiles do not apply: a tile is drawn without a shading point, the tree's proposal needs one. */
#ifndef RESTIRCL_LIGHT_TREE_H
#define RESTIRCL_LIGHT_TREE_H

#include "codes.h"

#include "lights/array.h"  /* light_pick_lights falls back to the array (and picks the distant lights by it) */
#include "lights/pick_table.h"

#define LIGHT_TREE_MEMO 15          /* the top four levels' branches are computed once per pixel and batch */

/* Where a light pick comes from, and what it needs to give the pick pdf of any light: the light array, or
 * the tree's nodes, per-light info (leaf node, or -1 with the light's row of the distant lights' table) and that
 * table (lights/distant_pick.py). */
typedef struct {
    const __global int* slots;
    const __global float* light_pdf;
    const __global LightTreeNode* nodes;
    const __global int2* info;
    const __global int8* distant;
    int tree;
    int leaves;
    int distant_count;
    float p_local;                 /* the tree's fixed share (of the light array): the local share's floor */
    const __global ushort* table;  /* the pixel's row of the per-pixel pick (lights/pick_table.h), or 0 */
    int table_n;                   /* its lights; 0: no table */
} LightPick;

inline LightPick light_pick_source(const __global int* slots, const __global float* light_pdf,
                                   const __global LightTreeNode* nodes, const __global int2* info,
                                   const __global int8* distant, SamplerParams sp)
{
    LightPick p = {slots, light_pdf, nodes, info, distant, sp.light_tree, sp.tree_leaves, sp.tree_distant,
                   sp.tree_p_local, 0, 0};
    return p;
}

/* Pick from pixel i's row of the per-pixel table `table` (of light_count lights) where the frame has one. */
inline void light_pick_use_table(LightPick* lp, const __global ushort* table, SamplerParams sp, int i)
{
#ifdef HAS_PICK_TABLE
    if (sp.pick_table && sp.light_count > 1) {
        lp->table = table + (size_t)i * (size_t)(sp.light_count - 1);
        lp->table_n = sp.light_count;
    }
#endif
}

/* Whether a pick takes a 32-bit word (the tree's descent, the table's inversion) rather than a slot. */
inline bool light_pick_takes_word(const LightPick* lp) { return lp->tree || lp->table_n > 0; }

#ifdef HAS_LIGHT_TREE
/* cos and sin of max(0, a - b), angles in [0, pi] given by cos and sin */
inline float2 light_tree_cos_sub(float cos_a, float sin_a, float cos_b, float sin_b)
{
    if (cos_a >= cos_b) return (float2)(1.0f, 0.0f);
    return (float2)(cos_a * cos_b + sin_a * sin_b, sin_a * cos_b - cos_a * sin_b);
}

/* What the lights below node nd can give point x of unit normal n, up to a constant: their power times a bound of
 * the orientation terms (incidence at x, emission by the lights' cone; 1 where x is inside the box's bounding sphere,
 * which every direction may reach, and no cone to test for lights that emit in every direction) over squared
 * distance, at two distances: .x at the box's nearest point (an upper bound; 0 when x is in the box, then kept
 * finite by a floor of 1e-12) and .y at its farthest corner. The centre's distance would judge a box with one light
 * beside x, its others metres away, as far as its centre. A surface that transmits (rough glass) takes light from
 * behind its tangent plane too: its callers pass 2 n (direct/light_side.h light_pick_normal), and the incidence
 * bound is then that of the nearer of n and -n, as Cycles' light tree treats a transmitting closure. */
inline float2 light_tree_importance(const __global LightTreeNode* nd, float3 x, float3 n)
{
    float4 lo = nd->lo, hi = nd->hi, ax = nd->axis;
    float3 d = x - 0.5f * (lo.xyz + hi.xyz);
    float3 half_ext = 0.5f * (hi.xyz - lo.xyz);
    float d2 = dot3(d, d), r2 = dot3(half_ext, half_ext);
    float bound = lo.w;
    if (d2 > r2) {
        float inv_d = 1.0f / sqrt(d2);
        float3 wo = d * inv_d;  /* from the node towards x */
        float sin2_b = r2 * inv_d * inv_d;
        float cos_b = sqrt(fmax_f(0.0f, 1.0f - sin2_b)), sin_b = sqrt(sin2_b);
        float cos_i = -dot3(n, wo);
#if defined(HAS_TRANSMISSION) && !defined(LIGHT_TREE_ONE_SIDED)  /* (defined only by tests/lights/test_tree_glass.py) */
        if (dot3(n, n) > 2.0f) cos_i = abs_f(0.5f * cos_i);  /* 2 n: a surface that takes light from both sides */
#endif
        float cos_ip = cos_i >= cos_b ? 1.0f
                                      : cos_i * cos_b + sqrt(fmax_f(0.0f, 1.0f - cos_i * cos_i)) * sin_b;
        if (!(cos_ip > 0.0f)) return (float2)(0.0f);  /* the incidence angle's bound: the box is behind x */
        float cos_p = 1.0f;                            /* the emission angle's bound */
        float cos_o = hi.w;
        if (cos_o > -1.0f) {
            float cos_w = dot3(ax.xyz, wo);
            if (nd->meta.y & LIGHT_TREE_TWO_SIDED) cos_w = abs_f(cos_w);
            float2 w_o = light_tree_cos_sub(cos_w, sqrt(fmax_f(0.0f, 1.0f - cos_w * cos_w)), cos_o,
                                            as_float(nd->meta.z));
            cos_p = light_tree_cos_sub(w_o.x, w_o.y, cos_b, sin_b).x;
            if (cos_p < ax.w) return (float2)(0.0f);
        }
        bound *= cos_ip * cos_p;
    }
    /* per axis, x's distance from the box's near face (0 between the faces) and from its far face */
    float3 ad = (float3)(abs_f(d.x), abs_f(d.y), abs_f(d.z));
    float3 near = (float3)(fmax_f(ad.x - half_ext.x, 0.0f), fmax_f(ad.y - half_ext.y, 0.0f),
                           fmax_f(ad.z - half_ext.z, 0.0f));
    float3 far = ad + half_ext;
    return (float2)(bound / fmax_f(dot3(near, near), 1e-12f), bound / fmax_f(dot3(far, far), 1e-12f));
}

/* A pick probability from an importance share and the power (or fixed) share: mixed by the floor
 * LIGHT_TREE_FLOOR, so that a light the bound rules out stays reachable (lights/pick_floor.py mixed). The branches,
 * the exact pick below small nodes and the tree's share against the distant lights all take it. */
inline float light_pick_floored(float share, float fixed)
{
    return (1.0f - LIGHT_TREE_FLOOR) * share + LIGHT_TREE_FLOOR * fixed;
}

/* The importance share from the shares at the near and the far distances (negative: undefined, a sum that is 0 or
 * not finite): their mean, one alone where the other is undefined, the power share pw where both are. */
inline float light_tree_near_far(float near, float far, float pw)
{
    return near >= 0.0f ? (far >= 0.0f ? 0.5f * (near + far) : near) : (far >= 0.0f ? far : pw);
}

/* The share a of a + b, or -1 where the sum is 0 or not finite. */
inline float light_tree_share(float a, float b)
{
    float sum = a + b;
    return sum > 0.0f && finite_f(sum) ? a / sum : -1.0f;
}

/* The probability of taking the first of the children c, c + 1 at x: the mean of their importance shares at the
 * near and at the far distances (light_tree_importance; one of them alone where the other's sum is 0 or not
 * finite, their power share where both are), mixed with the power share, and kept within [B, 1 - B] (B =
 * LIGHT_TREE_MIN_BRANCH): a float draw could not reach a branch of probability 1e-12 that the pmf would still count,
 * and 1 - p of the clamped p is what the descent takes the second child with, to float rounding. */
inline float light_tree_branch(const __global LightTreeNode* nodes, int c, float3 x, float3 n)
{
    float phi0 = nodes[c].lo.w, phi1 = nodes[c + 1].lo.w;
    /* a child without power is never taken (the light array gives such lights no slot either) */
    if (!(phi0 > 0.0f) || !(phi1 > 0.0f)) return phi0 > 0.0f ? 1.0f : 0.0f;
    float pw = phi0 / (phi0 + phi1);
    float2 i0 = light_tree_importance(&nodes[c], x, n), i1 = light_tree_importance(&nodes[c + 1], x, n);
    float pi = light_tree_near_far(light_tree_share(i0.x, i1.x), light_tree_share(i0.y, i1.y), pw);
    float p = light_pick_floored(pi, pw);
    return clamp_f(p, LIGHT_TREE_MIN_BRANCH, 1.0f - LIGHT_TREE_MIN_BRANCH);
}

#include "lights/distant_pick.h"  /* the distant lights against the tree (light_tree_local_share) */
#include "lights/tree_importance4.h"  /* the importance of four nodes at once, for the exact pick */
#include "lights/tree_exact.h"        /* below a node of few lights, each by its own importance */

/* light_tree_branch of node j's children at x, from memo[j] where j < LIGHT_TREE_MEMO (computed there the first
 * time: the top levels are the same for every candidate of a pixel; negative: not yet computed). */
inline float light_tree_branch_at(const LightPick* lp, int j, float3 x, float3 n, float* memo)
{
    if (j >= LIGHT_TREE_MEMO) return light_tree_branch(lp->nodes, 2 * j + 1, x, n);
    if (memo[j] < 0.0f) memo[j] = light_tree_branch(lp->nodes, 2 * j + 1, x, n);
    return memo[j];
}

/* Descend from the root: the light of the leaf reached, *pdf its probability (the product of the branches taken,
 * as light_tree_leaf_pdf computes it). Each branch draws a fresh number from the random stream `state`, or, with
 * `stratified`, compares the one uniform u in [0, 1) and remaps it onto [0, 1) for the next level: the stratified
 * descent, by which the strata of a Sobol word stay strata over the leaves (a stream seeded by the word loses
 * them). memo: light_tree_branch_at's. */
inline int light_tree_descend(const LightPick* lp, float3 x, float3 n, uint state, float u, int stratified, float* memo,
                              float* pdf)
{
    int j = 0;
    float p = 1.0f;
    while (j < lp->leaves - 1) {
        if (lp->nodes[j].meta.w <= LIGHT_TREE_EXACT_AT && light_tree_exact_here(lp, j, x)) {
            float q;  /* a node of few lights near x: one of them by its own importance (lights/tree_exact.h) */
            j = light_tree_exact_pick(lp, j, x, n, stratified ? u : rng_next(&state), &q);
            p *= q;
            break;
        }
        int c = 2 * j + 1;
        float p0 = light_tree_branch_at(lp, j, x, n, memo);
        bool first = (stratified ? u : rng_next(&state)) < p0;
        p *= first ? p0 : 1.0f - p0;
        j = first ? c : c + 1;
#ifndef TEST_DESCENT_WITHOUT_REMAP  /* negative control of the tests only (tests/bias_controls.py): u not remapped */
        if (stratified) u = fmin_f(first ? u / p0 : (u - p0) / (1.0f - p0), 0x1.fffffep-1f);  /* rounding may reach 1 */
#endif
    }
    *pdf = p;
    return lp->nodes[j].meta.x;
}

/* The probability with which light_tree_descend reaches leaf node `leaf` at x. */
inline float light_tree_leaf_pdf(const LightPick* lp, int leaf, float3 x, float3 n)
{
    uint path = (uint)leaf + 1u;
    float p = 1.0f;
    int j = 0;
    for (int d = 30 - (int)clz(path); d >= 0; --d) {
#ifndef TEST_TREE_EXACT_BRANCH_PDF  /* negative control of the tests only (tests/bias_controls.py): branches down */
        if (lp->nodes[j].meta.w <= LIGHT_TREE_EXACT_AT && light_tree_exact_here(lp, j, x))
            return p * light_tree_exact_pdf(lp, j, leaf, x, n);
#endif
        int c = 2 * j + 1;
        float p0 = light_tree_branch(lp->nodes, c, x, n);
        if ((path >> d) & 1u) {
            p *= 1.0f - p0;
            j = c + 1;
        } else {
            p *= p0;
            j = c;
        }
    }
    return p;
}

/* A light for the random word `bits` at x: from the tree with probability local_share (light_tree_local_share at
 * x), else a distant one (light_distant_pick; total: the distant lights' weighed shares at n). The word seeds the
 * descent's stream or, `stratified` (a Sobol word), is the one uniform of the stratified descent, its share below
 * local_share the tree's, the rest the distant lights'. */
inline int light_tree_pick(const LightPick* lp, float3 x, float3 n, uint bits, int stratified, float* memo,
                           float local_share, float total, float* pdf)
{
    uint state = bits;
    float u = stratified ? (float)(bits >> 8) * (1.0f / 16777216.0f) : rng_next(&state);
    if (lp->distant_count == 0 || u < local_share) {
        float p;
        float v = fmin_f(u / local_share, 0x1.fffffep-1f);
        int light = light_tree_descend(lp, x, n, state, v, stratified, memo, &p);
        *pdf = p * local_share;
        return light;
    }
    u = stratified ? fmin_f((u - local_share) / (1.0f - local_share), 0x1.fffffep-1f) : rng_next(&state);
    float share;
    int k = light_distant_pick(lp, n, total, u, &share);
    *pdf = (1.0f - local_share) * share;
    return lp->distant[k].s0;
}

/* The candidates' lights and pick pdfs for n random words (direct/ris.h, as light_array_lights does for slots). */
inline void light_tree_lights(const LightPick* lp, float3 x, float3 n, const uint* bits, int count, int stratified,
                              int* light, float* pdf)
{
    float memo[LIGHT_TREE_MEMO];
    for (int j = 0; j < LIGHT_TREE_MEMO; ++j) memo[j] = -1.0f;
    float total = light_distant_total(lp, n), local_share = light_tree_local_share(lp, x, n, total);
    for (int k = 0; k < count; ++k)
        light[k] = light_tree_pick(lp, x, n, bits[k], stratified, memo, local_share, total, &pdf[k]);
}
#endif

/* The lights of `count` candidates at x (normal n) and their pick pdfs, from the tree or from the light array
 * (then bits[k] is a slot); `stratified`: the words are Sobol words (the tree's descent keeps their strata). */
inline void light_pick_lights(const LightPick* lp, float3 x, float3 n, const uint* bits, int count, int stratified,
                              int* light, float* pdf)
{
#ifdef HAS_PICK_TABLE
    if (lp->table_n > 0) {
        for (int k = 0; k < count; ++k) light[k] = pick_table_light(lp->table, lp->table_n, bits[k], &pdf[k]);
        return;
    }
#endif
#ifdef HAS_LIGHT_TREE
    if (lp->tree) {
        light_tree_lights(lp, x, n, bits, count, stratified, light, pdf);
        return;
    }
#endif
    light_array_lights(lp->slots, lp->light_pdf, bits, count, light, pdf);
}

/* The probability with which the pick of lp chooses light `light` at x (normal n). */
inline float light_pick_pdf(const LightPick* lp, int light, float3 x, float3 n)
{
#ifdef HAS_PICK_TABLE
    if (lp->table_n > 0) return pick_table_pdf(lp->table, lp->table_n, light);
#endif
#ifdef HAS_LIGHT_TREE
    if (lp->tree) {
        int2 info = lp->info[light];
#ifdef TEST_DISTANT_PICK_FIXED_PDF  /* negative control of the tests only (tests/bias_controls.py): the fixed shares */
        if (info.x < 0) return (1.0f - lp->p_local) * as_float(lp->distant[info.y].s1);
        return lp->p_local * light_tree_leaf_pdf(lp, info.x, x, n);
#endif
        float total = light_distant_total(lp, n), local_share = light_tree_local_share(lp, x, n, total);
        if (info.x < 0) return (1.0f - local_share) * light_distant_share(lp, info.y, n, total);
        return local_share * light_tree_leaf_pdf(lp, info.x, x, n);
    }
#endif
    return lp->light_pdf[light];
}

#endif
