/* Next-event estimation at a path vertex: one light from the frame's light pick (the light array, or the tree where
 * the frame samples from it), one point on it, its unshadowed contribution f * Le * cos * G weighted by its MIS
 * weight against the BSDF ray (path/mis.h), and a shadow ray. Cycles' Light Threshold is a Russian roulette on the
 * sample before its shadow ray: a contribution whose largest channel is below the threshold survives with
 * probability max / threshold and is divided by it, so the estimate stays unbiased and dim samples cost no ray.
 * With the Sobol sampler (q->on: still RIS renders) the pick and the point come from the vertex's own 4D group,
 * and the tree descends by the stratified remap of the pick's word (lights/tree.h light_tree_descend), as a RIS
 * candidate does: the word's strata over the frames stay strata over the leaves. */
#ifndef RESTIRCL_PATH_NEE_H
#define RESTIRCL_PATH_NEE_H

inline float3 path_nee(const Surface* s, const __global Light* lights, const LightPick* lp, int slot_count,
                       BsdfSource hits, const __global BVHNode* nodes, const __global Tri* tris, float threshold,
                       uint* rng, const Qmc* q, uint group, int* picked)
{
    uint word;
    float r0, r1;
    if (q->on) {  /* the pick and the point as one Sobol point, as a RIS light candidate's (direct/ris.h) */
        uint4 a = qmc_quad_bits(q, group);
        word = light_pick_takes_word(lp) ? a.x : (uint)(((ulong)a.x * (ulong)slot_count) >> 32);
        r0 = qmc_float(a.y);
        r1 = qmc_float(a.z);
    } else {
        word = light_pick_takes_word(lp) ? rng_next_uint(rng) : rng_below(rng, (uint)slot_count);
        r0 = rng_next(rng);
        r1 = rng_next(rng);
    }
    float r_keep = rng_next(rng);
    int light;
    float pick;
    /* a Sobol word: the stratified descent */
    light_pick_lights(lp, s->x, light_pick_normal(s), &word, 1, q->on, &light, &pick);
    *picked = light;
    const __global Light* rec = &lights[light];
    int type = light_type(rec);
    float point;
    float2 uv = light_sample_typed(rec, type, s->x, r0, r1, &point);
    float p_light = pick * point;
    LightEval e;
    if (!(p_light > 0.0f) || !surface_light_eval(s, rec, uv.x, uv.y, &e) || !light_links(lights, rec, s, &e))
        return (float3)(0.0f);
    float w = path_mis_weight(p_light, path_bsdf_pdf(s, rec, type, light, hits, &e));
#ifdef TEST_PATH_LINKED_NEE_WEIGHT_ONE  /* negative control of tests/render/test_path_linked_lights.py only */
    if (!light_ray_findable(rec)) w = 1.0f;
#endif
    float3 c = unshadowed_contrib(s, &e) * (w / p_light);
    if (threshold > 0.0f) {
        float keep = fmax_f(c.x, fmax_f(c.y, c.z)) / threshold;
        if (keep < 1.0f) {
            if (!(r_keep < keep)) return (float3)(0.0f);
            c /= keep;
        }
    }
    Shadow v;
    if (!(luminance(c) > 0.0f) || !shadow_any(v = transmittance(nodes, tris, s, &e))) return (float3)(0.0f);
    return c * v;
}

#endif
