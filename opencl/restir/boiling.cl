/* ReSTIR's boiling filter (RTXDI's, run after the temporal pass): a light sample that was very unlikely to be
 * drawn but lights a large area spreads through spatial and temporal reuse as a bright blotch that grows and
 * fades ("boiling"). RTXDI finds such a sample by its contribution weight W, far above its neighbours'; the modes
 * below also compare the contribution. Each 8x8 tile's mean measure over its non-empty reservoirs is found first
 * (boiling_tiles, one work-item per tile: the kernels use no local memory); then a reservoir whose measure exceeds
 * `threshold` times the mean of the others in its tile is emptied or forgotten (boiling_filter).
 * threshold = 10 / strength - 9, as RTXDI's: strength 1 drops anything above the mean, 0.2 what is 41 times above
 * it. The filter is biased (it removes or down-weights rare, correct samples), so only the animation path runs it;
 * still renders and the unbiased estimator tests do not. */

#define BOIL_TILE 8

/* What the filter compares and does (Settings.boiling_mode, `mode`): BOIL_WEIGHT, the weight W (RTXDI's),
 * emptying an outlier; BOIL_CONTRIBUTION, the contribution target x W, the luminance the reservoir's sample adds
 * to its pixel before the shadow ray, emptying an outlier; BOIL_FORGET, the contribution, an outlier keeping its
 * sample and W but its M set to 1, so that the spatial merge after this pass and the next frames' temporal merges
 * weigh it as one candidate and let it go. Our scenes' blotches are samples of a light close to the pixel that a
 * lucky candidate found and the pixel's temporal chain then held for ~20 frames: their W is ordinary (the target is
 * large), their contribution is not. Emptying removes their energy (a darker image); forgetting mostly shortens how
 * long they last. */
inline float boil_measure(const Reservoir* r, int mode) { return mode != BOIL_WEIGHT ? r->W * r->target : r->W; }

/* Whether measure m stands above `threshold` times the mean of the others in its tile (st: their sum and count, m
 * included); never for a reservoir alone in its tile. Shared with ReSTIR GI's filter (restir_gi/boiling.cl). */
inline bool boil_outlier(float m, float2 st, float threshold)
{
    float others = st.y - 1.0f;
    return others >= 1.0f && m > threshold * ((st.x - m) / others);
}

__kernel void boiling_tiles(const __global Reservoir* res, __global float2* tile_stats, FrameParams frame_params,
                            int tiles_x, int mode)
{
    int t = get_global_id(0);
    int tiles_y = (frame_params.height + BOIL_TILE - 1) / BOIL_TILE;
    if (t >= tiles_x * tiles_y) return;
    int x0 = (t % tiles_x) * BOIL_TILE, y0 = (t / tiles_x) * BOIL_TILE;
    float sum = 0.0f, n = 0.0f;
    for (int y = y0; y < min(y0 + BOIL_TILE, frame_params.height); ++y) {
        for (int x = x0; x < min(x0 + BOIL_TILE, frame_params.width); ++x) {
            Reservoir r = res[y * frame_params.width + x];
            if (r.light >= 0 && r.W > 0.0f && finite_f(r.W)) {
                sum += boil_measure(&r, mode);
                n += 1.0f;
            }
        }
    }
    tile_stats[t] = (float2)(sum, n);
}

__kernel void boiling_filter(__global Reservoir* res, const __global float2* tile_stats, FrameParams frame_params,
                             int tiles_x, float threshold, int mode)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame_params.width || y >= frame_params.height) return;
    int i = y * frame_params.width + x;
    Reservoir r = res[i];
    if (r.light < 0 || !(r.W > 0.0f) || !finite_f(r.W)) return;
    float2 st = tile_stats[(y / BOIL_TILE) * tiles_x + x / BOIL_TILE];
    if (boil_outlier(boil_measure(&r, mode), st, threshold)) {
        if (mode == BOIL_FORGET)
            r.M = fmin_f(r.M, 1.0f);
        else
            res_init(&r);
        res[i] = r;
    }
}
