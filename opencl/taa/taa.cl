/* Temporal accumulation: f_n = a * s_n + (1 - a) * clip(history(reprojected)), a = max(1 / n, alpha_min) with a
 * per-pixel history length n. When something moves, history is fetched bilinearly from the taps that show the
 * same surface and clipped to the current 3x3 neighbourhood's YCoCg variance box (mean +- gamma * sigma,
 * taa/clip_box.h); in a still scene every frame's sample belongs to the pixel (the jitter moves the sample, not the
 * scene) and the history is kept whole. On view-dependent (glossy) surfaces a moving scene's history is shortened
 * and clipped harder (surface/view_dependence.h), and a pixel without history shows its surface's 3x3 mean
 * (taa/fresh_fill.h). A NaN/Inf never enters the history: it is counted and the pixel restarts. */

/* Move h towards the box centre until it lies inside the box centre +- extent. */
inline float3 clip_to_box(float3 h, float3 centre, float3 extent)
{
    float3 d = h - centre;
    float3 e = fmax(extent, (float3)(1e-7f));
    float3 ratio = fabs(d) / e;
    float m = fmax_f(ratio.x, fmax_f(ratio.y, ratio.z));
    return m > 1.0f ? centre + d / m : h;
}

/* Catmull-Rom weights of the four taps at -1, 0, 1, 2 around a sample at fraction f of the way from tap 0 to 1. */
inline float4 catmull_rom_weights(float f)
{
    float f2 = f * f, f3 = f2 * f;
    return (float4)(-0.5f * f3 + f2 - 0.5f * f, 1.5f * f3 - 2.5f * f2 + 1.0f, -1.5f * f3 + 2.0f * f2 + 0.5f * f,
                    0.5f * f3 - 0.5f * f2);
}

/* History at continuous previous-frame position `prev` from the taps that show the pixel's surface: bilinear (2x2),
 * or Catmull-Rom (4x4: sharper under motion, where bilinear blurs a little every frame). Catmull-Rom needs every
 * tap: where one is another surface or off-screen it falls back to bilinear over the valid ones, and its negative
 * lobes are clamped (the result never goes below 0). n (history length) is always taken bilinearly. */
inline bool taa_fetch(const GSample* cur, float2 prev, const __global GSample* prev_gbuf,
                      const __global float4* history_in, int width, int height, int moving, int filter,
                      float depth_tol, float normal_cos, float3* h, float* n_prev)
{
    float2 f = prev - 0.5f;
    int x0 = (int)floor(f.x), y0 = (int)floor(f.y);
    float fx = f.x - (float)x0, fy = f.y - (float)y0;
    float wsum = 0.0f, nsum = 0.0f;
    float3 hsum = (float3)(0.0f);
    bool all_valid = true;
    for (int t = 0; t < 4; ++t) {
        int tx = x0 + (t & 1), ty = y0 + (t >> 1);
        float wt = ((t & 1) ? fx : 1.0f - fx) * ((t >> 1) ? fy : 1.0f - fy);
        if (tx < 0 || ty < 0 || tx >= width || ty >= height) { all_valid = false; continue; }
        int j = ty * width + tx;
        GSample pg = prev_gbuf[j];
        if (moving && !reproject_same_surface(cur, &pg, depth_tol, normal_cos)) { all_valid = false; continue; }
        if (wt <= 0.0f) continue;
        float4 hv = history_in[j];
        wsum += wt;
        hsum += wt * hv.xyz;
        nsum += wt * hv.w;
    }
    if (!(wsum > 1e-3f)) return false;
    *h = hsum / wsum;
    *n_prev = nsum / wsum;
    if (filter != TAA_CATMULL_ROM || !all_valid || x0 < 1 || y0 < 1 || x0 + 2 >= width || y0 + 2 >= height)
        return true;
    float4 wx = catmull_rom_weights(fx), wy = catmull_rom_weights(fy);
    float3 c = (float3)(0.0f);
    for (int ty = 0; ty < 4; ++ty) {
        float wyt = ty == 0 ? wy.x : ty == 1 ? wy.y : ty == 2 ? wy.z : wy.w;
        for (int tx = 0; tx < 4; ++tx) {
            float wxt = tx == 0 ? wx.x : tx == 1 ? wx.y : tx == 2 ? wx.z : wx.w;
            int j = (y0 - 1 + ty) * width + (x0 - 1 + tx);
            /* the outer ring was not surface-tested: a different surface there keeps the bilinear value */
            if (moving && (tx == 0 || tx == 3 || ty == 0 || ty == 3)) {
                GSample pg = prev_gbuf[j];
                if (!reproject_same_surface(cur, &pg, depth_tol, normal_cos)) return true;
            }
            c += wxt * wyt * history_in[j].xyz;
        }
    }
    *h = fmax(c, (float3)(0.0f));
    return true;
}

