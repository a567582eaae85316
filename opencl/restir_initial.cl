/* ReSTIR pass 2: per pixel, RIS over `candidates` light samples drawn from the light array into a reservoir;
 * with visibility reuse, a chosen sample that is occluded gets W = 0 (its M stays). */

#define INITIAL_BATCH 8

__kernel void restir_initial(const __global GSample* gbuf, int pixel_count,
                             const __global BVHNode* nodes, const __global Tri* tris,
                             const __global Light* lights, int light_count,
                             const __global int* slots, int slot_count, const __global float* light_pdf,
                             RestirParams p, int visibility_reuse, __global Reservoir* out)
{
    int i = get_global_id(0);
    if (i >= pixel_count) return;
    Surface s = surface_load(gbuf, i);
    Reservoir r;
    res_init(&r);
    if (s.valid && light_count > 0) {
        uint rng = rng_seed((uint)i, (uint)p.frame, (uint)p.seed, 3u);
        LightEval e, chosen;  /* chosen: the evaluation of the picked candidate, for its shadow ray */
        /* Candidates in batches of INITIAL_BATCH: first every random number and every read of the light array (slot,
         * pdf, the light record's type), then the evaluations. With a million lights each read is a cache miss; read
         * for a whole batch first, the misses overlap instead of each waiting behind the previous candidate's
         * evaluation (1e6 point lights: initial pass 91-95 -> 66-68 ms). The random numbers are drawn in the same
         * order as one candidate at a time (slot, r0, r1, resampling): the same samples. (OpenCL's prefetch() did
         * nothing on PoCL.) */
        for (int k0 = 0; k0 < p.candidates; k0 += INITIAL_BATCH) {
            int n = min(INITIAL_BATCH, p.candidates - k0);
            int light[INITIAL_BATCH];
            float r0[INITIAL_BATCH], r1[INITIAL_BATCH], rnd[INITIAL_BATCH], pick_pdf[INITIAL_BATCH];
            for (int k = 0; k < n; ++k) {
                light[k] = (int)rng_below(&rng, (uint)slot_count);  /* the slot, for now */
                r0[k] = rng_next(&rng);
                r1[k] = rng_next(&rng);
                rnd[k] = rng_next(&rng);
            }
            for (int k = 0; k < n; ++k) light[k] = slots[light[k]];
            int type[INITIAL_BATCH];  /* read here, so that each light record's line is on its way early */
            for (int k = 0; k < n; ++k) {
                pick_pdf[k] = light_pdf[light[k]];
                type[k] = light_type(&lights[light[k]]);
            }
            for (int k = 0; k < n; ++k) {
                float py;
                float2 uv = light_sample_typed(&lights[light[k]], type[k], s.x, r0[k], r1[k], &py);
                float pdf = pick_pdf[k] * py;
                float t = pdf > 0.0f ? target_of(&s, lights, light[k], uv.x, uv.y, &e) : 0.0f;
                if (res_update(&r, light[k], uv.x, uv.y, t / pdf, t, rnd[k], 1.0f)) chosen = e;
            }
        }
        res_finalize(&r, r.M);
        /* W > 0: a candidate with target > 0 was picked, and chosen holds its evaluation */
        if (visibility_reuse && r.W > 0.0f && !visible(nodes, tris, &s, &chosen)) r.W = 0.0f;
    }
    out[i] = r;
}
