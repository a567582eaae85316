/* Direct lighting with one light sample per pixel, without reuse: the samplers `uniform`, `light_array` and
 * `ris` (candidates from the light array or the presampled light tiles; optionally one more, BSDF-sampled
 * direction combined with it by MIS, direct/bsdf_mis.h), and the exhaustive `reference` (every light, one sample each).
 * One shadow ray per light sample. Each contribution of direct light is clamped by Clamp Direct on its own
 * (direct/clamp.h) and, where light passes are on, split into them (film/light_passes.h). */

/* One light sample (light l at (u, v), drawn with probability density pdf) added to the pixel's direct light, its
 * light passes and its light group: its unshadowed contribution over pdf times the transmittance to it. */
inline void direct_add_light_sample(const Surface* s, const __global BVHNode* nodes, const __global Tri* tris,
                                    const __global Light* lights, int l, float2 uv, float pdf, float clamp,
                                    float3* c, DirectSplit* pass, GroupLight* gl)
{
    LightEval e;
    Shadow v = 0.0f;
    if (pdf > 0.0f && surface_light_eval(s, &lights[l], uv.x, uv.y, &e)
        && light_links(lights, &lights[l], s, &e) && shadow_any(v = transmittance(nodes, tris, s, &e))) {
        float3 x = direct_contribution(s, e.wi, unshadowed_contrib(s, &e) / pdf * v, clamp, pass);
        *c += x;
        GROUP_ADD(gl, lights, &lights[l], x);
    }
}

__kernel void shade_direct(const __global GSample* gbuf, const __global GlossySample* glossy, const __global BVHNode* nodes, const __global Tri* tris,
                           const __global Light* lights, const __global int* slots, const __global float* light_pdf,
                           const __global LightTreeNode* tree_nodes, const __global int2* tree_info,
                           const __global int8* tree_distant,
                           const __global Light* tile_rec, const __global int2* tile_info,
                           const __global int* tri_light, const __global ushort* pick_table,
                           volatile __global int* guards, __global float4* out, __global float4* light_passes,
                           FrameParams frame_params, ShadeParams params)
{
    const int pixel_count = frame_params.pixels;
    const uint frame = frame_params.sample, seed = frame_params.seed;
    const int light_count = params.sampler.light_count, slot_count = params.sampler.slot_count;
    const int tile_count = params.sampler.tile_count, tile_size = params.sampler.tile_size;
    const int method = params.method, candidates = params.candidates;
    int i = get_global_id(0);
    if (i >= pixel_count) return;
    Surface s = surface_load(gbuf, glossy, i);
    const float clamp = params.clamp_direct, k_seen = clamp_scale(gbuf[i].emission.xyz, clamp);
    float3 c = gbuf[i].emission.xyz * k_seen;
    DirectSplit pass = direct_split_zero();  /* the light passes' direct light */
    GroupLight gl;  /* ... and the light groups' (film/light_groups.h) */
    group_light_clear(&gl);
    if (s.valid && light_count > 0) {
        uint rng = rng_seed((uint)i, frame, seed, 1u);
        LightEval e;
        if (method == METHOD_RIS) {
            Reservoir r;
            res_init(&r);
            LightPick lp = light_pick_source(slots, light_pdf, tree_nodes, tree_info, tree_distant, params.sampler);
            light_pick_use_table(&lp, pick_table, params.sampler, i);
            RisSource src = ris_source(slot_count, tile_count, tile_size, i, frame, seed);
            BsdfSource bsdf = bsdf_source(params.sampler);
            bsdf.mis_sample = params.bsdf_mis_sample;
            Qmc q = qmc_stream(frame_params.qmc, frame_params.qmc_index, frame_params.qmc_key, (uint)i);
            ris_candidates(&s, lights, &lp, tile_rec, tile_info, src, candidates, nodes, tris, tri_light,
                           bsdf, &rng, &q, &r, &e);
            res_finalize(&r, r.M);
            /* W > 0: a candidate of target > 0 was picked, and e holds its evaluation */
            Shadow v = 0.0f;  /* the transmittance: 1 or 0 but through transparent surfaces and thin walls */
            if (r.W > 0.0f && shadow_any(v = transmittance(nodes, tris, &s, &e))) {
                float3 x = direct_contribution(&s, e.wi, unshadowed_contrib(&s, &e) * r.W * v, clamp, &pass);
                c += x;
                GROUP_ADD(&gl, lights, &lights[r.light], x);
            }
            if (bsdf.mis_sample) {  /* the lights its ray meets, as one contribution */
                float3 wi;
                GroupLight mg;
                group_light_clear(&mg);
                float3 m = bsdf_mis_sample(&s, lights, &lp, nodes, tris, tri_light, bsdf, &rng, &q, &wi, &mg);
                group_light_merge(&gl, &mg, (float3)(clamp_scale(m, clamp)));
                c += direct_contribution(&s, wi, m, clamp, &pass);
            }
        } else {
            float2 uv;
            float pdf;
            int light = light_draw(method == METHOD_UNIFORM, lights, light_count, slots, slot_count, light_pdf, s.x, &rng, &uv, &pdf);
#ifdef TEST_PICK_PDF_SCALE  /* negative controls of the tests only (tests/bias_controls.py): a wrong pdf */
            pdf *= TEST_PICK_PDF_SCALE;
#endif
            direct_add_light_sample(&s, nodes, tris, lights, light, uv, pdf, clamp, &c, &pass, &gl);
        }
    }
    direct_passes(light_passes, pixel_count, i, &pass, k_seen);
    light_groups_add(light_passes, pixel_count, i, &gl, k_seen);
    out[i] = (float4)(guard_finite(c, guards, GUARD_NONFINITE_SAMPLE), film_coverage(gbuf[i]));
}

__kernel void shade_reference(const __global GSample* gbuf, const __global GlossySample* glossy, const __global BVHNode* nodes, const __global Tri* tris,
                              const __global Light* lights, volatile __global int* guards, __global float4* out,
                              __global float4* light_passes, FrameParams frame_params, ShadeParams params)
{
    const int pixel_count = frame_params.pixels;
    const uint frame = frame_params.sample, seed = frame_params.seed;
    const int light_count = params.sampler.light_count;
    int i = get_global_id(0);
    if (i >= pixel_count) return;
    Surface s = surface_load(gbuf, glossy, i);
    const float clamp = params.clamp_direct, k_seen = clamp_scale(gbuf[i].emission.xyz, clamp);
    float3 c = gbuf[i].emission.xyz * k_seen;
    DirectSplit pass = direct_split_zero();
    GroupLight gl;
    group_light_clear(&gl);
    if (s.valid) {
        uint rng = rng_seed((uint)i, frame, seed, 2u);
        for (int l = 0; l < light_count; ++l) {
            float r0 = rng_next(&rng), r1 = rng_next(&rng);
            float pdf;
            float2 uv = light_sample(&lights[l], s.x, r0, r1, &pdf);
#ifdef TEST_REFERENCE_PDF_SCALE  /* negative control of the tests only (tests/bias_controls.py): a wrong pdf */
            pdf *= TEST_REFERENCE_PDF_SCALE;
#endif
            direct_add_light_sample(&s, nodes, tris, lights, l, uv, pdf, clamp, &c, &pass, &gl);
        }
    }
    direct_passes(light_passes, pixel_count, i, &pass, k_seen);
    light_groups_add(light_passes, pixel_count, i, &gl, k_seen);
    out[i] = (float4)(guard_finite(c, guards, GUARD_NONFINITE_SAMPLE), film_coverage(gbuf[i]));
}
