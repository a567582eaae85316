/* ReSTIR GI pass 1 (animation and viewport frames with Max Bounces > 0 and gi_reuse): the pixel's initial sample.
 * From the G-buffer's surface x0 one BSDF sample (density p in solid angle) finds the secondary vertex x1; the path
 * then walks on from x1 (path/walk.h: NEE there, further bounces, the emitters their rays meet) and what it gathers
 * is the radiance L_o leaving x1 towards x0. The reservoir holds (x1, its geometric normal facing x0, L_o) with
 * M = 1, target p-hat = luminance(f cos L_o) and W = 1 / p (RIS over one candidate). A ray that escapes, or meets
 * only light the direct estimators have (the emitters of the ray from x0), leaves an empty reservoir of M = 1.
 *
 * The walk from x1 starts with throughput 1: its Russian roulette and bounce limits see the path from x1 on, which
 * is the same whichever visible point it is reused at (x0's own scatter enters only the clamp, as the contribution
 * reaches this pixel), so that a sample moved to another pixel is a sample of the same distribution there. */

__kernel void gi_initial(const __global GSample* gbuf, const __global GlossySample* glossy,
                         const __global BVHNode* nodes, const __global Tri* tris, const __global Material* materials,
                         const __global TriAttr* tri_attr, const __global ObjectInfo* objects,
                         const __global Closure* closures, const __global TexNode* tex_nodes,
                         const __global TexImage* tex_images, const __global float4* texels,
                         const __global float* ggx_tables, const __global Light* lights, const __global int* slots,
                         const __global float* light_pdf, const __global LightTreeNode* tree_nodes,
                         const __global int2* tree_info, const __global int8* tree_distant,
                         const __global int* tri_light, volatile __global int* guards, __global GIReservoir* out,
                         FrameParams frame_params, PathParams params)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    const SceneSurfaces sc = {tris, materials, tri_attr, objects, closures, tex_nodes, tex_images, texels, ggx_tables};
    const LightPick lp = light_pick_source(slots, light_pdf, tree_nodes, tree_info, tree_distant, params.sampler);
    const PathScene ps = {&sc, nodes, lights, tri_light, &lp, bsdf_source(params.sampler), &params};
    const Qmc q = qmc_stream(0, 0u, 0u, (uint)i);  /* random numbers: reuse is for animation frames */
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 12u);
    GIReservoir r;
    gi_res_init(&r);
    r.M = 1.0f;
    Surface s = surface_load(gbuf, glossy, i);
    float u0 = rng_next(&rng), u1 = rng_next(&rng);
    float3 wi = (float3)(0.0f);
    float pdf = 0.0f;
    int part = -1;
    float3 f = s.valid ? bsdf_sample_part(&s, s.wo, u0, u1, &wi, &pdf, &part) : (float3)(0.0f);
    float cos_n = s.valid ? dot3(s.n, wi) : 0.0f;
    Hit h;
    h.prim = -1;
    if (pdf > 0.0f && cos_n > 0.0f && params.max_bounces > 0)
        h = trace_closest(nodes, tris, path_ray_origin(tris, &s, wi), wi, INFINITY);
    if (s.valid && h.prim >= 0 && pdf > 0.0f && cos_n > 0.0f) {
        PathState st = {path_vertex(&sc, h, wi), (float3)(1.0f), f * (cos_n / pdf), 1, part < 0, part >= 0};
        if (st.diffuse <= params.max_diffuse && st.gloss <= params.max_glossy) {
            r.pos = (float4)(st.s.x, 0.0f);
            r.normal = (float4)(st.s.ng, 0.0f);
            float3 Lo = path_vertex_light(&ps, &st, &rng, &q);
            Lo += path_walk(&ps, &st, &rng, &q);
            if (!finite3_f(Lo)) {
                guard_count(guards, GUARD_NONFINITE_SAMPLE);
                Lo = (float3)(0.0f);
            }
            float t = luminance(f * (cos_n * Lo));
            if (t > 0.0f && finite_f(t) && finite_f(1.0f / pdf)) {
                r.radiance = (float4)(Lo, 0.0f);
                r.target = t;
                r.w_sum = t / pdf;
                r.W = 1.0f / pdf;
            }
        }
    }
    out[i] = r;
}
