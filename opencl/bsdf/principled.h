/* Resolving a material's closures at a primary hit into what the BSDF evaluates (bsdf/bsdf.h): the diffuse albedo
 * (GSample.albedo) and up to MAX_LAYERS GGX lobes (GlossySample), for this pixel's view direction. It follows
 * Cycles 4.x/5.0's Principled BSDF without coat, sheen, subsurface and transmission:
 *   metal     weight w * metallic, F82-tint Fresnel from the clamped Base Color with Specular Tint as the tint;
 *   specular  weight w * (1 - metallic), the real dielectric Fresnel of the IOR remapped onto [f0, 1], f0 = F0(IOR)
 *             scaled by 2 * Specular IOR Level (0.5: unchanged; 0: no specular) times Specular Tint;
 *   diffuse   Lambert, Base Color * w * (1 - metallic) * (1 - the specular's estimated albedo at this view), the
 *             albedo-scaling layering that keeps diffuse + specular <= 1;
 * metal and specular share one GGX distribution (alpha = Roughness^2). Multiscatter GGX scales each part by
 * 1 + F_ms (1 - E) / E (Kulla and Conty's compensation with a Fresnel-coloured multiple-scattering term, E and E_avg
 * from the tables), which makes a white metal reflect all the energy at every roughness. The Glossy BSDF is the
 * metal part with f0 = 1 (no Fresnel) and its colour as the weight; the Diffuse BSDF is the Lambert part (its
 * Roughness, Oren-Nayar, is not modelled). Everything depends on the view only through mu = cos(n, wo), so it is
 * done once per pixel here and not in the shading passes. Inputs come as ClosureInputs (textures/closure_inputs.h), whether
 * constants or texture values. */
#ifndef RESTIRCL_BSDF_PRINCIPLED_H
#define RESTIRCL_BSDF_PRINCIPLED_H

#define CLOSURE_WEIGHT_CUTOFF 1e-5f

