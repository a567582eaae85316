/* ReSTIR GI pass 4: the pixel's final sample shades it: f cos L_o W (restir_gi/sample.h), its indirect light, added
 * to this frame's sample and kept in `indirect` (the frame's bounced light). visible_known: the unbiased modes keep
 * only samples visible from their own visible point (restir_gi/reuse.h), so no ray is traced; the biased mode's
 * reuse tests no visibility, and one ray here keeps it from shading a point the pixel cannot see. */

__kernel void gi_shade(const __global GSample* gbuf, const __global GlossySample* glossy,
                       const __global BVHNode* nodes, const __global Tri* tris, const __global GIReservoir* res,
                       volatile __global int* guards, __global float4* sample, __global float4* indirect,
                       __global float4* light_passes, FrameParams frame_params, GIShadeParams params)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    Surface s = surface_load(gbuf, glossy, i);
#ifdef HAS_TRANSMISSION  /* a pixel that transmits takes its bounced light from the path pass (path/path.cl) */
    if (params.split_glass && s.valid && surface_transmits(&s)) return;
#endif
    GIReservoir r = res[i];
    float3 c = (float3)(0.0f);
    float3 contrib;
    float g;
    if (s.valid && gi_has_sample(&r) && gi_target(&s, &r, &contrib, &g) > 0.0f
        && (params.visible_known || gi_visible(nodes, tris, &s, &r)))
        c = contrib * r.W;
    c = guard_finite(c, guards, GUARD_NONFINITE_SAMPLE);
    indirect[i] = (float4)(c, 1.0f);
    sample[i].xyz += c;
#ifdef HAS_LIGHT_PASSES  /* split by the BSDF at the visible point towards x_s: the first bounce's */
    float3 share = (float3)(0.0f);
    int through = 0;
    if (s.valid && gi_has_sample(&r)) {
        float3 wi = normalize(r.pos.xyz - s.x);
        share = light_pass_diffuse_share(&s, wi);
        through = light_pass_through(&s, wi);
    }
    light_pass_indirect(light_passes, frame_params.pixels, i, c, share, through);
#else
    (void)light_passes;
#endif
}
