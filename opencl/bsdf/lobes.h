/* Every kind of lobe a pixel's BSDF may hold beyond its Lambert part, and the one place that dispatches on a lobe's
 * kind (lobe_kind, bsdf/lobe_record.h). A kind is one file, bsdf/<name>.h, that defines LOBE_<NAME> (its code, kept
 * in the record) and, for a Lobe record l about the lobes' normal n, with wo towards the viewer and wi towards the
 * light (unit vectors leaving the surface):
 *   float3 <name>_eval(l, n, wo, wi)             f, without the cosine at the surface;
 *   float  <name>_pdf(l, n, wo, wi)              the solid-angle density of <name>_sample's wi;
 *   bool   <name>_sample(l, n, wo, u0, u1, &wi)  a direction from (u0, u1) uniform in [0, 1)^2 (false: none);
 *   float3 <name>_albedo(l)                      what it reflects at normal incidence (the denoiser's guide);
 *   float2 <name>_weights(l)                     its weights summed over rgb: x metallic, y the rest (reuse);
 * and an encode step that fills the record (its alpha, sampling weight and kind through lobe_record). Registering
 * it is its include below and one line in BSDF_LOBE_KINDS, which expands into every dispatch function, so no
 * function can miss a kind (tests/materials/test_bsdf_lobes.py checks each kind's pieces and runs each one). */
#ifndef RESTIRCL_BSDF_LOBES_H
#define RESTIRCL_BSDF_LOBES_H

#include "bsdf/lobe_record.h"
#include "bsdf/microfacet_reflection.h"
#ifdef HAS_TRANSMISSION
#include "bsdf/microfacet_dielectric.h"
#include "bsdf/thin_dielectric.h"
#endif
#ifdef HAS_THIN_FILM
#include "bsdf/thin_film_reflection.h"
#endif

/* X(code, name) for every lobe kind; the dielectric (refracting) and thin dielectric lobes only in builds whose
 * scene transmits (HAS_TRANSMISSION), the thin-film reflection only where some closure has a film (HAS_THIN_FILM),
 * so that the others keep one kind and no test of it */
#if defined(HAS_TRANSMISSION) && defined(HAS_THIN_FILM)
#define BSDF_LOBE_KINDS(X) \
    X(LOBE_MICROFACET_REFLECTION, microfacet_reflection) \
    X(LOBE_MICROFACET_DIELECTRIC, microfacet_dielectric) \
    X(LOBE_THIN_DIELECTRIC, thin_dielectric) \
    X(LOBE_THIN_FILM_REFLECTION, thin_film_reflection)
#elif defined(HAS_TRANSMISSION)
#define BSDF_LOBE_KINDS(X) \
    X(LOBE_MICROFACET_REFLECTION, microfacet_reflection) \
    X(LOBE_MICROFACET_DIELECTRIC, microfacet_dielectric) \
    X(LOBE_THIN_DIELECTRIC, thin_dielectric)
#elif defined(HAS_THIN_FILM)
#define BSDF_LOBE_KINDS(X) \
    X(LOBE_MICROFACET_REFLECTION, microfacet_reflection) \
    X(LOBE_THIN_FILM_REFLECTION, thin_film_reflection)
#else
#define BSDF_LOBE_KINDS(X) \
    X(LOBE_MICROFACET_REFLECTION, microfacet_reflection)
#endif

#define LOBE_EVAL_CASE(code, name) case code: return name##_eval(l, n, wo, wi);
#define LOBE_PDF_CASE(code, name) case code: return name##_pdf(l, n, wo, wi);
#define LOBE_SAMPLE_CASE(code, name) case code: return name##_sample(l, n, wo, u0, u1, wi);
#define LOBE_ALBEDO_CASE(code, name) case code: return name##_albedo(l);
#define LOBE_WEIGHTS_CASE(code, name) case code: return name##_weights(l);

/* Each dispatch is a switch whose default is the first kind: with one kind registered the compiler drops the
 * test of the kind altogether. A record's kind is always a registered one (the resolves write only those;
 * tests/materials/test_closure_kinds.py checks that each closure kind's lobes are registered). A switch that
 * tested the first kind too and gave 0 to the others cost 4 % of a BSDF-bound kernel on PoCL (docs/design.md,
 * "The BSDF seam: lobes and closures"). */
inline float3 lobe_eval(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    switch (lobe_kind(l)) {
    default:
    BSDF_LOBE_KINDS(LOBE_EVAL_CASE)
    }
}

inline float lobe_pdf(const Lobe* l, float3 n, float3 wo, float3 wi)
{
    switch (lobe_kind(l)) {
    default:
    BSDF_LOBE_KINDS(LOBE_PDF_CASE)
    }
}

inline bool lobe_sample(const Lobe* l, float3 n, float3 wo, float u0, float u1, float3* wi)
{
    switch (lobe_kind(l)) {
    default:
    BSDF_LOBE_KINDS(LOBE_SAMPLE_CASE)
    }
}

inline float3 lobe_albedo(const Lobe* l)
{
    switch (lobe_kind(l)) {
    default:
    BSDF_LOBE_KINDS(LOBE_ALBEDO_CASE)
    }
}

inline float2 lobe_weights(const Lobe* l)
{
    switch (lobe_kind(l)) {
    default:
    BSDF_LOBE_KINDS(LOBE_WEIGHTS_CASE)
    }
}

#endif