/* The previous position of the nearest surface (smallest view depth) among the pixel and its 8 neighbours. */
inline bool taa_dilated_position(const __global GSample* gbuf, int x, int y, int width, int height, float2* prev)
{
    int best = -1;
    float depth = INFINITY;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            int j = ny * width + nx;
            GSample g = gbuf[j];
            if (as_int(g.normal.w) < 0 || !(g.pos.w < depth)) continue;
            depth = g.pos.w;
            best = j;
        }
    if (best < 0) return false;
    float4 m = gbuf[best].motion;
    if (m.z == 0.0f) return false;
    *prev = (float2)((float)x + 0.5f, (float)y + 0.5f) + m.xy;
    return finite_f(prev->x) && finite_f(prev->y);
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
    MaterialKey key;  /* the surface's material key, for the fresh-pixel fill (moving frames only) */
    if (p.moving) {
        Surface sf = surface_load(gbuf, glossy, i);
        alpha_min = view_dependent_alpha_min(&sf, alpha_min);
        gamma = view_dependent_gamma(&sf, gamma);
        key = material_key(&sf.mat);
    }
    float3 h = (float3)(0.0f);
    float n_prev = 0.0f;
    float2 prev, sweep = (float2)(0.0f);
    const bool blurred = p.moving && p.sweep_close > p.sweep_open;
    bool swept = false;
    if (!p.reset) {
        GSample cur = gbuf[i];
        /* with motion blur, where the fastest path over the shutter that crosses the pixel is TAA_SWEEP_MIN
         * pixels long or more, that motion and any surface's history (taa/sweep.h); else the nearest surface's
         * motion (edges of a moving object follow it), then the pixel's own */
        bool fetched = false;
        swept = blurred && taa_sweep_motion(gbuf, x, y, width, height, p.sweep_open, p.sweep_close, &sweep)
            && length(sweep) * (p.sweep_close - p.sweep_open) >= TAA_SWEEP_MIN;
        if (swept) {
            prev = (float2)((float)x + 0.5f, (float)y + 0.5f) + sweep;
            fetched = finite_f(prev.x) && finite_f(prev.y)
                && taa_fetch(&cur, prev, prev_gbuf, history_in, width, height, 0, p.filter,
                             p.similar.depth_tolerance, p.similar.normal_cos, &h, &n_prev);
        }
        if (!fetched && p.dilate && p.moving && taa_dilated_position(gbuf, x, y, width, height, &prev))
            fetched = taa_fetch(&cur, prev, prev_gbuf, history_in, width, height, p.moving, p.filter,
                                p.similar.depth_tolerance, p.similar.normal_cos, &h, &n_prev);
        if (!fetched && reproject_position(gbuf, x, y, width, &prev))
            fetched = taa_fetch(&cur, prev, prev_gbuf, history_in, width, height, p.moving, p.filter,
                                p.similar.depth_tolerance, p.similar.normal_cos, &h, &n_prev);
        if (fetched && (!finite3_f(h) || !finite_f(n_prev))) {
            guard_count(guards, GUARD_NONFINITE_HISTORY);
            h = (float3)(0.0f);
            n_prev = 0.0f;
        }
    }
    if (p.fresh_fill && p.moving && !p.reset && !(n_prev > 0.0f))
        s = taa_fresh_fill(sample, gbuf, glossy, x, y, width, height, p.similar.depth_tolerance,
                           p.similar.normal_cos, &key, s);
    if (n_prev > 0.0f && p.moving) {
        float3 mean, sigma;
        taa_clip_box(sample, gbuf, x, y, width, height, p.clip_surface, p.similar.depth_tolerance,
                     p.similar.normal_cos, &mean, &sigma);
        float3 extent = gamma * sigma;
        if (swept) {
            /* motion blur: the box also spans what the pixel sees along its sweep (a blurred pixel's history
             * mixes those colours: a variance box of the mixture would clip its extremes) */
            float3 lo = mean - extent, hi = mean + extent;
            for (int k = 0; k < TAA_SWEEP_TAPS; ++k) {
                float3 v = taa_sweep_tap(sample, x, y, width, height, sweep, p.sweep_open, p.sweep_close, k);
                if (!finite3_f(v)) continue;
                v = rgb_to_ycocg(v);
                lo = fmin(lo, v);
                hi = fmax(hi, v);
            }
            mean = 0.5f * (lo + hi);
            extent = 0.5f * (hi - lo);
        }
        h = ycocg_to_rgb(clip_to_box(rgb_to_ycocg(h), mean, extent));
    }
    float n = fmin_f(n_prev + 1.0f, (float)p.max_history);
    /* a still scene keeps converging (1/n up to max_history); motion brings back the floor alpha_min */
    float a = n_prev > 0.0f ? fmax_f(1.0f / n, p.moving ? alpha_min : 0.0f) : 1.0f;
    float3 o = a * s + (1.0f - a) * h;
    if (!finite3_f(o)) { guard_count(guards, GUARD_NONFINITE_HISTORY); o = s; n = 1.0f; }
    history_out[i] = (float4)(o, n);
}
