/* ReSTIR pass 6: one shadow ray to the pixel's final sample: f * Le * G * V * W, plus emission seen directly.
 * visible_known: the reuse passes already kept W = 0 for samples occluded at this pixel (unbiased mode with
 * visibility reuse), so the shadow ray is left out. Clamp Direct clamps the emission seen and the shaded sample, each
 * as one contribution (direct/clamp.h); the resampling before it is not clamped. */

__kernel void restir_shade(const __global GSample* gbuf, const __global GlossySample* glossy, const __global BVHNode* nodes, const __global Tri* tris,
                           const __global Light* lights, const __global Reservoir* res,
                           volatile __global int* guards, __global float4* out, __global float4* light_passes,
                           FrameParams frame_params, ShadeParams params)
{
    const int pixel_count = frame_params.pixels;
    const int visible_known = params.visible_known;
    int i = get_global_id(0);
    if (i >= pixel_count) return;
    Surface s = surface_load(gbuf, glossy, i);
    const float clamp = params.clamp_direct, k_seen = clamp_scale(gbuf[i].emission.xyz, clamp);
    float3 c = gbuf[i].emission.xyz * k_seen;
    DirectSplit pass = direct_split_zero();
    GroupLight gl;  /* the light groups' direct light (film/light_groups.h) */
    group_light_clear(&gl);
    Reservoir r = res[i];
    LightEval e;
#ifdef HAS_THIN_SHADOW  /* a smooth thin wall passes a colour (bvh/thin_wall_shadow.h): always the shadow ray's */
    Shadow v = 0.0f;
    (void)visible_known;
    if (s.valid && r.light >= 0 && r.W > 0.0f && target_of(&s, lights, r.light, r.u, r.v, &e) > 0.0f
        && shadow_any(v = transmittance(nodes, tris, &s, &e))) {
        float3 x = direct_contribution(&s, e.wi, unshadowed_contrib(&s, &e) * r.W * v, clamp, &pass);
#else
    if (s.valid && r.light >= 0 && r.W > 0.0f && target_of(&s, lights, r.light, r.u, r.v, &e) > 0.0f
        && (visible_known || visible(nodes, tris, &s, &e))) {
        float3 x = direct_contribution(&s, e.wi, unshadowed_contrib(&s, &e) * r.W, clamp, &pass);
#endif
        c += x;
        GROUP_ADD(&gl, lights, &lights[r.light], x);
    }
    direct_passes(light_passes, pixel_count, i, &pass, k_seen);
    light_groups_add(light_passes, pixel_count, i, &gl, k_seen);
    out[i] = (float4)(guard_finite(c, guards, GUARD_NONFINITE_SAMPLE), film_coverage(gbuf[i]));
}
