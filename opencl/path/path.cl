/* The path pass (Settings.max_bounces > 0): light that reaches the primary hit after bouncing, added to this frame's
 * sample. From the pixel's G-buffer surface the path walks (path/walk.h): it samples the BSDF, traces the ray and, at
 * every vertex it reaches, estimates the direct light there by NEE (path/nee.h) while the rays it traces count the
 * emitters they meet (path/emitters.h), the two combined by MIS (path/mis.h), within Cycles' Light Paths. The result,
 * with its own guard, also goes to `indirect` (a pass) and, where light passes are on, to Diffuse or Glossy
 * Indirect. Animation and viewport frames with ReSTIR GI take the same walk from the secondary vertex instead
 * (restir_gi/initial.cl). */

__kernel void path_trace(const __global GSample* gbuf, const __global GlossySample* glossy,
                         const __global BVHNode* nodes, const __global Tri* tris, const __global Material* materials,
                         const __global TriAttr* tri_attr, const __global ObjectInfo* objects,
                         const __global Closure* closures, const __global TexNode* tex_nodes,
                         const __global TexImage* tex_images, const __global float4* texels,
                         const __global float* ggx_tables, const __global Light* lights, const __global int* slots,
                         const __global float* light_pdf, const __global LightTreeNode* tree_nodes,
                         const __global int2* tree_info, const __global int8* tree_distant,
                         const __global int* tri_light, volatile __global int* guards, __global float4* sample,
                         __global float4* indirect, __global float4* light_passes, FrameParams frame_params,
                         PathParams params)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    const SceneSurfaces sc = {tris, materials, tri_attr, objects, closures, tex_nodes, tex_images, texels, ggx_tables};
    const LightPick lp = light_pick_source(slots, light_pdf, tree_nodes, tree_info, tree_distant, params.sampler);
    const PathScene ps = {&sc, nodes, lights, tri_light, &lp, bsdf_source(params.sampler), &params};
    PathState st = {surface_load(gbuf, glossy, i), (float3)(1.0f), (float3)(1.0f), 0, 0, 0};
#ifdef HAS_TRANSMISSION  /* beside ReSTIR GI, which cannot reuse a path refracted at x0: only the pixels that transmit */
    if (params.split_glass && !(st.s.valid && surface_transmits(&st.s))) return;
#endif
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 8u);
    /* still RIS renders: the BSDF directions and the NEE samples from the pixel's Sobol sequence (sampling/qmc.h) */
    const Qmc q = qmc_stream(frame_params.qmc, frame_params.qmc_index, frame_params.qmc_key, (uint)i);
    float3 L = path_walk(&ps, &st, &rng, &q);
    L = guard_finite(L, guards, GUARD_NONFINITE_SAMPLE);
    indirect[i] = (float4)(L, 1.0f);
    sample[i].xyz += L;
#ifdef HAS_LIGHT_PASSES  /* all of it is bounced light, diffuse, glossy or transmission by the first scatter (Cycles') */
    light_pass_indirect(light_passes, frame_params.pixels, i, L, st.pass_diffuse, st.pass_through);
#ifdef HAS_LIGHT_GROUPS  /* ... and each light's share to its group */
    light_groups_add(light_passes, frame_params.pixels, i, &st.groups, 1.0f);
#endif
#else
    (void)light_passes;
#endif
}
