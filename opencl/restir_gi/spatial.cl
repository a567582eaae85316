/* ReSTIR GI pass 3: merge up to `neighbours` reservoirs of random pixels within `radius` (restir/neighbours.h)
 * whose surface is similar to the pixel's (view depth, normal, material) with the pixel's own; each neighbour's
 * sample moves to this pixel's visible point with its Jacobian (restir_gi/reuse.h). */

/* the table's limit (settings/table.py) arrives as -DMAX_GI_NEIGHBOURS; this fallback serves other builds */
#ifndef MAX_GI_NEIGHBOURS
#define MAX_GI_NEIGHBOURS 16
#endif

/* The similar neighbours of pixel (x, y) with surface s: their pixels in used[] and reservoirs in qs[], how many. */
inline int gi_neighbours(const __global GSample* gbuf, const __global GlossySample* glossy,
                         const __global GIReservoir* input, const Surface* s, int x, int y, int width, int height,
                         const GISpatialParams* p, uint* rng, int* used, GIReservoir* qs)
{
    /* disocclusion boost: a pixel the temporal pass found no history for (its own sample alone, M <= 1) takes more
     * neighbours; the count depends on the history's presence, not on any sample, so the modes stay as they were */
    int k_want = (input[y * width + x].M <= 1.0f && p->boost_neighbours > p->neighbours) ? p->boost_neighbours
                                                                                        : p->neighbours;
    int k_max = min(k_want, MAX_GI_NEIGHBOURS), n_used = 0;
    const MaterialKey key = material_key(&s->mat);
    for (int k = 0; k < k_max; ++k) {
        float2 o = disk_offset(p->radius, rng);
        int nx = x + round_i(o.x), ny = y + round_i(o.y);
        if (nx < 0 || ny < 0 || nx >= width || ny >= height || (nx == x && ny == y)) continue;
        int j = ny * width + nx;
        float4 nn = gbuf[j].normal;
        float nd = gbuf[j].pos.w;
        if (as_int(nn.w) < 0 || !(abs_f(nd - s->depth) <= p->similar.depth_tolerance * s->depth)
            || dot3(nn.xyz, s->n) < p->similar.normal_cos)
            continue;
        SurfaceMaterial m = surface_material_load(gbuf, glossy, j, 1);
        MaterialKey nk = material_key(&m);
        if (!material_keys_similar(&key, &nk)) continue;  /* a glossy target is not a diffuse one's */
        used[n_used] = j;
        qs[n_used++] = input[j];
    }
    return n_used;
}

__kernel void gi_spatial(const __global GSample* gbuf, const __global GlossySample* glossy,
                         const __global BVHNode* nodes, const __global Tri* tris, const __global GIReservoir* input,
                         __global GIReservoir* out, FrameParams frame_params, GISpatialParams params)
{
    const int width = frame_params.width, height = frame_params.height;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    GIReservoir c = input[i];
    Surface s = surface_load(gbuf, glossy, i);
    if (!s.valid) { out[i] = c; return; }
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 14u);
    int used[MAX_GI_NEIGHBOURS];
    GIReservoir qs[MAX_GI_NEIGHBOURS];
    int n = gi_neighbours(gbuf, glossy, input, &s, x, y, width, height, &params, &rng, used, qs);
    if (n == 0) { out[i] = c; return; }
    const GIInputs in = {qs, used, n, gbuf, glossy};
    GIReservoir r;
    gi_reuse_combine(&s, &c, &in, params.bias_correction, nodes, tris, &rng, &r);
    out[i] = r;
}
