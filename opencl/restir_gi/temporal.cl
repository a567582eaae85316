/* ReSTIR GI pass 2: merge the pixel's initial reservoir with last frame's reservoir of the same surface, found by
 * reprojection (camera/reproject.h, permutation sampling as ReSTIR DI's), its M capped at m_cap (a sample whose
 * radiance L_o was gathered frames ago, with lights or objects since moved, must fade out). Last frame's sample
 * moves from last frame's visible point to this one's with its Jacobian (restir_gi/reuse.h); last frame's surface
 * must carry a similar material, and the cap shrinks on view-dependent surfaces (surface/view_dependence.h) as ReSTIR
 * DI's does. */

__kernel void gi_temporal(const __global GSample* gbuf, const __global GSample* prev_gbuf,
                          const __global GlossySample* glossy, const __global GlossySample* prev_glossy,
                          const __global BVHNode* nodes, const __global Tri* tris, const __global GIReservoir* current,
                          const __global GIReservoir* previous, __global GIReservoir* out, volatile __global int* guards,
                          FrameParams frame_params, GITemporalParams params)
{
    const int width = frame_params.width, height = frame_params.height;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    GIReservoir c = current[i];
    Surface s = surface_load(gbuf, glossy, i);
    if (!s.valid) { out[i] = c; return; }
    int j = reproject_pixel(gbuf, prev_gbuf, x, y, width, height, params.similar.depth_tolerance,
                            params.similar.normal_cos, params.permutation);
    if (j < 0) { out[i] = c; return; }
    Surface sp = surface_load(prev_gbuf, prev_glossy, j);
    if (!surface_material_similar(&s, &sp)) { out[i] = c; return; }
    GIReservoir q = previous[j];
    q.M = fmin_f(q.M, params.m_cap * view_dependent_cap(&s));
    if (!finite_f(q.W) || !finite_f(q.M) || !finite3_f(q.radiance.xyz)) {
        guard_count(guards, GUARD_NONFINITE_RESERVOIR);
        out[i] = c;
        return;
    }
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 13u);
    const GIInputs in = {&q, &j, 1, prev_gbuf, prev_glossy};
    GIReservoir r;
    gi_reuse_combine(&s, &c, &in, params.bias_correction, nodes, tris, &rng, &r);
    out[i] = r;
}
