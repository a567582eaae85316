/* One BSDF-sampled direction per pixel with its own shadow ray beside the RIS light sample, the two combined by
 * multiple importance sampling (the `ris` sampler's --bsdf-mis-sample; Cycles' light sample + BSDF sample, with RIS
 * as the light strategy).
 *
 * Why: RIS resamples by the unshadowed contribution, so where a bright small emitter (a sun in a sky) is occluded,
 * the one shadow ray still goes to it most of the time and the rest of the light (the sky) gets few samples. A
 * BSDF direction with its own shadow ray samples the sky there whatever the sun does. BSDF candidates inside the
 * reservoir (direct/bsdf_candidates.h) do not help with this: the reservoir still picks by the unshadowed contribution.
 *
 * The two estimators split the integrand by a partition of unity over light samples y, with the balance heuristic
 * of the light strategy's source density p_l(y) (pick pdf x point pdf) and the BSDF's density p_b(y) in the same
 * measure (bsdf_pdf_light_measure): m_b = p_b / (p_l + p_b), m_l = 1 - m_b. RIS estimates the integral of f m_l:
 * each light candidate's target and contribution are scaled by m_l (bsdf_mis_light_weight). The BSDF sample
 * estimates the integral of f m_b: f(y) m_b(y) / p_b(y) = f(y) / (p_l + p_b) for every light its ray meets (the
 * analytic ones and the first emissive triangle, as bsdf_candidates finds them). Where the BSDF cannot produce y
 * (delta lights, lights beyond the tested ones) p_b = 0 and m_l = 1; an emissive triangle behind an occluder gets
 * p_b > 0 though the ray meets the occluder, but there f's visibility is 0 for both parts, so the sum stays f. */
#ifndef RESTIRCL_BSDF_MIS_H
#define RESTIRCL_BSDF_MIS_H

/* m_l of a light candidate with source density p_light (its evaluation e) when a BSDF sample shares the integral. */
inline float bsdf_mis_light_weight(const Surface* s, const __global Light* rec, int type, int index, BsdfSource b,
                                   float p_light, const LightEval* e)
{
    float p_b = light_hittable(rec, type, index, b.analytic, b.triangles) ? bsdf_pdf_light_measure(s, e) : 0.0f;
#ifdef TEST_WITHOUT_MIS_WEIGHT  /* negative control (tests/bias_controls.py): the light sample's MIS weight dropped */
    return 1.0f;
#endif
    return p_b > 0.0f ? p_light / (p_light + p_b) : 1.0f;
}

/* The BSDF part of light `index` met in direction-sample (u, v): f m_b / p_b, shadowed. */
inline float3 bsdf_mis_term(const Surface* s, const __global Light* lights, const __global Light* rec, int type,
                            int index, float2 uv, const LightPick* lp, const __global BVHNode* nodes,
                            const __global Tri* tris)
{
    LightEval e;
    if (!(target_of_record(s, lights, rec, uv.x, uv.y, &e) > 0.0f)) return (float3)(0.0f);
    float p_b = bsdf_pdf_light_measure(s, &e);
    float p_l = light_pick_pdf(lp, index, s->x, light_pick_normal(s)) * light_point_pdf(rec, type, s->x, &e);
#ifdef HAS_THIN_SHADOW  /* through a smooth thin wall the light keeps its colour T */
    Shadow v;
    if (!(p_b > 0.0f) || !shadow_any(v = transmittance(nodes, tris, s, &e))) return (float3)(0.0f);
    return unshadowed_contrib(s, &e) * v / (p_l + p_b);
#else
    if (!(p_b > 0.0f) || !visible(nodes, tris, s, &e)) return (float3)(0.0f);
    return unshadowed_contrib(s, &e) / (p_l + p_b);
#endif
}

/* Draw one BSDF direction at s (*wi_out) and return its MIS-weighted, shadowed contribution (the lights it meets; each
 * light's share also to *groups, film/light_groups.h). With QMC
 * (q->on) the direction comes from the pixel's Sobol pair QMC_BSDF_MIS: where the light sample's shadow ray is
 * blocked (a sun behind an occluder) this sample carries the sky, and stratified across a still's frames its
 * error falls faster than with random numbers, as the light sample's does. */
inline float3 bsdf_mis_sample(const Surface* s, const __global Light* lights, const LightPick* lp,
                              const __global BVHNode* nodes, const __global Tri* tris, const __global int* tri_light,
                              BsdfSource b, uint* rng, const Qmc* q, float3* wi_out, GroupLight* groups)
{
    float2 u;
    if (q->on) {
        u = qmc_pair(q, QMC_BSDF_MIS);
    } else {
        u.x = rng_next(rng);  /* in this order: the random stream stays as it was */
        u.y = rng_next(rng);
    }
    float3 wi;
    float pdf;
    float3 c = (float3)(0.0f);
    bsdf_sample(s, s->wo, u.x, u.y, &wi, &pdf);
    *wi_out = wi;
    if (!(pdf > 0.0f)) return c;
    for (int l = 0; l < b.analytic; ++l) {
        const __global Light* rec = &lights[l];
        int type = light_type(rec);
        float2 uv;
        if (light_hittable(rec, type, l, b.analytic, b.triangles) && light_hit(rec, type, s->x, wi, &uv)) {
            float3 t = bsdf_mis_term(s, lights, rec, type, l, uv, lp, nodes, tris);
            c += t;
            GROUP_ADD(groups, lights, rec, t);
        }
    }
#ifdef HAS_TRIANGLE_LIGHTS
    if (b.triangles) {
        float2 uv;
        int l = bsdf_ray_triangle_light(s, nodes, tris, tri_light, wi, &uv);
        if (l >= 0 && light_ray_findable(&lights[l])) {  /* as light_hittable says for the light sample */
            float3 t = bsdf_mis_term(s, lights, &lights[l], LIGHT_TRIANGLE, l, uv, lp, nodes, tris);
            c += t;
            GROUP_ADD(groups, lights, &lights[l], t);
        }
    }
#endif
    (void)groups;
    return c;
}

#endif
