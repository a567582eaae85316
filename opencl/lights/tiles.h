/* Presampled light tiles (Wyman and Panteleev, "Rearchitecting spatiotemporal resampling for production", HPG
 * 2021): once per frame, tile_count x tile_size light-array samples are drawn (light with probability slots / M) and
 * their light records copied into one contiguous buffer. RIS candidates are then drawn uniformly from one tile per
 * strip of 64 consecutive pixels instead of from the whole light array: with a million lights every candidate was a
 * cache miss in 64 MB of records; a tile is 72 KB and stays in cache for the strip.
 *
 * Each tile entry is a light drawn from the light array, so a candidate drawn uniformly from a tile is again a light
 * of probability slots / M (its marginal pdf); only the candidates of pixels that share a tile are correlated. RIS
 * (and reuse of its reservoirs) stays unbiased with candidates of the right marginal pdf, whatever their
 * correlation: its expectation is a sum over the candidates, one term each. */
#ifndef RESTIRCL_LIGHT_TILES_H
#define RESTIRCL_LIGHT_TILES_H

#define LIGHT_TILE_STRIP 64  /* consecutive pixels that draw from one tile */

/* The first entry of the tile that pixel i draws from in this frame. */
inline int light_tile_base(int i, uint frame, uint seed, int tile_count, int tile_size)
{
    uint h = pcg_hash((uint)(i / LIGHT_TILE_STRIP) ^ pcg_hash(frame ^ pcg_hash(seed ^ 0x5bd1e995u)));
    return (int)(((ulong)h * (ulong)tile_count) >> 32) * tile_size;
}

/* Tile entry k: the light's record in tile_rec[k]; tile_info[k] = (light index, pick pdf as float bits). */
inline void light_tile_write(const __global Light* lights, int light, float pdf, int k, __global Light* tile_rec,
                             __global int2* tile_info)
{
    tile_rec[k] = lights[light];
    tile_info[k] = (int2)(light, as_int(pdf));
}

/* Entries base + entry[0 .. n-1]: their lights, pick pdfs and records (as light_array_lights does for slots). */
inline void light_tile_entries(const __global Light* tile_rec, const __global int2* tile_info, int base,
                               const uint* entry, int n, int* light, float* pdf, const __global Light** rec)
{
    for (int k = 0; k < n; ++k) {
        int2 info = tile_info[base + (int)entry[k]];
        light[k] = info.x;
        pdf[k] = as_float(info.y);
        rec[k] = &tile_rec[base + (int)entry[k]];
    }
}

#endif
