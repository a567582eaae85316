/* A lonely fresh pixel (restir/spatial.cl, first pass): the temporal pass found it no history and the spatial pass
 * no similar neighbour, so its reservoir holds this frame's own candidates alone and TAA, without history there
 * either, shows it at full weight; a rare candidate of large weight then makes a bright outlier. With
 * fresh_candidates = K > 0 such a pixel draws a second reservoir e of K light candidates (and the sampler's BSDF
 * candidates) from the same proposal (restir/candidates.h) and merges it with its own by their M: the two share the
 * pixel's target and proposal, so the constant weights M_c / (M_c + M_e) and M_e / (M_c + M_e) sum to 1 wherever
 * either reaches (unbiased), and M grows by e's M so that later reuse weighs the reservoir by all its candidates.
 * Whether a pixel is lonely depends on its history and its neighbours' surfaces, not on a sample (except with the
 * boiling filter on, which empties or forgets an outlier's reservoir so that it reads as fresh). With visibility
 * reuse, e's sample is shadow-tested when the merge picks it; c's is known visible where its W > 0. */
#ifndef RESTIRCL_RESTIR_LONELY_FRESH_H
#define RESTIRCL_RESTIR_LONELY_FRESH_H

inline Reservoir lonely_fresh(const Surface* s, int i, const Reservoir* c, const __global Light* lights,
                              const __global int* slots, const __global float* light_pdf,
                              const __global LightTreeNode* tree_nodes, const __global int2* tree_info,
                              const __global int8* tree_distant, const __global Light* tile_rec,
                              const __global int2* tile_info, const __global BVHNode* nodes, const __global Tri* tris,
                              const __global int* tri_light, const SpatialParams* p, FrameParams frame_params,
                              uint* rng)
{
    LightEval chosen;
    Qmc q = qmc_stream(0, 0u, 0u, (uint)i);  /* off: the initial pass's QMC points would repeat its candidates */
    Reservoir e = restir_candidates(s, i, lights, slots, light_pdf, tree_nodes, tree_info, tree_distant, tile_rec,
                                    tile_info, nodes, tris, tri_light, p->sampler, p->fresh_candidates,
                                    frame_params.sample, frame_params.seed, &q, rng, &chosen);
    Reservoir r;
    res_init(&r);
    res_update(&r, c->light, c->u, c->v, c->target * c->W * c->M, c->target, rng_next(rng), c->M);
    bool picked = res_update(&r, e.light, e.u, e.v, e.target * e.W * e.M, e.target, rng_next(rng), e.M);
#ifdef TEST_LONELY_FRESH_M_KEPT  /* negative control (tests/bias_controls.py): e's candidates not counted in M */
    r.M = c->M;
#endif
    res_finalize(&r, r.M);
    r.vis_age = picked ? 0 : c->vis_age;
    if (picked && p->visibility_reuse && r.W > 0.0f && !visible(nodes, tris, s, &chosen)) r.W = 0.0f;
    return r;
}

#endif
