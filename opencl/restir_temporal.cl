/* ReSTIR pass 4: merge the pixel's new reservoir with last frame's reservoir of the same surface (found by
 * reprojection), its M capped. The target is re-evaluated with this frame's lights, so a light switched off
 * stops contributing at once. bias_correction: BIAS_NONE plain M-weighted merge (biased), BIAS_Z_COUNT 1/Z,
 * BIAS_PAIRWISE pairwise MIS with k = 1, i.e. the balance heuristic of the two inputs (restir_pairwise.h). The
 * previous input's target p_prev is evaluated at last frame's surface with this frame's lights and geometry;
 * lights_static: the light records are last frame's, so p_prev of last frame's own sample is the target it stored
 * (computed at that surface with those records) and is not evaluated again. */

__kernel void restir_temporal(const __global GSample* gbuf, const __global GSample* prev_gbuf,
                              const __global BVHNode* nodes, const __global Tri* tris, const __global Light* lights,
                              const __global Reservoir* current, const __global Reservoir* previous,
                              __global Reservoir* out, volatile __global int* guards, FrameParams frame_params,
                              TemporalParams params)
{
    const TemporalParams p = params;
    const int width = frame_params.width, height = frame_params.height;
    const int bias_correction = p.bias_correction, visibility_reuse = p.visibility_reuse;
    const int lights_static = p.lights_static;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    Reservoir c = current[i];
    Surface s = surface_load(gbuf, i);
    if (!s.valid) { out[i] = c; return; }
    int j = reproject_pixel(gbuf, prev_gbuf, x, y, width, height, p.depth_tolerance, p.normal_cos);
    if (j < 0) { out[i] = c; return; }
    Reservoir q = previous[j];
    q.M = fmin_f(q.M, p.m_cap);
    if (!finite_f(q.W) || !finite_f(q.M)) { guard_count(guards, GUARD_NONFINITE_RESERVOIR); out[i] = c; return; }
    uint rng = rng_seed((uint)i, (uint)p.frame, (uint)p.seed, 4u);
    Reservoir r;
    res_init(&r);
    LightEval e, chosen;  /* chosen: the evaluation at s of last frame's sample, when it is picked */
    Surface sp = surface_load(prev_gbuf, j);
    bool from_prev;
    if (bias_correction == BIAS_PAIRWISE) {
        PairwiseMis mis = pairwise_begin(&c, 1.0f);
        float own = !(q.light >= 0 && q.W > 0.0f) ? 0.0f
                    : lights_static ? q.target : target_of(&sp, lights, q.light, q.u, q.v, &e);
        from_prev = pairwise_neighbour(&mis, &r, &s, &sp, &c, &q, own, nodes, tris, lights, visibility_reuse,
                                       rng_next(&rng), &chosen);
        if (pairwise_canonical(&mis, &r, &c, rng_next(&rng))) from_prev = false;
        res_finalize(&r, 1.0f);
    } else {
        res_update(&r, c.light, c.u, c.v, c.target * c.W * c.M, c.target, rng_next(&rng), c.M);
        float tq = q.light >= 0 ? target_of(&s, lights, q.light, q.u, q.v, &e) : 0.0f;
        from_prev = res_merge(&r, &q, tq, rng_next(&rng));
        if (from_prev) chosen = e;
        float norm = r.M;
        if (bias_correction == BIAS_Z_COUNT && r.light >= 0) {
            norm = c.M;
            /* last frame's reservoir supports its own sample (W > 0: p-hat > 0 and, with visibility reuse, visible
             * there); any other sample is tested at the previous surface */
            if ((from_prev && q.W > 0.0f) || in_support(&sp, nodes, tris, lights, r.light, r.u, r.v, visibility_reuse))
                norm += q.M;
        }
        res_finalize(&r, norm);
    }
    /* as in restir_spatial.cl: only a sample taken from last frame needs its shadow ray here */
    if (visibility_reuse && bias_correction != BIAS_NONE && r.W > 0.0f && from_prev
        && !visible(nodes, tris, &s, &chosen))
        r.W = 0.0f;
    out[i] = r;
}
