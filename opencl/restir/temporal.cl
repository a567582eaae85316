/* ReSTIR pass 4: merge the pixel's new reservoir with last frame's reservoir of the same surface (found by
 * reprojection), its M capped, by the reuse combine (restir/reuse.h). Targets at this pixel are evaluated with this
 * frame's lights, so a light switched off stops contributing at once. Pairwise MIS also needs the previous input's
 * target at its own sample, at last frame's surface with this frame's lights and geometry; lights_static: the light
 * records are last frame's, so that is the target the reservoir stored and is not evaluated again. Last frame's
 * surface must carry a similar material (surface_material_similar), and the history cap shrinks on view-dependent
 * (glossy) surfaces, whose target moves with the camera (surface/view_dependence.h).
 * The visibility shortcut (vis_max_age > 0, static scene): where last frame's point is within vis_max_distance
 * pixel footprints of this pixel's, the two shadow tests of the merge are answered from the stored ones
 * (restir/reuse.h, VisKnown). */

/* Is last frame's point xp within max_distance footprints of a pixel (at x, facing the camera) of point x? */
inline bool same_point(const __global Camera* cam, float3 x, float3 xp, float max_distance)
{
    float3 d = x - cam->origin.xyz;
    float t = len3(d);
    float tol = max_distance * camera_footprint(cam, t > 0.0f ? d / t : cam->forward.xyz, t);
    float3 e = x - xp;
    return dot3(e, e) <= tol * tol;
}

__kernel void restir_temporal(const __global Camera* cam, const __global GSample* gbuf, const __global GSample* prev_gbuf,
                              const __global GlossySample* glossy, const __global GlossySample* prev_glossy,
                              const __global BVHNode* nodes, const __global Tri* tris, const __global Light* lights,
                              const __global Reservoir* current, const __global Reservoir* previous,
                              __global Reservoir* out, volatile __global int* guards, FrameParams frame_params,
                              TemporalParams params)
{
    const TemporalParams p = params;
    const int width = frame_params.width, height = frame_params.height;
    const int bias_correction = p.bias_correction, visibility_reuse = p.visibility_reuse;
    const int lights_static = p.lights_static;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    Reservoir c = current[i];
    Surface s = surface_load(gbuf, glossy, i);
    if (!s.valid) { out[i] = c; return; }
    int j = reproject_pixel(gbuf, prev_gbuf, x, y, width, height, p.similar.depth_tolerance, p.similar.normal_cos,
                            p.permutation);
    if (j < 0) { out[i] = c; return; }
    Surface sp = surface_load(prev_gbuf, prev_glossy, j);
    if (!surface_material_similar(&s, &sp)) { out[i] = c; return; }  /* a glossy target is not a diffuse one's */
    Reservoir q = previous[j];
    q.M = fmin_f(q.M, p.m_cap * view_dependent_cap(&s));
    if (!finite_f(q.W) || !finite_f(q.M)) { guard_count(guards, GUARD_NONFINITE_RESERVOIR); out[i] = c; return; }
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 4u);
    if (bias_correction == BIAS_PAIRWISE && !lights_static && q.light >= 0 && q.W > 0.0f) {
        LightEval e;
        q.target = target_of(&sp, lights, q.light, q.u, q.v, &e);
    }
    VisKnown known = vis_known_none();
    if (visibility_reuse && p.vis_static) {
        known.max_age = p.vis_max_age;
        known.same_point = p.vis_max_age > 0 && same_point(cam, s.x, sp.x, p.vis_max_distance);
    }
    Reservoir r;
    reuse_combine(&s, &c, &q, 1, prev_gbuf, prev_glossy, &j, nodes, tris, lights, bias_correction, visibility_reuse,
                  &known, &rng, &r);
#ifdef PROBE_REUSE_LIGHT  /* tools/experiments/near_light_spikes.py --trace: the merges that hold one light */
    if (q.light == PROBE_REUSE_LIGHT || c.light == PROBE_REUSE_LIGHT) {
        LightEval pe;
        float t_c = q.light >= 0 ? target_of(&s, lights, q.light, q.u, q.v, &pe) : 0.0f;
        float t_q = c.light >= 0 ? target_of(&sp, lights, c.light, c.u, c.v, &pe) : 0.0f;
        printf("reuse sample %u temporal (%d,%d) from (%d,%d): history l %d M %g W %g p_q %g p_c %g; own l %d M %g "
               "W %g p_c %g p_q %g -> l %d M %g W %g value %g\n", frame_params.sample, x, y, j % width, j / width,
               q.light, q.M, q.W, q.target, t_c, c.light, c.M, c.W, c.target, t_q, r.light, r.M, r.W,
               r.W * r.target);
    }
#endif
    out[i] = r;
}
