/* The weights of a path's two ways to find an emitter at a vertex: next-event estimation (a light sample with a
 * shadow ray, path/nee.h) and the BSDF-sampled ray that happens to meet it (path/emitters.h). Both take the power
 * heuristic (beta = 2, as Cycles) of the two densities of the same point in the light's measure: p_light, the light
 * pick times light_sample's density of the point, and p_bsdf, the BSDF's solid-angle density times cos_l / d^2
 * (bsdf_pdf_light_measure). A light that BSDF rays cannot meet (a delta, or an analytic light beyond the tested ones)
 * has p_bsdf = 0: its NEE weight is 1 and no ray ever finds it, so the weights of every point sum to one. */
#ifndef RESTIRCL_PATH_MIS_H
#define RESTIRCL_PATH_MIS_H

/* The power heuristic's weight of the strategy of density p against the other's q. */
inline float path_mis_weight(float p, float q)
{
    float p2 = p * p, q2 = q * q;
    return p2 > 0.0f ? p2 / (p2 + q2) : 0.0f;
}

/* Can a BSDF ray of the path find light `index` (hits: what the path's rays look for)? As light_hittable, and
 * also an analytic light whose shadows are linked: path/emitters.h tests the light's own blockers between the
 * vertex and the light, as NEE's shadow ray does, where the ray itself stops at the first surface it meets. */
inline bool path_light_hittable(const __global Light* rec, int type, int index, BsdfSource hits)
{
#ifdef TEST_PATH_LINKED_NEE_ONLY  /* the reference of tests/render/test_path_linked_lights.py only: NEE alone */
    return light_hittable(rec, type, index, hits.analytic, hits.triangles);
#else
    return (type != LIGHT_TRIANGLE || light_ray_findable(rec))
           && light_type_hittable(rec, type, index, hits.analytic, hits.triangles);
#endif
}

/* The BSDF's density of light sample e at s, where a BSDF ray of the path can find light `index`, else 0. */
inline float path_bsdf_pdf(const Surface* s, const __global Light* rec, int type, int index, BsdfSource hits,
                           const LightEval* e)
{
    return path_light_hittable(rec, type, index, hits) ? bsdf_pdf_light_measure(s, e) : 0.0f;
}

#endif
