/* The Refraction BSDF: GGX refraction of Color through an interface of the IOR, no reflection, no Fresnel (Cycles:
 * what total internal reflection keeps is lost); the lobe of bsdf/closures/glass.h. */
#ifndef RESTIRCL_BSDF_CLOSURES_REFRACTION_H
#define RESTIRCL_BSDF_CLOSURES_REFRACTION_H

#include "bsdf/closures/glass.h"

/* Refraction BSDF: its lobe (lobes[0], *count = 1), no diffuse part */
inline float3 refraction_resolve(const ClosureInputs* c, float w, float3 base, float mu, const __global float* tab,
                                 Lobe* lobes, int* count)
{
    lobes[0] = dielectric_closure_lobe(c, mu, (float3)(0.0f), base * w, (float3)(0.0f), true, base, tab);
    *count = 1;
    return (float3)(0.0f);
}

#endif
