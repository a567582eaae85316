/* The light tree's small subtrees (the host's mirror and why: lights/tree_exact.py): a descent that reaches a node
 * with at most LIGHT_TREE_EXACT lights below it (meta.w) picks one of them directly, light l with probability
 *     p(l | j) = (1 - F) (N_l / sum N + R_l / sum R) / 2 + F phi_l / phi_j,
 * N and R the importance of l's leaf at its box's nearest point and farthest corner (light_tree_importance; one share
 * alone where the other sum is 0 or not finite, the power share where both are), phi the power, F LIGHT_TREE_FLOOR.
 * A node's bound cannot say where in its box its lights are; a light's own bound can. The leaves below j are walked
 * level by level, left to right (lights/tree_exact.py subtree_leaf_nodes); the pick and light_tree_exact_pdf
 * compute p(l | j) with the same arithmetic. */
#ifndef RESTIRCL_LIGHT_TREE_EXACT_H
#define RESTIRCL_LIGHT_TREE_EXACT_H

/* The largest node picked exactly; tests may build another (TEST_LIGHT_TREE_EXACT, at most LIGHT_TREE_EXACT, the size
 * of the pick's array below: 1 makes every pick descend by branches to its leaf, tests/render/test_path_descent.py). */
#ifdef TEST_LIGHT_TREE_EXACT
#if TEST_LIGHT_TREE_EXACT > LIGHT_TREE_EXACT
#error "TEST_LIGHT_TREE_EXACT above LIGHT_TREE_EXACT overflows light_tree_exact_pick's array"
#endif
#define LIGHT_TREE_EXACT_AT TEST_LIGHT_TREE_EXACT
#else
#define LIGHT_TREE_EXACT_AT LIGHT_TREE_EXACT
#endif

/* The exact pick is taken only where x is near the node: its distance to the node's box at most LIGHT_TREE_NEAR
 * times the box's diagonal (codes.h, from lights/tree_exact.py NEAR: why and its value). Farther, the children's bounds already
 * follow their lights' shares and the descent goes on branching (and tests the next small node again). */
#ifdef TEST_LIGHT_TREE_NEAR
#define LIGHT_TREE_NEAR_AT TEST_LIGHT_TREE_NEAR
#else
#define LIGHT_TREE_NEAR_AT LIGHT_TREE_NEAR  /* codes.h, from lights/tree_exact.py NEAR */
#endif

/* Whether node j (of at most LIGHT_TREE_EXACT_AT lights) picks exactly at x: x near its box (above). */
inline bool light_tree_exact_here(const LightPick* lp, int j, float3 x)
{
    float3 lo = lp->nodes[j].lo.xyz, hi = lp->nodes[j].hi.xyz, diag = hi - lo;
    float3 d = (float3)(fmax_f(fmax_f(lo.x - x.x, x.x - hi.x), 0.0f), fmax_f(fmax_f(lo.y - x.y, x.y - hi.y), 0.0f),
                        fmax_f(fmax_f(lo.z - x.z, x.z - hi.z), 0.0f));
    return dot3(d, d) <= LIGHT_TREE_NEAR_AT * LIGHT_TREE_NEAR_AT * dot3(diag, diag);
}

/* The importances at x of the leaves below node j, in the order lights/tree_exact.py subtree_leaf_nodes walks them
 * (level by level, left to right), into imp; returns how many. Four at a time while a level's run has four left
 * (light_tree_importance4), the rest one by one. */
inline int light_tree_exact_importances(const LightPick* lp, int j, float3 x, float3 n, float2* imp)
{
    int last = 2 * lp->leaves - 2, inner = lp->leaves - 1, k = 0;
    for (int first = j, width = 1; first <= last; first = 2 * first + 1, width *= 2) {
        int m = max(first, inner), end = min(first + width - 1, last);
        for (; m + 3 <= end; m += 4, k += 4) {
            float4 nr, fr;
            light_tree_importance4(&lp->nodes[m], x, n, &nr, &fr);
            imp[k] = (float2)(nr.s0, fr.s0);
            imp[k + 1] = (float2)(nr.s1, fr.s1);
            imp[k + 2] = (float2)(nr.s2, fr.s2);
            imp[k + 3] = (float2)(nr.s3, fr.s3);
        }
        for (; m <= end; ++m) imp[k++] = light_tree_importance(&lp->nodes[m], x, n);
    }
    return k;
}

/* Their sums: .x at the nearest point, .y at the farthest corner. */
inline float2 light_tree_exact_sum(const float2* imp, int count)
{
    float2 sum = (float2)(0.0f);
    for (int k = 0; k < count; ++k) sum += imp[k];
    return sum;
}

/* p(l | j) of the light of leaf node m below j, of importance imp at x, given the sums (light_tree_exact_sum) and
 * j's power. */
inline float light_tree_exact_share(const LightPick* lp, int m, float2 imp, float2 sum, float phi_j)
{
    float pw = lp->nodes[m].lo.w / phi_j;
    float near = sum.x > 0.0f && finite_f(sum.x) ? imp.x / sum.x : -1.0f;
    float far = sum.y > 0.0f && finite_f(sum.y) ? imp.y / sum.y : -1.0f;
    return light_pick_floored(light_tree_near_far(near, far, pw), pw);
}

/* The leaf node below j for the uniform u in [0, 1) (*p: its p(l | j)): the first whose running sum of p(l | j)
 * passes u, the last leaf where rounding leaves u beyond them all. */
inline int light_tree_exact_pick(const LightPick* lp, int j, float3 x, float3 n, float u, float* p)
{
    float2 imp[LIGHT_TREE_EXACT];
    int count = light_tree_exact_importances(lp, j, x, n, imp);
    float2 sum = light_tree_exact_sum(imp, count);
    float phi_j = lp->nodes[j].lo.w;
    float run = 0.0f;
    int chosen = -1, k = 0, last = 2 * lp->leaves - 2, inner = lp->leaves - 1;
    for (int first = j, width = 1; first <= last; first = 2 * first + 1, width *= 2)
        for (int m = max(first, inner); m < first + width && m <= last; ++m) {
            float q = light_tree_exact_share(lp, m, imp[k++], sum, phi_j);
            run += q;
            *p = q;
            chosen = m;
            if (u < run) return m;
        }
    return chosen;
}

/* p(l | j) of leaf node `leaf` below node j at x: the pick's arithmetic, its importance the one of the same pass. */
inline float light_tree_exact_pdf(const LightPick* lp, int j, int leaf, float3 x, float3 n)
{
    float2 imp[LIGHT_TREE_EXACT];
    int count = light_tree_exact_importances(lp, j, x, n, imp);
    float2 sum = light_tree_exact_sum(imp, count);
    float phi_j = lp->nodes[j].lo.w;
    int k = 0, last = 2 * lp->leaves - 2, inner = lp->leaves - 1;
    for (int first = j, width = 1; first <= last; first = 2 * first + 1, width *= 2) {
        int m = max(first, inner), end = min(first + width - 1, last);
        if (leaf >= m && leaf <= end) return light_tree_exact_share(lp, leaf, imp[k + leaf - m], sum, phi_j);
        k += max(end - m + 1, 0);
    }
    return 0.0f;  /* leaf is not below j */
}

#endif
