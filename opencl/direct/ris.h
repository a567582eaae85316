/* RIS over light-array candidates (the lecture's "RIS over a few candidates"), shared by the `ris` sampler
 * (direct/direct.cl) and ReSTIR's initial reservoirs (restir/initial.cl): `candidates` samples drawn from the light
 * array (light with probability slots / M, a point on it by light_sample) streamed into a reservoir with resampling
 * weight target / source pdf.
 *
 * Candidates run in batches of RIS_BATCH: first every random number and every read of the light array (slot, pdf,
 * the light record's type: light_array_lights, light_tile_entries), then the evaluations. With a million lights each
 * of those reads is a cache miss; read for a whole batch first, the misses overlap instead of each waiting behind
 * the previous candidate's evaluation (1e6 point lights: ReSTIR's initial pass 91-95 -> 65-66 ms). The random
 * numbers are drawn in the same order as one candidate at a time (slot, r0, r1, resampling): the same samples.
 * (OpenCL's prefetch() did nothing on PoCL.) With presampled light tiles (lights/tiles.h) a candidate is an entry of
 * the pixel's tile instead of a slot; with the light tree (lights/tree.h) a light picked by a descent at the shading
 * point. With BSDF candidates (direct/bsdf_candidates.h) every weight's source pdf is the two strategies' mixture
 * density, and the BSDF's candidates follow the light candidates; without them the weights are target / pdf exactly
 * as before. With a BSDF sample outside the reservoir (direct/bsdf_mis.h) every light candidate's target is scaled
 * by its MIS weight. With QMC (q->on, sampling/qmc.h) the pick, the point on the light and the BSDF direction of
 * every candidate come from the pixel's scrambled Sobol groups (the first candidate's from the camera vertex's,
 * which also places the camera ray in its pixel), and all resampling choices from one uniform (res_update_remap). */
#ifndef RESTIRCL_RIS_H
#define RESTIRCL_RIS_H

#define RIS_BATCH 8

/* Where the candidates come from: the light array or tree (tile_count 0; LightPick says which), or the presampled
 * tile of this pixel (lights/tiles.h; tile_base: its first entry). */
typedef struct {
    int slot_count;
    int tile_count;
    int tile_size;
    int tile_base;
} RisSource;

/* The source of pixel i's candidates in this frame. */
inline RisSource ris_source(int slot_count, int tile_count, int tile_size, int i, uint frame, uint seed)
{
    RisSource src = {slot_count, tile_count, tile_size, 0};
    if (tile_count > 0) src.tile_base = light_tile_base(i, frame, seed, tile_count, tile_size);
    return src;
}

/* Stream `candidates` light-array samples and bsdf.count BSDF samples for surface s into r (not finalised).
 * *chosen: the evaluation of the candidate r holds (valid when r->light >= 0 and its target > 0), for the caller's
 * shadow ray. */
