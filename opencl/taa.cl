/* Temporal accumulation: f_n = a * s_n + (1 - a) * clip(history(reprojected)), a = max(1 / n, alpha_min) with a
 * per-pixel history length n. When something moves, history is fetched bilinearly from the taps that show the
 * same surface and clipped to the current 3x3 neighbourhood's YCoCg variance box (mean +- gamma * sigma); in a
 * still scene every frame's sample belongs to the pixel (the jitter moves the sample, not the scene) and the
 * history is kept whole. On view-dependent (glossy) surfaces a moving scene's history is shortened and clipped
 * harder (view_dependence.h). A NaN/Inf never enters the history: it is counted and the pixel restarts. */

inline float3 rgb_to_ycocg(float3 c)
{
    return (float3)(0.25f * c.x + 0.5f * c.y + 0.25f * c.z, 0.5f * c.x - 0.5f * c.z, -0.25f * c.x + 0.5f * c.y - 0.25f * c.z);
}

inline float3 ycocg_to_rgb(float3 c)
{
    return (float3)(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

/* Move h towards the box centre until it lies inside the box centre +- extent. */
inline float3 clip_to_box(float3 h, float3 centre, float3 extent)
{
    float3 d = h - centre;
    float3 e = fmax(extent, (float3)(1e-7f));
    float3 ratio = fabs(d) / e;
    float m = fmax_f(ratio.x, fmax_f(ratio.y, ratio.z));
    return m > 1.0f ? centre + d / m : h;
}

__kernel void taa(const __global float4* sample, const __global GSample* gbuf, const __global GlossySample* glossy,
                  const __global GSample* prev_gbuf,
                  const __global float4* history_in, __global float4* history_out, volatile __global int* guards,
                  FrameParams frame_params, TaaParams params)
{
    const TaaParams p = params;
    const int width = frame_params.width, height = frame_params.height;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    float3 s = sample[i].xyz;
    if (!finite3_f(s)) { guard_count(guards, GUARD_NONFINITE_SAMPLE); s = (float3)(0.0f); }
    /* a view-dependent (glossy) surface's history does not follow its motion: shorter, clipped harder */
    float alpha_min = p.alpha_min, gamma = p.gamma;
    if (p.moving) {
        Surface sf = surface_load(gbuf, glossy, i);
        alpha_min = view_dependent_alpha_min(&sf, alpha_min);
        gamma = view_dependent_gamma(&sf, gamma);
    }
    float3 h = (float3)(0.0f);
    float n_prev = 0.0f;
    float2 prev;
    if (!p.reset && reproject_position(gbuf, x, y, width, &prev)) {
        GSample cur = gbuf[i];
        float2 f = prev - 0.5f;
        int x0 = (int)floor(f.x), y0 = (int)floor(f.y);
        float fx = f.x - (float)x0, fy = f.y - (float)y0;
        float wsum = 0.0f;
        float3 hsum = (float3)(0.0f);
        float nsum = 0.0f;
        for (int t = 0; t < 4; ++t) {
            int tx = x0 + (t & 1), ty = y0 + (t >> 1);
            float wt = ((t & 1) ? fx : 1.0f - fx) * ((t >> 1) ? fy : 1.0f - fy);
            if (wt <= 0.0f || tx < 0 || ty < 0 || tx >= width || ty >= height) continue;
            int j = ty * width + tx;
            GSample pg = prev_gbuf[j];
            if (p.moving && !reproject_same_surface(&cur, &pg, p.similar.depth_tolerance, p.similar.normal_cos)) continue;
            float4 hv = history_in[j];
            wsum += wt;
            hsum += wt * hv.xyz;
            nsum += wt * hv.w;
        }
        if (wsum > 1e-3f) {
            h = hsum / wsum;
            n_prev = nsum / wsum;
            if (!finite3_f(h) || !finite_f(n_prev)) {
                guard_count(guards, GUARD_NONFINITE_HISTORY);
                n_prev = 0.0f;
            }
        }
    }
    if (n_prev > 0.0f && p.moving) {
        float3 m1 = (float3)(0.0f), m2 = (float3)(0.0f);
        float cnt = 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                int nx = clamp(x + dx, 0, width - 1), ny = clamp(y + dy, 0, height - 1);
                float3 v = sample[ny * width + nx].xyz;
                if (!finite3_f(v)) continue;
                v = rgb_to_ycocg(v);
                m1 += v;
                m2 += v * v;
                cnt += 1.0f;
            }
        float3 mean = m1 / cnt;
        float3 sigma = sqrt(fmax(m2 / cnt - mean * mean, (float3)(0.0f)));
        h = ycocg_to_rgb(clip_to_box(rgb_to_ycocg(h), mean, gamma * sigma));
    }
    float n = fmin_f(n_prev + 1.0f, (float)p.max_history);
    float a = n_prev > 0.0f ? fmax_f(1.0f / n, alpha_min) : 1.0f;
    float3 o = a * s + (1.0f - a) * h;
    if (!finite3_f(o)) { guard_count(guards, GUARD_NONFINITE_HISTORY); o = s; n = 1.0f; }
    history_out[i] = (float4)(o, n);
}
