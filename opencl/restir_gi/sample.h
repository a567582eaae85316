/* A ReSTIR GI sample (GIReservoir, types.h) seen from a receiving surface: the secondary point x_s with its normal
 * n_s and the radiance L_o that leaves it, reconnected to the receiver's visible point x_r.
 *
 * Its target at the receiver is the luminance of f_r(wo_r, w) cos_r L_o, w the unit direction x_r -> x_s: the
 * receiver's whole BSDF, so a glossy receiver evaluates its own lobes. L_o is taken as the same towards every
 * receiver, which holds where x_s is Lambertian (the walk's own choices after x_s do not depend on where it came
 * from: restir_gi/initial.cl); a glossy x_s makes reuse an approximation, as in the paper and RTXDI.
 *
 * A reservoir's W is in solid angle at its own visible point. Taking a sample from visible point x_q to x_r changes
 * its direction, and densities change by the Jacobian |J| = (cos phi_r / |x_r - x_s|^2) / (cos phi_q / |x_q -
 * x_s|^2), phi the angle at x_s between n_s and the direction to that visible point: gi_geometry is the factor of one
 * side. A receiver behind x_s (cos phi <= 0) cannot take the sample; one whose |J| lies outside [1/GI_JACOBIAN_MAX,
 * GI_JACOBIAN_MAX] does not either (the reconnection is defined only there, in both directions alike, so the
 * unbiased modes stay unbiased: restir_gi/reuse.h). */
#ifndef RESTIRCL_RESTIR_GI_SAMPLE_H
#define RESTIRCL_RESTIR_GI_SAMPLE_H

/* The band of |J| within which a sample moves between visible points (RTXDI rejects beyond 10x as well): a sample
 * whose solid angle shrinks or grows more than this is an outlier of variance (a wall seen at grazing angles). */
#ifndef GI_JACOBIAN_MAX
#define GI_JACOBIAN_MAX 10.0f
#endif

/* Whether r holds a sample: one was picked (target > 0) and it counts (W > 0). */
inline bool gi_has_sample(const GIReservoir* r) { return r->target > 0.0f && r->W > 0.0f; }

/* cos phi / d^2 at r's sample towards visible point x (0 where x lies behind it or on it) */
inline float gi_geometry(float3 x, const GIReservoir* r)
{
    float3 d = x - r->pos.xyz;
    float d2 = dot3(d, d);
    float c = dot3(r->normal.xyz, d);
    return (d2 > 0.0f && c > 0.0f) ? c / (d2 * sqrt(d2)) : 0.0f;
}

/* The receiver's Jacobian of a sample from visible point x_q (its side g_q) at the receiver (side g_r): d omega_r /
 * d omega_q, 0 where either side cannot see the sample. */
inline float gi_jacobian(float g_r, float g_q) { return (g_r > 0.0f && g_q > 0.0f) ? g_r / g_q : 0.0f; }

inline bool gi_jacobian_ok(float j)
{
#ifdef GI_WITHOUT_JACOBIAN  /* defined only by the negative control of tests/render/test_restir_gi.py */
    return j > 0.0f;
#else
    return j >= 1.0f / GI_JACOBIAN_MAX && j <= GI_JACOBIAN_MAX;
#endif
}

/* The factor a sample's W takes when it moves by Jacobian j (1 in the negative control that leaves it out). */
inline float gi_jacobian_factor(float j)
{
#ifdef GI_WITHOUT_JACOBIAN
    (void)j;
    return 1.0f;
#else
    return j;
#endif
}

/* f_r cos_r L_o of r's sample at receiver s in *contrib and its luminance (the target, 0 where s cannot take it), and
 * the receiver's side of the Jacobian in *g. */
inline float gi_target(const Surface* s, const GIReservoir* r, float3* contrib, float* g)
{
    *g = 0.0f;
    if (!s->valid) return 0.0f;
    float3 d = r->pos.xyz - s->x;
    float d2 = dot3(d, d);
    if (!(d2 > 0.0f)) return 0.0f;
    float3 wi = d * (1.0f / sqrt(d2));
    float cos_r = dot3(s->n, wi);
    *g = gi_geometry(s->x, r);
    if (!(cos_r > 0.0f) || !(*g > 0.0f)) return 0.0f;
    *contrib = bsdf_eval(s, s->wo, wi) * (cos_r * r->radiance.xyz);
    float t = luminance(*contrib);
    return (t > 0.0f && finite_f(t)) ? t : 0.0f;
}

/* Whether x_s of r is visible from s: the shadow ray leaves s as direct/visibility.h's does and ends 1e-4 of its
 * length short of x_s (x_s's own triangle is not known here; that margin is far above float32's rounding of both
 * ends). */
inline bool gi_visible(const __global BVHNode* nodes, const __global Tri* tris, const Surface* s, const GIReservoir* r)
{
    Tri tri = tris[s->prim];
    float err = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(s->x) + max_abs3(tri.e1.xyz) + max_abs3(tri.e2.xyz));
    float3 d = r->pos.xyz - s->x;
    float3 o = s->x + err * (dot3(s->ng, d) >= 0.0f ? s->ng : -s->ng);
    d = r->pos.xyz - o;
    float len = len3(d);
    if (!(len > 0.0f)) return true;
    return !trace_any(nodes, tris, o, d / len, len * 0.9999f);
}

#endif
