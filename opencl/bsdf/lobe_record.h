/* The lanes of the 80-byte Lobe record (types.h) that every lobe kind fills the same way: its alpha (roughness^2)
 * in a.w, which reuse (surface/surface.h) and TAA (surface/view_dependence.h) read to tell a sharp lobe from a
 * rough one; its sampling weight in d.w, the share of the BSDF's samples it draws (bsdf/bsdf.h), its albedo as
 * estimated for the pixel's view; and its kind code in e.w, which bsdf/lobes.h dispatches on. What the other lanes
 * mean depends on the kind: each bsdf/<kind>.h decodes them into named fields. */
#ifndef RESTIRCL_BSDF_LOBE_RECORD_H
#define RESTIRCL_BSDF_LOBE_RECORD_H

#include "types.h"

inline int lobe_kind(const Lobe* l) { return as_int(l->e.w); }

inline float lobe_alpha(const Lobe* l) { return l->a.w; }

inline float lobe_weight(const Lobe* l) { return l->d.w; }

/* The shared lanes of a lobe of kind `kind`; the kind's encode step fills the rest. */
inline Lobe lobe_record(int kind, float alpha, float weight)
{
    Lobe l;
    l.a = (float4)(0.0f, 0.0f, 0.0f, alpha);
    l.b = (float4)(0.0f);
    l.c = (float4)(0.0f);
    l.d = (float4)(0.0f, 0.0f, 0.0f, weight);
    l.e = (float4)(0.0f, 0.0f, 0.0f, as_float(kind));
    return l;
}

#endif
