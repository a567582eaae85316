/* The path pass (Settings.max_bounces > 0): light that reaches the primary hit after bouncing, added to this frame's
 * sample. From the pixel's G-buffer surface the path samples the BSDF, traces the ray and, at every vertex it
 * reaches, estimates the direct light there by NEE (path/nee.h) while the rays it traces count the emitters they meet
 * (path/emitters.h), the two combined by MIS (path/mis.h); the ray from the primary hit meets only light that the
 * direct estimators already have, so its emitters are left out.
 *
 * Cycles' Light Paths: a path that has scattered n times carries light of n bounces; Max Bounces B keeps n <= B
 * (total), and Diffuse / Glossy bound the scatterings of each kind (the BSDF's part drawn: Lambert or a lobe). A
 * scatter past a bound still counts the emitters its ray meets (they are light of the bounces before it) and ends
 * the path. Russian roulette from bounce min_bounces + 2 on survives with q = min(1, sqrt(max throughput)) and divides
 * by q (Cycles' continuation probability); Clamp Indirect scales a contribution whose rgb sum exceeds 3x the clamp
 * down to it (Cycles' per-contribution clamp). The result, with its own guard, also goes to `indirect` (a pass). */

inline float3 path_clamp(float3 c, float clamp)
{
    float sum = c.x + c.y + c.z;
    return (clamp > 0.0f && sum > 3.0f * clamp) ? c * (3.0f * clamp / sum) : c;
}

__kernel void path_trace(const __global GSample* gbuf, const __global GlossySample* glossy,
                         const __global BVHNode* nodes, const __global Tri* tris, const __global Material* materials,
                         const __global TriAttr* tri_attr, const __global ObjectInfo* objects,
                         const __global Closure* closures, const __global TexNode* tex_nodes,
                         const __global TexImage* tex_images, const __global float4* texels,
                         const __global float* ggx_tables, const __global Light* lights, const __global int* slots,
                         const __global float* light_pdf, const __global LightTreeNode* tree_nodes,
                         const __global int2* tree_info, const __global int2* tree_distant,
                         const __global int* tri_light, volatile __global int* guards, __global float4* sample,
                         __global float4* indirect, FrameParams frame_params, PathParams params)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    const SceneSurfaces sc = {tris, materials, tri_attr, objects, closures, tex_nodes, tex_images, texels, ggx_tables};
    const LightPick lp = light_pick_source(slots, light_pdf, tree_nodes, tree_info, tree_distant, params.sampler);
    const BsdfSource hits = bsdf_source(params.sampler);
    const bool nee = params.sampler.light_count > 0;
    Surface s = surface_load(gbuf, glossy, i);
    float3 L = (float3)(0.0f), T = (float3)(1.0f);
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 8u);
    /* still RIS renders: the BSDF directions and the NEE samples from the pixel's Sobol sequence (sampling/qmc.h) */
    const Qmc q = qmc_stream(frame_params.qmc, frame_params.qmc_index, frame_params.qmc_key, (uint)i);
    int bounces = 0, diffuse = 0, gloss = 0;
    while (s.valid) {
        float u0 = rng_next(&rng), u1 = rng_next(&rng), u_rr = rng_next(&rng);
        if (q.on) {
            float2 u = qmc_pair(&q, QMC_PATH_BSDF(bounces));
            u0 = u.x;
            u1 = u.y;
        }
        /* Russian roulette at this vertex, before it scatters */
        if (bounces > params.min_bounces + 1) {
            float q = fmin_f(sqrt(fmax_f(T.x, fmax_f(T.y, T.z))), 1.0f);
            if (!(u_rr < q)) break;
#ifndef PATH_ROULETTE_WITHOUT_DIVIDE  /* defined only by the negative control of tests/render/test_paths.py */
            T /= q;
#endif
        }
        float3 wi;
        float pdf;
        int part;
        float3 f = bsdf_sample_part(&s, s.wo, u0, u1, &wi, &pdf, &part);
        float cos_n = dot3(s.n, wi);
        if (!(pdf > 0.0f) || !(cos_n > 0.0f)) break;
        const float3 T_before = T;
        T *= f * (cos_n / pdf);
        ++bounces;
        if (part < 0) ++diffuse; else ++gloss;
        bool last = bounces > params.max_bounces || diffuse > params.max_diffuse || gloss > params.max_glossy;
        Hit h = trace_closest(nodes, tris, path_ray_origin(tris, &s, wi), wi, INFINITY);
        if (bounces > 1 && nee)
            L += path_clamp(T_before * path_emitters(&s, wi, h, lights, tri_light, &lp, hits),
                            params.clamp_indirect);
        if (last || h.prim < 0 || !(fmax_f(T.x, fmax_f(T.y, T.z)) > 0.0f)) break;
        s = path_vertex(&sc, h, wi);
        if (nee)
            L += path_clamp(T * path_nee(&s, lights, &lp, params.sampler.slot_count, hits, nodes, tris,
                                         params.light_threshold, &rng, &q, QMC_PATH_LIGHT(bounces)),
                            params.clamp_indirect);
    }
    L = guard_finite(L, guards, GUARD_NONFINITE_SAMPLE);
    indirect[i] = (float4)(L, 1.0f);
    sample[i].xyz += L;
}
