/* ReSTIR GI's boiling filter (boiling_filter, boiling_mode; run after its temporal pass, as ReSTIR DI's is after its
 * own, restir/boiling.cl, which explains the tiles and the threshold, and shares its tile size and test): a secondary
 * sample whose contribution to its pixel (target x W, the luminance it adds; W alone with the weight mode) stands far
 * above the mean of the others in its 8x8 tile is emptied, or (forget) keeps its sample but its M drops to 1. GI's
 * outliers are a lucky L_o (a path that found a light from close by) or a sample moved across a corner with a large
 * Jacobian; the spatial pass spreads them, the temporal pass holds them for up to gi_m_cap frames. Biased: animation
 * path only. */

inline float gi_boil_measure(const GIReservoir* r, int mode) { return mode != BOIL_WEIGHT ? r->W * r->target : r->W; }

__kernel void gi_boiling_tiles(const __global GIReservoir* res, __global float2* tile_stats, FrameParams frame_params,
                               int tiles_x, int mode)
{
    int t = get_global_id(0);
    int tiles_y = (frame_params.height + BOIL_TILE - 1) / BOIL_TILE;
    if (t >= tiles_x * tiles_y) return;
    int x0 = (t % tiles_x) * BOIL_TILE, y0 = (t / tiles_x) * BOIL_TILE;
    float2 st = (float2)(0.0f);
    for (int y = y0; y < min(y0 + BOIL_TILE, frame_params.height); ++y) {
        for (int x = x0; x < min(x0 + BOIL_TILE, frame_params.width); ++x) {
            GIReservoir r = res[y * frame_params.width + x];
            if (gi_has_sample(&r) && finite_f(r.W)) st += (float2)(gi_boil_measure(&r, mode), 1.0f);
        }
    }
    tile_stats[t] = st;
}

__kernel void gi_boiling_filter(__global GIReservoir* res, const __global float2* tile_stats,
                                FrameParams frame_params, int tiles_x, float threshold, int mode)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= frame_params.width || y >= frame_params.height) return;
    int i = y * frame_params.width + x;
    GIReservoir r = res[i];
    if (!gi_has_sample(&r) || !finite_f(r.W)) return;
    float2 st = tile_stats[(y / BOIL_TILE) * tiles_x + x / BOIL_TILE];
    if (!boil_outlier(gi_boil_measure(&r, mode), st, threshold)) return;
    if (mode == BOIL_FORGET)
        r.M = fmin_f(r.M, 1.0f);
    else
        gi_res_init(&r);
    res[i] = r;
}
