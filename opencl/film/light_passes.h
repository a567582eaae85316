/* Cycles' light passes (HAS_LIGHT_PASSES, Settings.light_passes; render/passes.py, docs/design.md "Light passes").
 * The kernels that add to a pixel's sample also write their share of it into planes of float4, plane p of pixel i
 * at lp[p * pixels + i] (LPASS_* in codes.h): the primary pass what the camera sees of the emitters and of the
 * world, and the colours of the first surface; the direct estimators the light that reaches the first surface
 * straight from the emitters; the path pass and ReSTIR GI the light that bounced. Light at the first surface is
 * split as Cycles splits it: a contribution that arrives from direction wi (for bounced light, the first bounce's
 * direction) is diffuse by the share f_d(wi) / f(wi) of the BSDF's Lambert part, per channel, and glossy by the
 * rest. The planes hold the light before the division by the colours, which the host makes once the samples are
 * summed (render/light_passes.py). */
#ifndef RESTIRCL_FILM_LIGHT_PASSES_H
#define RESTIRCL_FILM_LIGHT_PASSES_H

/* A plane's value of pixel i; NaN or Inf as 0, as the sample's guard makes them (guards.h) */
inline void light_pass_put(__global float4* lp, int pixels, int plane, int i, float3 v)
{
    lp[plane * pixels + i] = (float4)(finite3_f(v) ? v : (float3)(0.0f), 0.0f);
}

/* The diffuse share fd / f per channel (0 where f is: no light arrives there) */
inline float3 light_pass_share(float3 f, float3 fd)
{
    return (float3)(f.x > 0.0f ? fd.x / f.x : 0.0f, f.y > 0.0f ? fd.y / f.y : 0.0f, f.z > 0.0f ? fd.z / f.z : 0.0f);
}

/* The diffuse share of light arriving at s from wi */
inline float3 light_pass_diffuse_share(const Surface* s, float3 wi)
{
#ifdef HAS_GLOSSY
    return light_pass_share(bsdf_eval(s, s->wo, wi), bsdf_eval_diffuse(s, wi));
#else
    (void)s;
    (void)wi;
    return (float3)(1.0f);
#endif
}

/* Contribution c at s from wi split into the diffuse (*d) and glossy (*g) sums; the two add up to c */
inline void light_pass_split(const Surface* s, float3 wi, float3 c, float3* d, float3* g)
{
    float3 cd = c * light_pass_diffuse_share(s, wi);
    *d += cd;
    *g += c - cd;
}

/* The direct light of pixel i (diffuse d, glossy g); the bounced light's planes are cleared, for the path pass or
 * ReSTIR GI to fill where they run. k: Clamp Direct's scale of what the camera sees (1: not clamped). */
inline void light_pass_direct(__global float4* lp, int pixels, int i, float3 d, float3 g, float k)
{
    light_pass_put(lp, pixels, LPASS_DIFFUSE_DIRECT, i, d);
    light_pass_put(lp, pixels, LPASS_GLOSSY_DIRECT, i, g);
    light_pass_put(lp, pixels, LPASS_DIFFUSE_INDIRECT, i, (float3)(0.0f));
    light_pass_put(lp, pixels, LPASS_GLOSSY_INDIRECT, i, (float3)(0.0f));
    if (k != 1.0f) {
        lp[LPASS_EMISSION * pixels + i] *= k;
        lp[LPASS_ENVIRONMENT * pixels + i] *= k;
    }
}

/* What the camera ray of pixel i sees: emission e of emitters, environment w of the world, and the first surface's
 * colours (diffuse albedo, the lobes' reflectance at normal incidence) */
inline void light_pass_seen(__global float4* lp, int pixels, int i, float3 e, float3 w, float3 dc, float3 gc)
{
    light_pass_put(lp, pixels, LPASS_EMISSION, i, e);
    light_pass_put(lp, pixels, LPASS_ENVIRONMENT, i, w);
    light_pass_put(lp, pixels, LPASS_DIFFUSE_COLOR, i, dc);
    light_pass_put(lp, pixels, LPASS_GLOSSY_COLOR, i, gc);
}

/* The bounced light L of pixel i, of diffuse share `share` */
inline void light_pass_indirect(__global float4* lp, int pixels, int i, float3 L, float3 share)
{
    float3 d = L * share;
    light_pass_put(lp, pixels, LPASS_DIFFUSE_INDIRECT, i, d);
    light_pass_put(lp, pixels, LPASS_GLOSSY_INDIRECT, i, L - d);
}

#endif
