/* The distant lights (suns, the world) beside the light tree, picked by what can reach the shading point: each
 * fixed share of the light array (the tree's, lp->p_local, and each distant light's) weighed by the bound of its
 * incidence cosine at the normal (a sun's: the cosine to its cone, 0 behind the surface; the world's: 1; the
 * tree's: 1 where the root's importance is above 0, lights/tree.h light_tree_importance), normalised, and mixed
 * with the fixed shares by LIGHT_TREE_FLOOR, as a branch is. The host's mirror, why, and the table's lanes:
 * lights/distant_pick.py. light_pick_pdf recomputes the same functions for the MIS weights, so that sampling and
 * weighting agree. */
#ifndef RESTIRCL_LIGHT_DISTANT_PICK_H
#define RESTIRCL_LIGHT_DISTANT_PICK_H

/* Row d's share of the light array weighed by its incidence bound at normal n (2 n: a surface that takes light
 * from both sides). */
inline float light_distant_importance(const __global int8* d, float3 n)
{
    int8 r = *d;
    float weight = as_float(r.s2), cos_half = as_float(r.s3);
    if (cos_half < -1.5f) return weight;  /* the world: some of it above every surface */
    float cos_i = dot3(n, (float3)(as_float(r.s4), as_float(r.s5), as_float(r.s6)));
    if (dot3(n, n) > 2.0f) cos_i = abs_f(0.5f * cos_i);
    float bound = light_tree_cos_sub(cos_i, sqrt(fmax_f(0.0f, 1.0f - cos_i * cos_i)), cos_half, as_float(r.s7)).x;
    return weight * fmax_f(bound, 0.0f);
}

/* The distant lights' summed importance at normal n. */
inline float light_distant_total(const LightPick* lp, float3 n)
{
    float total = 0.0f;
    for (int k = 0; k < lp->distant_count; ++k) total += light_distant_importance(&lp->distant[k], n);
    return total;
}

/* The probability of distant light k once the pick went to the distant lights (total: light_distant_total). */
inline float light_distant_share(const LightPick* lp, int k, float3 n, float total)
{
    float fixed = as_float(lp->distant[k].s1);
    if (!(total > 0.0f) || !finite_f(total)) return fixed;
    return (1.0f - LIGHT_TREE_FLOOR) * light_distant_importance(&lp->distant[k], n) / total + LIGHT_TREE_FLOOR * fixed;
}

/* The probability that a pick at x (normal n) descends the tree (total: light_distant_total at n). */
inline float light_tree_local_share(const LightPick* lp, float3 x, float3 n, float total)
{
    if (lp->distant_count == 0) return 1.0f;
    if (lp->leaves == 0) return 0.0f;
    float fixed = lp->p_local;
    float reach = light_tree_importance(&lp->nodes[0], x, n).x > 0.0f ? fixed : 0.0f;
    float share = light_tree_share(reach, total);
    float p = light_pick_floored(share >= 0.0f ? share : fixed, fixed);
    return clamp_f(p, LIGHT_TREE_MIN_BRANCH, 1.0f - LIGHT_TREE_MIN_BRANCH);
}

/* A distant light for the uniform u in [0, 1) at normal n; *share its light_distant_share. */
inline int light_distant_pick(const LightPick* lp, float3 n, float total, float u, float* share)
{
    int k = 0;
    float q = light_distant_share(lp, 0, n, total);
    while (k < lp->distant_count - 1 && !(u < q)) {
        u -= q;
        q = light_distant_share(lp, ++k, n, total);
    }
    *share = q;
    return k;
}

#endif
