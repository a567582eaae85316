/* ReSTIR pass 2: per pixel, RIS over `candidates` light samples drawn from the light array (or from the pixel's
 * presampled light tile, lights/tiles.h, or from the light tree, lights/tree.h) into a reservoir
 * (restir/candidates.h); with visibility reuse, a chosen sample that is occluded gets W = 0 (its M stays). */

__kernel void restir_initial(const __global GSample* gbuf, const __global GlossySample* glossy, const __global BVHNode* nodes, const __global Tri* tris,
                             const __global Light* lights, const __global int* slots, const __global float* light_pdf,
                             const __global LightTreeNode* tree_nodes, const __global int2* tree_info,
                             const __global int8* tree_distant,
                             const __global Light* tile_rec, const __global int2* tile_info,
                             const __global int* tri_light, __global Reservoir* out, FrameParams frame_params, InitialParams params)
{
    const InitialParams p = params;
    const int pixel_count = frame_params.pixels;
    const int light_count = p.sampler.light_count;
    const int visibility_reuse = p.visibility_reuse;
    int i = get_global_id(0);
    if (i >= pixel_count) return;
    Surface s = surface_load(gbuf, glossy, i);
    Reservoir r;
    res_init(&r);
    if (s.valid && light_count > 0) {
        uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 3u);
        LightEval chosen;  /* the evaluation of the picked candidate, for its shadow ray */
        Qmc q = qmc_stream(frame_params.qmc, frame_params.qmc_index, frame_params.qmc_key, (uint)i);
        r = restir_candidates(&s, i, lights, slots, light_pdf, tree_nodes, tree_info, tree_distant, tile_rec,
                              tile_info, nodes, tris, tri_light, p.sampler, p.candidates, frame_params.sample,
                              frame_params.seed, &q, &rng, &chosen);
        /* W > 0: a candidate with target > 0 was picked, and chosen holds its evaluation */
        if (visibility_reuse && r.W > 0.0f && !visible(nodes, tris, &s, &chosen)) r.W = 0.0f;
    }
    out[i] = r;
}
