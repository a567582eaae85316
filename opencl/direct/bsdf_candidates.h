/* BSDF-sampled light candidates, combined with the light candidates by multiple importance sampling inside RIS
 * (DESIGN section 3; the scheme of RTXDI's initial sampling, written here for our samples y = (light, u, v)).
 *
 * A pixel draws N_l candidates from the light array (direct/ris.h) and N_b directions from its BSDF (bsdf_sample). A
 * direction that meets an emitter becomes a light sample y: an emissive triangle the BVH hits (tri_light maps the
 * triangle to its light), and every analytic light (quad, disk, sphere, spot, sun) the ray meets, each its own
 * candidate. Every candidate, whichever strategy drew it, streams with the resampling weight
 *     w(y) = p-hat(y) / p_mix(y),   p_mix = (N_l p_light(y) + N_b p_bsdf(y)) / (N_l + N_b),
 * and the reservoir counts M = N_l + N_b; W = w_sum / (M p-hat) as before. That is the balance heuristic over the
 * two strategies (m_s = N_s p_s / (N_l p_l + N_b p_b), weight m_s p-hat / p_s), written as one mixture density.
 * Both pdfs are in the light's measure (area for area lights, solid angle for the sun), like p-hat: p_light is the
 * light pick (light array or tree: light_pick_pdf) times light_sample's density of the point (lights/lights.h),
 * p_bsdf the BSDF's solid-angle density times cos_l / d^2. A direction that meets nothing adds 1 to M and no candidate.
 *
 * What the BSDF strategy cannot produce gets p_bsdf = 0 in every candidate's p_mix, so the weights still sum to one
 * wherever the light strategy reaches (everywhere a light emits): delta lights, and analytic lights beyond the
 * `analytic` first ones (a loop over them costs per ray; the host tests at most a bound). For analytic lights the
 * ray meets every light on its line, occluders or not, so p_bsdf is exact. For emissive triangles the BVH returns
 * the first triangle only: p_bsdf is right where the point is visible and 0 behind an occluder, where the
 * mixture overcounts it; those points are shadowed, so the shaded estimate stays unbiased, and so does reuse with
 * visibility reuse (a reservoir keeps only visible samples). Without visibility reuse, a neighbour's triangle
 * sample that is occluded at its own pixel but visible here is weighted slightly low. */
#ifndef RESTIRCL_BSDF_CANDIDATES_H
#define RESTIRCL_BSDF_CANDIDATES_H

#include "direct/thin_wall_rays.h"  /* HAS_THIN_SHADOW: BSDF rays find lights past smooth thin walls */

#include "sampling/qmc.h"

/* What the BSDF candidates of a frame look for (SamplerParams). */
typedef struct {
    int count;        /* BSDF candidates per pixel; 0: light candidates only */
    int analytic;     /* the first `analytic` lights (the scene's analytic lights) are tested against each ray */
    int triangles;    /* 1: emissive triangles are found through the BVH (tri_light) */
    int glossy_only;  /* 1: only at pixels whose material has a specular lobe (bsdf_sampling "auto") */
    int mis_sample;   /* 1: a BSDF sample outside the reservoir shares the integral (direct/bsdf_mis.h) */
} BsdfSource;

inline BsdfSource bsdf_source(SamplerParams sp)
{
    BsdfSource b = {sp.bsdf_candidates, sp.bsdf_analytic, sp.bsdf_triangles, sp.bsdf_glossy_only, 0};
    return b;
}

/* The BSDF candidates surface s gets: none on a diffuse pixel when they are for glossy ones only. The count depends
 * on the surface alone, so every pixel's estimator stays unbiased (M counts what it drew). */
inline BsdfSource bsdf_source_at(const Surface* s, BsdfSource b)
{
#ifdef HAS_GLOSSY
    if (b.glossy_only && s->mat.lobes == 0) b.count = 0;
#else
    if (b.glossy_only) b.count = 0;
#endif
    return b;
}

/* The BSDF's density of the evaluated light sample e at s, in the light's measure: solid angle times cos_l / d^2
 * for a point on an area light, the solid angle itself for the sun (dist INFINITY). */
inline float bsdf_pdf_light_measure(const Surface* s, const LightEval* e)
{
    float p = bsdf_pdf(s, s->wo, e->wi);
    if (!finite_f(e->dist)) return p;
    float cos_l = -dot3(e->nl, e->wi);
    return cos_l > 0.0f ? p * cos_l / (e->dist * e->dist) : 0.0f;
}

/* The mixture density of N_l light and N_b BSDF candidates at a point with these two densities. */
inline float mis_mixture_pdf(float n_light, float p_light, float n_bsdf, float p_bsdf)
{
    return (n_light * p_light + n_bsdf * p_bsdf) / (n_light + n_bsdf);
}

/* The BSDF's density of a light candidate that light sampling drew (e: its evaluation, index: its light). */
inline float bsdf_pdf_of_light_sample(const Surface* s, const __global Light* rec, int type, int index,
                                      BsdfSource b, const LightEval* e)
{
    return light_hittable(rec, type, index, b.analytic, b.triangles) ? bsdf_pdf_light_measure(s, e) : 0.0f;
}

