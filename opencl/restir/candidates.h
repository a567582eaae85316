/* A pixel's own RIS reservoir (direct/ris.h), finalised: `candidates` light candidates and the sampler's BSDF
 * candidates, drawn from the proposal the sampler names (the light array or tree, or the pixel's light tile). One code
 * path for ReSTIR's initial reservoirs (restir/initial.cl) and the extra candidates of a lonely fresh pixel
 * (restir/spatial.cl), so that both draw from the same proposal. *chosen: the picked candidate's evaluation, valid when
 * W > 0, for the caller's shadow ray. */
#ifndef RESTIRCL_RESTIR_CANDIDATES_H
#define RESTIRCL_RESTIR_CANDIDATES_H

inline Reservoir restir_candidates(const Surface* s, int i, const __global Light* lights, const __global int* slots,
                                   const __global float* light_pdf, const __global LightTreeNode* tree_nodes,
                                   const __global int2* tree_info, const __global int8* tree_distant,
                                   const __global Light* tile_rec, const __global int2* tile_info,
                                   const __global BVHNode* nodes, const __global Tri* tris,
                                   const __global int* tri_light, SamplerParams sampler, int candidates,
                                   uint frame, uint seed, const Qmc* q, uint* rng, LightEval* chosen)
{
    Reservoir r;
    res_init(&r);
    LightPick lp = light_pick_source(slots, light_pdf, tree_nodes, tree_info, tree_distant, sampler);
    RisSource src = ris_source(sampler.slot_count, sampler.tile_count, sampler.tile_size, i, frame, seed);
    ris_candidates(s, lights, &lp, tile_rec, tile_info, src, candidates, nodes, tris, tri_light,
                   bsdf_source(sampler), rng, q, &r, chosen);
    res_finalize(&r, r.M);
    return r;
}

#endif
