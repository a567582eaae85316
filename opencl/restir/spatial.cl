/* ReSTIR pass 5: merge up to `spatial_neighbours` (or `boost_neighbours`) reservoirs of random pixels within
 * `spatial_radius` whose surface is similar (view depth, normal and material: surface_material_similar) with the
 * pixel's own (restir/reuse.h); the pixels are picked by restir/neighbours.h. A fresh pixel none of them is similar to
 * takes `fresh_candidates` more candidates of its own instead (restir/lonely_fresh.h). */

__kernel void restir_spatial(const __global GSample* gbuf, const __global GlossySample* glossy, const __global BVHNode* nodes, const __global Tri* tris,
                             const __global Light* lights, const __global int* slots, const __global float* light_pdf,
                             const __global LightTreeNode* tree_nodes, const __global int2* tree_info,
                             const __global int8* tree_distant,
                             const __global Light* tile_rec, const __global int2* tile_info,
                             const __global int* tri_light, const __global Reservoir* input, __global Reservoir* out,
                             FrameParams frame_params, SpatialParams params)
{
    const SpatialParams p = params;
    const int width = frame_params.width, height = frame_params.height;
    const int bias_correction = p.bias_correction, visibility_reuse = p.visibility_reuse;
    const int pass = p.pass_index;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    Reservoir c = input[i];
    Surface s = surface_load(gbuf, glossy, i);
    if (!s.valid) { out[i] = c; return; }
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 5u + (uint)pass);
    /* the neighbours: random pixels in the disk that show a similar surface */
    int used[MAX_NEIGHBOURS];
    /* disocclusion boost (first pass): a pixel the temporal pass found no history for takes more neighbours. The
     * count depends on the history's presence, not on any sample, so every bias correction stays as it was. */
    const bool fresh = pass == 0 && c.M <= p.fresh_m;
    int k_want = (fresh && p.boost_neighbours > p.spatial_neighbours)
                 ? p.boost_neighbours : p.spatial_neighbours;
    int k_max = min(k_want, MAX_NEIGHBOURS);
    float radius = p.spatial_radius;
#ifdef EXPERIMENT_COC_RADIUS_SCALE
    /* tools/experiments/dof_coc_reuse.py, compiled out of every ordinary build: the disk grown to the pixel's circle
     * of confusion (radius in pixels = scale * |1 / depth - 1 / focus|), at most 64 pixels */
    radius = fmax_f(radius, fmin_f(EXPERIMENT_COC_RADIUS_SCALE * fabs(1.0f / s.depth - EXPERIMENT_COC_FOCUS_INV), 64.0f));
#endif
    for (int k = 0; k < k_max; ++k) {
        float2 o = disk_offset(radius, &rng);
        int nx = x + round_i(o.x), ny = y + round_i(o.y);
        bool inside = nx >= 0 && ny >= 0 && nx < width && ny < height && !(nx == x && ny == y);
        used[k] = inside ? ny * width + nx : i;  /* i: rejected below */
    }
    /* What the tests need of each neighbour (depth, normal, material key) and its reservoir are read in one loop
     * and tested in the next: the reads (cache misses, random pixels within the radius) then overlap instead of
     * each waiting behind the branch on the last one. */
    float4 nn[MAX_NEIGHBOURS];  /* normal; w: the primitive (int bits), < 0 for a miss */
    float nd[MAX_NEIGHBOURS];
    MaterialKey nk[MAX_NEIGHBOURS];
    Reservoir qs[MAX_NEIGHBOURS];
    for (int k = 0; k < k_max; ++k) {
        nn[k] = gbuf[used[k]].normal;
        nd[k] = gbuf[used[k]].pos.w;
        SurfaceMaterial m = surface_material_load(gbuf, glossy, used[k], as_int(nn[k].w) >= 0);
        nk[k] = material_key(&m);
        qs[k] = input[used[k]];
    }
    const MaterialKey key = material_key(&s.mat);
    int n_used = 0;
    for (int k = 0; k < k_max; ++k) {
        /* the material too: a glossy target is not a diffuse one's */
        bool similar = used[k] != i && as_int(nn[k].w) >= 0 && abs_f(nd[k] - s.depth) <= p.similar.depth_tolerance * s.depth
                       && dot3(nn[k].xyz, s.n) >= p.similar.normal_cos && material_keys_similar(&key, &nk[k]);
        if (similar) {
            used[n_used] = used[k];
            qs[n_used++] = qs[k];
        }
    }
    if (n_used == 0) {
        if (fresh && p.fresh_candidates > 0 && p.sampler.light_count > 0) c = lonely_fresh(&s, i, &c, lights, slots,
            light_pdf, tree_nodes, tree_info, tree_distant, tile_rec, tile_info, nodes, tris, tri_light, &p,
            frame_params, &rng);
        out[i] = c;
        return;
    }

    VisKnown known = vis_known_none();  /* a neighbour's point is not this pixel's */
    Reservoir r;
    reuse_combine(&s, &c, qs, n_used, gbuf, glossy, used, nodes, tris, lights, bias_correction, visibility_reuse,
                  &known, &rng, &r);
#ifdef PROBE_REUSE_LIGHT  /* tools/experiments/near_light_spikes.py --trace */
    bool traced = r.light == PROBE_REUSE_LIGHT || c.light == PROBE_REUSE_LIGHT;
    for (int k = 0; k < n_used; ++k) traced = traced || qs[k].light == PROBE_REUSE_LIGHT;
    if (traced) {
        printf("reuse sample %u spatial (%d,%d): own l %d M %g W %g p_c %g -> l %d M %g W %g value %g\n",
               frame_params.sample, x, y, c.light, c.M, c.W, c.target, r.light, r.M, r.W, r.W * r.target);
        for (int k = 0; k < n_used; ++k)
            printf("reuse sample %u spatial (%d,%d):   neighbour (%d,%d) l %d M %g W %g p_q %g\n", frame_params.sample,
                   x, y, used[k] % width, used[k] / width, qs[k].light, qs[k].M, qs[k].W, qs[k].target);
    }
#endif
    out[i] = r;
}
