/* Lookups in the GGX energy tables (python/restircl/upload/ggx_tables.py computes them; one float buffer, the offsets
 * below match its E_OFFSET, E_AVG_OFFSET, S_OFFSET). Grid point i of n stands for the parameter i / (n - 1);
 * between points the tables are interpolated linearly, and parameters outside [0, 1] are clamped. */
#ifndef RESTIRCL_BSDF_TABLES_H
#define RESTIRCL_BSDF_TABLES_H

#include "codes.h"

/* the grid cell of parameter x in [0, 1] on n points: *i and *i + 1, *t the weight of *i + 1 */
inline void table_cell(float x, int n, int* i, float* t)
{
    float p = clamp_f(x, 0.0f, 1.0f) * (float)(n - 1);
    int k = min((int)p, n - 2);
    *i = k;
    *t = p - (float)k;
}

inline float table_1d(const __global float* tab, int offset, float x, int n)
{
    int i;
    float t;
    table_cell(x, n, &i, &t);
    return tab[offset + i] * (1.0f - t) + tab[offset + i + 1] * t;
}

/* tab[offset + y * n + x] */
inline float table_2d(const __global float* tab, int offset, float x, float y, int n)
{
    int j;
    float t;
    table_cell(y, n, &j, &t);
    return table_1d(tab, offset + j * n, x, n) * (1.0f - t) + table_1d(tab, offset + (j + 1) * n, x, n) * t;
}

/* tab[offset + (z * n + y) * n + x] */
inline float table_3d(const __global float* tab, int offset, float x, float y, float z, int n)
{
    int k;
    float t;
    table_cell(z, n, &k, &t);
    return table_2d(tab, offset + k * n * n, x, y, n) * (1.0f - t) + table_2d(tab, offset + (k + 1) * n * n, x, y, n) * t;
}

/* E(roughness, mu): the directional albedo of GGX without Fresnel */
inline float ggx_albedo(const __global float* tab, float roughness, float mu)
{
    return table_2d(tab, GGX_E_OFFSET, roughness, mu, GGX_E_SIZE);
}

/* E_avg(roughness): E averaged over the cosine-weighted hemisphere */
inline float ggx_albedo_avg(const __global float* tab, float roughness)
{
    return table_1d(tab, GGX_E_AVG_OFFSET, roughness, GGX_E_SIZE);
}

/* s: where between f0 and 1 the directional albedo of a GGX dielectric specular of IOR eta lies, at view cosine
 * mu (its layering estimate is mix(f0, 1, s)) */
inline float ggx_fresnel_blend(const __global float* tab, float roughness, float mu, float eta)
{
    float z = sqrt(abs_f((eta - 1.0f) / (eta + 1.0f)));
    return table_3d(tab, GGX_S_OFFSET, roughness, mu, z, GGX_S_SIZE);
}

#endif
