/* Weighted reservoir sampling of ReSTIR GI samples (GIReservoir, types.h): streaming update and finalisation to the
 * unbiased contribution weight W, as sampling/reservoir.h does for light samples. */
#ifndef RESTIRCL_RESTIR_GI_RESERVOIR_H
#define RESTIRCL_RESTIR_GI_RESERVOIR_H

inline void gi_res_init(GIReservoir* r)
{
    r->pos = (float4)(0.0f);
    r->normal = (float4)(0.0f);
    r->radiance = (float4)(0.0f);
    r->w_sum = 0.0f;
    r->M = 0.0f;
    r->W = 0.0f;
    r->target = 0.0f;
}

/* Stream src's sample with resampling weight w and its target at this reservoir's pixel; count is added to M. A
 * candidate of weight <= 0 (or NaN) is counted but never picked. Returns true if it was picked. */
inline bool gi_res_update(GIReservoir* r, const GIReservoir* src, float w, float target, float rnd, float count)
{
    r->M += count;
    if (!(w > 0.0f) || !finite_f(w)) return false;
    r->w_sum += w;
    if (rnd * r->w_sum < w) {
        r->pos = src->pos;
        r->normal = src->normal;
        r->radiance = src->radiance;
        r->target = target;
        return true;
    }
    return false;
}

/* W = w_sum / (norm * target): norm is M (biased reuse), Z (1/Z) or 1 (pairwise MIS, whose weights sum to one).
 * target 0 or a non-finite result leaves no sample (W = 0, target = 0). */
inline void gi_res_finalize(GIReservoir* r, float norm)
{
    float denom = norm * r->target;
    r->W = denom > 0.0f ? r->w_sum / denom : 0.0f;
    if (!finite_f(r->W) || !finite_f(r->w_sum) || !(r->W > 0.0f)) {
        r->W = 0.0f;
        r->w_sum = 0.0f;
        r->target = 0.0f;
    }
}

#endif