#ifdef HAS_TRIANGLE_LIGHTS
/* The light of the emissive triangle that the ray from s in direction wi meets first (-1: none, or the first
 * triangle does not emit), and its sample *uv. */
inline int bsdf_ray_triangle_light(const Surface* s, const __global BVHNode* nodes, const __global Tri* tris,
                                   const __global int* tri_light, float3 wi, float2* uv)
{
    /* off the surface as visible() offsets a shadow ray (direct/visibility.h) */
    Tri tri = tris[s->prim];
    float err = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(s->x) + max_abs3(tri.e1.xyz) + max_abs3(tri.e2.xyz));
    float3 o = s->x + err * (dot3(s->ng, wi) >= 0.0f ? s->ng : -s->ng);
    Hit h = trace_closest(nodes, tris, o, wi, INFINITY);
#ifdef HAS_THIN_SHADOW  /* past smooth thin walls: the candidate's shadow ray passes them (direct/thin_wall_rays.h) */
    float3 pass;
    h = thin_wall_next(nodes, tris, h, o, wi, shadow_allowance(s), &pass);
    if (!shadow_any(pass)) h.prim = -1;
#endif
    int l = h.prim >= 0 ? tri_light[h.prim] : -1;
    if (l >= 0) *uv = triangle_uv(h.u, h.v);
    return l;
}
#endif

/* Stream the sample (u, v) of light `index` that a BSDF ray met, as one candidate (M unchanged). */
inline void bsdf_candidate_add(const Surface* s, const __global Light* lights, const __global Light* rec, int type,
                               int index, float2 uv,
                               const LightPick* lp, float n_light, BsdfSource b, uint* rng, float* sel,
                               Reservoir* r, LightEval* chosen)
{
    LightEval e;
    float rnd = sel ? 0.0f : rng_next(rng);
    float t = target_of_record(s, lights, rec, uv.x, uv.y, &e);
    if (!(t > 0.0f)) return;
    float p_light = light_pick_pdf(lp, index, s->x, light_pick_normal(s)) * light_point_pdf(rec, type, s->x, &e);
    float p_mix = mis_mixture_pdf(n_light, p_light, (float)b.count, bsdf_pdf_light_measure(s, &e));
#ifdef PROBE_FLYFIRE
    if (t / p_mix > PROBE_FLYFIRE)
        printf("bsdf gid %d light %d t %g p_light %g p_bsdf %g pmix %g d %g w %g\n", (int)get_global_id(0), index, t,
               p_light, bsdf_pdf_light_measure(s, &e), p_mix, e.dist, t / p_mix);
#endif
    bool picked = sel ? res_update_remap(r, index, uv.x, uv.y, t / p_mix, t, sel, 0.0f)
                      : res_update(r, index, uv.x, uv.y, t / p_mix, t, rnd, 0.0f);
    if (picked) *chosen = e;
}

/* Draw b.count BSDF directions at s and stream the light samples they meet into r (M += b.count). With q->on the
 * directions come from QMC pairs QMC_BSDF(k) and the resampling choices from *sel (res_update_remap). */
inline void bsdf_candidates(const Surface* s, const __global Light* lights, const LightPick* lp,
                            const __global BVHNode* nodes, const __global Tri* tris, const __global int* tri_light,
                            float n_light, BsdfSource b, uint* rng, const Qmc* q, float* sel, Reservoir* r,
                            LightEval* chosen)
{
    for (int k = 0; k < b.count; ++k) {
        float u0, u1;
        if (q->on) {
            float2 u = qmc_pair(q, QMC_BSDF(k));
            u0 = u.x;
            u1 = u.y;
        } else {
            u0 = rng_next(rng);
            u1 = rng_next(rng);
        }
        float3 wi;
        float pdf;
        bsdf_sample(s, s->wo, u0, u1, &wi, &pdf);
        r->M += 1.0f;
        if (!(pdf > 0.0f)) continue;
        for (int l = 0; l < b.analytic; ++l) {
            const __global Light* rec = &lights[l];
            int type = light_type(rec);
            float2 uv;
            if (light_hittable(rec, type, l, b.analytic, b.triangles) && light_hit(rec, type, s->x, wi, &uv))
                bsdf_candidate_add(s, lights, rec, type, l, uv, lp, n_light, b, rng, sel, r, chosen);
        }
#ifdef HAS_TRIANGLE_LIGHTS
        if (b.triangles) {
            float2 uv;
            int l = bsdf_ray_triangle_light(s, nodes, tris, tri_light, wi, &uv);
            if (l >= 0 && light_ray_findable(&lights[l]))  /* as light_hittable says for its light candidates */
                bsdf_candidate_add(s, lights, &lights[l], LIGHT_TRIANGLE, l, uv, lp, n_light, b, rng, sel, r,
                                   chosen);
        }
#endif
    }
}

#endif
