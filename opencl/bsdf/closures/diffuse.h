/* The Diffuse BSDF: the Lambert part alone, of colour Color (its Roughness, Oren-Nayar, is not modelled). */
#ifndef RESTIRCL_BSDF_CLOSURES_DIFFUSE_H
#define RESTIRCL_BSDF_CLOSURES_DIFFUSE_H

#include "bsdf/closure.h"

/* The closure's diffuse albedo (returned) at weight w > 0 and clamped colour base; no lobe (*count = 0). */
inline float3 diffuse_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                              Lobe* lobes, int* count)
{
    (void)c;
    (void)mu;
    (void)tab;
    (void)lobes;
    *count = 0;
    return base * w;
}

#endif
