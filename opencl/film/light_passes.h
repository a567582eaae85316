/* Cycles' light passes (HAS_LIGHT_PASSES, Settings.light_passes; render/passes.py, docs/design.md "Light passes").
 * The kernels that add to a pixel's sample also write their share of it into planes of float4, plane p of pixel i
 * at lp[p * pixels + i] (LPASS_* in codes.h): the primary pass what the camera sees of the emitters and of the
 * world, and the colours of the first surface; the direct estimators the light that reaches the first surface
 * straight from the emitters; the path pass and ReSTIR GI the light that bounced. Light at the first surface is
 * split as Cycles splits it: a contribution that arrives from direction wi (for bounced light, the first bounce's
 * direction) is transmission where wi lies behind the surface (only a dielectric lobe scatters there: Cycles counts
 * a glass closure as transmission for directions on the far side of its normal), else diffuse by the share
 * f_d(wi) / f(wi) of the BSDF's Lambert part, per channel, and glossy by the rest. The planes hold the light before
 * the division by the colours, which the host makes once the samples are summed (render/light_passes.py). */
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

/* Whether light from wi reaches s through it (wi behind the surface): Transmission's, not Diffuse's or Glossy's */
inline int light_pass_through(const Surface* s, float3 wi)
{
#ifdef HAS_TRANSMISSION
    return dot3(s->n, wi) < 0.0f;
#else
    (void)s;
    (void)wi;
    return 0;
#endif
}

/* Contribution c at s from wi split into the diffuse (*d), glossy (*g) and transmission (*t) sums; they add up to c */
inline void light_pass_split(const Surface* s, float3 wi, float3 c, float3* d, float3* g, float3* t)
{
    if (light_pass_through(s, wi)) {
        *t += c;
        return;
    }
    float3 cd = c * light_pass_diffuse_share(s, wi);
    *d += cd;
    *g += c - cd;
}

/* The direct light of pixel i (diffuse d, glossy g, transmission t); the bounced light's planes are cleared, for the
 * path pass or ReSTIR GI to fill where they run. k: Clamp Direct's scale of what the camera sees (1: not clamped). */
inline void light_pass_direct(__global float4* lp, int pixels, int i, float3 d, float3 g, float3 t, float k)
{
    light_pass_put(lp, pixels, LPASS_DIFFUSE_DIRECT, i, d);
    light_pass_put(lp, pixels, LPASS_GLOSSY_DIRECT, i, g);
    light_pass_put(lp, pixels, LPASS_TRANSMISSION_DIRECT, i, t);
    light_pass_put(lp, pixels, LPASS_DIFFUSE_INDIRECT, i, (float3)(0.0f));
    light_pass_put(lp, pixels, LPASS_GLOSSY_INDIRECT, i, (float3)(0.0f));
    light_pass_put(lp, pixels, LPASS_TRANSMISSION_INDIRECT, i, (float3)(0.0f));
    if (k != 1.0f) {
        lp[LPASS_EMISSION * pixels + i] *= k;
        lp[LPASS_ENVIRONMENT * pixels + i] *= k;
    }
}

/* What the camera ray of pixel i sees: emission e of emitters, environment w of the world, and the first surface's
 * colours (diffuse albedo, the lobes' reflectance at normal incidence); its transmission colour 0, which
 * light_pass_transmission_colour then sets where the surface transmits */
inline void light_pass_seen(__global float4* lp, int pixels, int i, float3 e, float3 w, float3 dc, float3 gc)
{
    light_pass_put(lp, pixels, LPASS_EMISSION, i, e);
    light_pass_put(lp, pixels, LPASS_ENVIRONMENT, i, w);
    light_pass_put(lp, pixels, LPASS_DIFFUSE_COLOR, i, dc);
    light_pass_put(lp, pixels, LPASS_GLOSSY_COLOR, i, gc);
    light_pass_put(lp, pixels, LPASS_TRANSMISSION_COLOR, i, (float3)(0.0f));
}

#ifdef HAS_TRANSMISSION
/* The transmission colour of pixel i (Cycles' Transmission Color): what the dielectric lobes of s let through at its
 * view, 1 - F at the lobes' normal times the refraction's tint (bsdf/microfacet_dielectric.h), as Cycles estimates a
 * glass closure's transmission albedo */
inline void light_pass_transmission_colour(__global float4* lp, int pixels, int i, const Surface* s)
{
    float3 tc = (float3)(0.0f);
    for (int k = 0; k < s->mat.lobes; ++k)
        if (lobe_kind(&s->mat.lobe[k]) == LOBE_MICROFACET_DIELECTRIC)
            tc += microfacet_dielectric_transmittance(&s->mat.lobe[k], dot3(s->nl, s->wo));
        else if (lobe_kind(&s->mat.lobe[k]) == LOBE_THIN_DIELECTRIC)
            tc += thin_dielectric_transmittance(&s->mat.lobe[k]);
    light_pass_put(lp, pixels, LPASS_TRANSMISSION_COLOR, i, tc);
}
#endif

/* The bounced light L of pixel i: all transmission where its first bounce went through the surface (`through`), else
 * diffuse by the share `share` and glossy by the rest */
inline void light_pass_indirect(__global float4* lp, int pixels, int i, float3 L, float3 share, int through)
{
    float3 d = through ? (float3)(0.0f) : L * share;
    light_pass_put(lp, pixels, LPASS_DIFFUSE_INDIRECT, i, d);
    light_pass_put(lp, pixels, LPASS_GLOSSY_INDIRECT, i, through ? (float3)(0.0f) : L - d);
    light_pass_put(lp, pixels, LPASS_TRANSMISSION_INDIRECT, i, through ? L : (float3)(0.0f));
}

#endif