inline float avg3(float3 c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

inline float3 max0_3(float3 c) { return (float3)(fmax_f(c.x, 0.0f), fmax_f(c.y, 0.0f), fmax_f(c.z, 0.0f)); }

/* The multiscatter factor 1 + F_ms (1 - E) / E of a lobe whose single-scattering Fresnel averages f_ss. */
inline float3 multiscatter_factor(float3 f_ss, float e, float e_avg)
{
    float3 f_ms = f_ss * e_avg / ((float3)(1.0f) - f_ss * (1.0f - e_avg));
    return (float3)(1.0f) + f_ms * ((1.0f - e) / e);
}

inline SpecLobe spec_lobe_empty(float alpha)
{
    SpecLobe l;
    l.metal_f0 = (float4)(0.0f, 0.0f, 0.0f, alpha);
    l.metal_b = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
    l.metal_w = (float4)(0.0f);
    l.diel_f0 = (float4)(0.0f);
    l.diel_w = (float4)(0.0f);
    return l;
}

/* Closure c at view cosine mu: its diffuse albedo (returned) and, when it has one, its lobe (*lobe, *has_lobe). */
inline float3 closure_resolve(const ClosureInputs* c, float mu, const __global float* tab, SpecLobe* lobe,
                              bool* has_lobe)
{
    float w = fmax_f(c->weight, 0.0f);
    float3 base = max0_3(c->base);
    *has_lobe = false;
    if (w <= CLOSURE_WEIGHT_CUTOFF) return (float3)(0.0f);
    if (c->kind == CLOSURE_DIFFUSE) return base * w;
    float r = clamp_f(c->roughness, 0.0f, 1.0f);
    float alpha = fmax_f(r * r, GGX_ALPHA_MIN);
    float e = 1.0f, e_avg = 1.0f;
    bool ms = c->multiscatter != 0;
    if (ms) {
        e = fmax_f(ggx_albedo(tab, r, mu), 1e-3f);
        e_avg = fmax_f(ggx_albedo_avg(tab, r), 1e-3f);
    }
    SpecLobe l = spec_lobe_empty(alpha);
    if (c->kind == CLOSURE_GLOSSY) {
        l.metal_f0.xyz = (float3)(1.0f);
        l.metal_w.xyz = base * w * (ms ? multiscatter_factor(base, e, e_avg) : (float3)(1.0f));
        l.diel_f0.w = avg3(l.metal_w.xyz);
        *lobe = l;
        *has_lobe = true;
        return (float3)(0.0f);
    }
    /* Principled */
    float metallic = clamp_f(c->metallic, 0.0f, 1.0f);
    float3 tint = max0_3(c->tint);
    float sample_w = 0.0f;
    if (metallic > CLOSURE_WEIGHT_CUTOFF) {
        float3 f0 = saturate3(base);
        float3 f82 = (float3)(fmin_f(tint.x, 1.0f), fmin_f(tint.y, 1.0f), fmin_f(tint.z, 1.0f));
        float3 b = (f82.x == 1.0f && f82.y == 1.0f && f82.z == 1.0f) ? (float3)(0.0f) : fresnel_f82_b(f0, f82);
        l.metal_f0.xyz = f0;
        l.metal_b.xyz = b;
        l.metal_w.xyz = (float3)(w * metallic) * (ms ? multiscatter_factor(fresnel_f82_avg(f0, b), e, e_avg)
                                                     : (float3)(1.0f));
        sample_w += avg3(l.metal_w.xyz * fresnel_f82(mu, f0, b));
        *has_lobe = true;
    }
    float wr = w * (1.0f - metallic);
    float ior = fmax_f(c->ior, 1e-5f);
    float f0 = f0_from_ior(ior);
    float eta = ior;
    float level = fmax_f(c->specular, 0.0f);
    if (level != 0.5f) {
        f0 *= 2.0f * level;
        eta = ior_from_f0(f0);
        if (ior < 1.0f) eta = 1.0f / eta;
    }
    float3 diffuse_w = (float3)(wr);
    if (wr > CLOSURE_WEIGHT_CUTOFF && eta > 1.0f) {  /* an IOR <= 1: no reflection modelled (no transmission) */
        float3 df0 = saturate3((float3)(f0) * tint);
        float f0_eta = f0_from_ior(eta);
        float s_avg = clamp_f((fresnel_dielectric_avg(eta) - f0_eta) / (1.0f - f0_eta), 0.0f, 1.0f);
        float3 darkening = (float3)(1.0f);
        float3 comp = (float3)(1.0f);
        if (ms) {
            comp = multiscatter_factor(mix3(df0, (float3)(1.0f), s_avg), e, e_avg);
            darkening = comp * e;
        }
        l.metal_b.w = eta;
        l.metal_w.w = f0_eta;
        l.diel_f0.xyz = df0;
        l.diel_w.xyz = (float3)(wr) * comp;
        sample_w += avg3(l.diel_w.xyz * fresnel_principled(mu, eta, f0_eta, df0));
        /* layering: the diffuse gets what the specular's estimated albedo at this view leaves */
        float3 albedo = darkening * mix3(df0, (float3)(1.0f), ggx_fresnel_blend(tab, r, mu, eta));
        diffuse_w *= clamp_f(1.0f - max3_f(albedo), 0.0f, 1.0f);
        *has_lobe = true;
    }
    /* a lobe that reflects only at grazing half vectors still needs a chance to be sampled */
    l.diel_f0.w = fmax_f(sample_w, 1e-3f * (avg3(l.metal_w.xyz) + avg3(l.diel_w.xyz)));
    *lobe = l;
    return base * diffuse_w;
}

/* Resolve count closures (at most MAX_LAYERS) at a surface of normal n seen from wo: the diffuse albedo (returned)
 * and the G-buffer extension *out (wo and the lobes). */
inline float3 surface_resolve(const ClosureInputs* in, int count, float3 n, float3 wo, const __global float* tab,
                              GlossySample* out)
{
    float mu = clamp_f(dot3(n, wo), 0.0f, 1.0f);
    float3 diffuse = (float3)(0.0f);
    SpecLobe lobes[MAX_LAYERS];
    int k = 0;
    for (int c = 0; c < min(count, MAX_LAYERS); ++c) {
        bool has_lobe;
        diffuse += closure_resolve(&in[c], mu, tab, &lobes[k], &has_lobe);
        if (has_lobe) ++k;
    }
    out->wo = (float4)(wo, as_float(k));
    out->lobe0 = k > 0 ? lobes[0] : spec_lobe_empty(1.0f);
    out->lobe1 = k > 1 ? lobes[1] : spec_lobe_empty(1.0f);
    return diffuse;
}

#endif