inline void ris_candidates(const Surface* s, const __global Light* lights, const LightPick* lp,
                           const __global Light* tile_rec,
                           const __global int2* tile_info, RisSource src, int candidates,
                           const __global BVHNode* nodes, const __global Tri* tris, const __global int* tri_light,
                           BsdfSource bsdf_frame, uint* rng, const Qmc* q, Reservoir* r, LightEval* chosen)
{
    const BsdfSource bsdf = bsdf_source_at(s, bsdf_frame);
    const float n_light = (float)candidates, n_bsdf = (float)bsdf.count;
    LightEval e;
    bool tiled = src.tile_count > 0;
    uint draw_range = (uint)(tiled ? src.tile_size : src.slot_count);
    float sel = 0.0f;  /* QMC: the one uniform of the resampling choices (res_update_remap) */
    for (int k0 = 0; k0 < candidates; k0 += RIS_BATCH) {
        int n = min(RIS_BATCH, candidates - k0);
        uint pick[RIS_BATCH];
        int light[RIS_BATCH], type[RIS_BATCH];
        const __global Light* rec[RIS_BATCH];
        float r0[RIS_BATCH], r1[RIS_BATCH], rnd[RIS_BATCH], pick_pdf[RIS_BATCH];
        for (int k = 0; k < n; ++k) {
            if (q->on) {
                /* the first candidate shares the camera vertex's group with the pixel jitter (sampling/qmc.h) */
                uint4 a = k0 + k == 0 ? qmc_camera_light_bits(q) : qmc_quad_bits(q, QMC_LIGHT(k0 + k));
                pick[k] = light_pick_takes_word(lp) ? a.x : (uint)(((ulong)a.x * (ulong)draw_range) >> 32);
                if (k0 + k == 0) sel = qmc_float(a.w);
                r0[k] = qmc_float(a.y);
                r1[k] = qmc_float(a.z);
                rnd[k] = 0.0f;
                continue;
            }
            /* a slot, an entry of the tile, or the tree's or the table's random word */
            pick[k] = light_pick_takes_word(lp) ? rng_next_uint(rng) : rng_below(rng, draw_range);
            r0[k] = rng_next(rng);
            r1[k] = rng_next(rng);
            rnd[k] = rng_next(rng);
        }
        if (tiled) {
            light_tile_entries(tile_rec, tile_info, src.tile_base, pick, n, light, pick_pdf, rec);
        } else {
            light_pick_lights(lp, s->x, light_pick_normal(s), pick, n, q->on, light, pick_pdf);
            for (int k = 0; k < n; ++k) rec[k] = &lights[light[k]];
        }
        for (int k = 0; k < n; ++k) type[k] = light_type(rec[k]);  /* read here: the record's line on its way early */
#ifdef HAS_ENVIRONMENT
        /* the environment's map follows the records of the light buffer, not a tile's copy (lights/environment.h) */
        for (int k = 0; k < n; ++k) if (type[k] == LIGHT_ENVIRONMENT) rec[k] = &lights[light[k]];
#endif
#ifdef HAS_TRIANGLE_LIGHTS
        /* so do a textured triangle's image and block (lights/textured_emission.h) */
        if (tiled) for (int k = 0; k < n; ++k) if (light_textured(rec[k])) rec[k] = &lights[light[k]];
#endif
        for (int k = 0; k < n; ++k) {
            float py;
            float2 uv = light_sample_typed(rec[k], type[k], s->x, r0[k], r1[k], &py);
            float pdf = pick_pdf[k] * py;
#ifdef TEST_PICK_PDF_SCALE  /* negative controls of the tests only (tests/bias_controls.py): a wrong pdf */
            pdf *= TEST_PICK_PDF_SCALE;
#endif
            float t = pdf > 0.0f ? target_of_record(s, lights, rec[k], uv.x, uv.y, &e) : 0.0f;
            if (bsdf.mis_sample && t > 0.0f) {
                float m = bsdf_mis_light_weight(s, rec[k], type[k], light[k], bsdf, pdf, &e);
                t *= m;
                e.contrib *= m;  /* the contribution the shade multiplies by W: f m_l */
            }
#ifndef TEST_WITHOUT_MIXTURE_PDF  /* negative control (tests/bias_controls.py): light candidates keep p_light */
            if (bsdf.count > 0 && t > 0.0f)
                pdf = mis_mixture_pdf(n_light, pdf, n_bsdf,
                                      bsdf_pdf_of_light_sample(s, rec[k], type[k], light[k], bsdf, &e));
#endif
#ifdef PROBE_FLYFIRE  /* a scratch probe: the light candidates whose weight exceeds PROBE_FLYFIRE */
            if (t / pdf > PROBE_FLYFIRE)
                printf("light gid %d light %d type %d t %g pick %g py %g pmix %g d %g w %g\n", (int)get_global_id(0),
                       light[k], type[k], t, pick_pdf[k], py, pdf, e.dist, t / pdf);
#endif
            bool picked = q->on ? res_update_remap(r, light[k], uv.x, uv.y, t / pdf, t, &sel, 1.0f)
                                : res_update(r, light[k], uv.x, uv.y, t / pdf, t, rnd[k], 1.0f);
            if (picked) *chosen = e;
        }
    }
    if (bsdf.count > 0) bsdf_candidates(s, lights, lp, nodes, tris, tri_light, n_light, bsdf, rng, q,
                                     q->on ? &sel : 0, r, chosen);
}

#endif
