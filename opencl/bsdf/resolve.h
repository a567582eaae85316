/* Resolving a material's closures at a primary hit into what the BSDF evaluates (bsdf/bsdf.h): the diffuse albedo
 * (GSample.albedo) and up to MAX_LAYERS lobes (GlossySample), for this pixel's view direction. Each closure kind
 * (CLOSURE_* in types.h; python/restircl/materials/closures/ on the host) has its resolve in
 * bsdf/closures/<kind>.h, reached through the one switch below: a new kind is its file, its include and its case.
 * Everything depends on the view only through mu = cos(n, wo), so it is done once per pixel here and not in the
 * shading passes. Inputs come as ClosureInputs (textures/closure_inputs.h), whether constants or texture values. */
#ifndef RESTIRCL_BSDF_RESOLVE_H
#define RESTIRCL_BSDF_RESOLVE_H

#include "bsdf/closure.h"
#include "bsdf/closures/diffuse.h"
#include "bsdf/closures/glossy.h"
#include "bsdf/closures/principled.h"
#ifdef HAS_TRANSMISSION
#include "bsdf/closures/glass.h"
#include "bsdf/closures/refraction.h"
#endif
#if defined(HAS_TRANSMISSION) || defined(HAS_THIN_FILM)
/* a Principled BSDF with transmission or a thin film adds up to two lobes: room for every closure's, of which
 * MAX_LAYERS are kept */
#define RESOLVE_SLOTS (2 * MAX_LAYERS)
#else
#define RESOLVE_SLOTS MAX_LAYERS
#endif

/* Closure c at view cosine mu: its diffuse albedo (returned) and the lobes it adds (lobes[0 .. *count)). Every kind
 * adds one at most, except a Principled BSDF with transmission (its reflection and its glass) or with a thin film
 * (its metal's and its specular's, bsdf/closures/principled_thin_film.h): the G-buffer keeps
 * the first MAX_LAYERS lobes of a material (the host warns where a material makes more: materials/check.py). */
inline float3 closure_resolve(const ClosureInputs* c, float mu, const __global float* tab, Lobe* lobes, int* count)
{
    float w = fmax_f(c->weight, 0.0f);
    float3 base = max0_3(c->base);
    *count = 0;
    if (w <= CLOSURE_WEIGHT_CUTOFF) return (float3)(0.0f);
    switch (c->kind) {
    case CLOSURE_PRINCIPLED: return principled_resolve(c, w, base, mu, tab, lobes, count);
    case CLOSURE_DIFFUSE: return diffuse_resolve(c, w, base, mu, tab, lobes, count);
    case CLOSURE_GLOSSY: return glossy_resolve(c, w, base, mu, tab, lobes, count);
#ifdef HAS_TRANSMISSION
    case CLOSURE_GLASS: return glass_resolve(c, w, base, mu, tab, lobes, count);
    case CLOSURE_REFRACTION: return refraction_resolve(c, w, base, mu, tab, lobes, count);
#endif
    default: break;  /* the host validates kinds: none else reaches here */
    }
    return (float3)(0.0f);
}

/* Resolve count closures (at most MAX_LAYERS) at a surface of normal n seen from wo: the diffuse albedo (returned)
 * and the G-buffer extension *out (wo and the lobes). */
inline float3 surface_resolve(const ClosureInputs* in, int count, float3 n, float3 wo, const __global float* tab,
                              GlossySample* out)
{
    float mu = clamp_f(dot3(n, wo), 0.0f, 1.0f);
    float3 diffuse = (float3)(0.0f);
    Lobe lobes[RESOLVE_SLOTS];
    int k = 0;
    for (int c = 0; c < min(count, MAX_LAYERS); ++c) {
        int added;
        diffuse += closure_resolve(&in[c], mu, tab, &lobes[k], &added);
        k += added;
    }
    k = min(k, MAX_LAYERS);
    MicrofacetReflection unused = microfacet_reflection_none(1.0f);
    Lobe none = microfacet_reflection_lobe(&unused, 0.0f);
    out->wo = (float4)(wo, as_float(k));
    out->lobe0 = k > 0 ? lobes[0] : none;
    out->lobe1 = k > 1 ? lobes[1] : none;
    return diffuse;
}

#endif
