/* sin, cos and atan2 for the spherical light maps, as short polynomials after range reduction. PoCL calls its
 * correctly rounded builtins out of line at 200-400 ns each on these CPUs, against ~20 ns for a whole area sample
 * (measured: a spherical-rectangle sample with three builtins took 1.3 us); these take a few dozen flops and stay
 * within a few float32 ulps, relative for small arguments (where the maps need it), on every device. */
#ifndef RESTIRCL_LIGHTS_TRIG_H
#define RESTIRCL_LIGHTS_TRIG_H

#include "numerics.h"

/* sin and cos of x for |x| <= ~8 (the maps' angles are within [-2 pi, 2 pi]): x = n pi/2 + r, |r| <= pi/4, with pi/2
 * split in two so r keeps its precision; Taylor polynomials of degree 9 and 10 (truncation below 2e-9). */
inline float2 sincos_f(float x)
{
    float t = x * 0.636619772367581f;
    float n = (float)(int)(t + (t >= 0.0f ? 0.5f : -0.5f));  /* round to nearest: rint is a call on PoCL */
    float r = (x - n * 1.5707963705062866f) + n * 4.37113883e-8f;
    float r2 = r * r;
    float s = r * (1.0f + r2 * (-1.0f / 6.0f + r2 * (1.0f / 120.0f + r2 * (-1.0f / 5040.0f + r2 * (1.0f / 362880.0f)))));
    float c = 1.0f + r2 * (-0.5f + r2 * (1.0f / 24.0f + r2 * (-1.0f / 720.0f + r2 * (1.0f / 40320.0f +
                                                                                   r2 * (-1.0f / 3628800.0f)))));
    int q = ((int)n) & 3;
    float2 out = q == 0 ? (float2)(s, c) : q == 1 ? (float2)(c, -s) : q == 2 ? (float2)(-s, -c) : (float2)(-c, s);
    return out;  /* (sin x, cos x) */
}

/* atan of t in [0, 1]: above tan(pi/8) by atan(t) = pi/4 + atan((t - 1) / (t + 1)), then the Taylor series to
 * degree 17 on |t| <= tan(pi/8) (truncation below 3e-9). */
inline float atan01_f(float t)
{
    bool big = t > 0.41421356f;
    float z = big ? (t - 1.0f) / (t + 1.0f) : t;
    float z2 = z * z;
    float p = 1.0f / 17.0f;
    p = p * z2 - 1.0f / 15.0f;
    p = p * z2 + 1.0f / 13.0f;
    p = p * z2 - 1.0f / 11.0f;
    p = p * z2 + 1.0f / 9.0f;
    p = p * z2 - 1.0f / 7.0f;
    p = p * z2 + 1.0f / 5.0f;
    p = p * z2 - 1.0f / 3.0f;
    p = p * z2 + 1.0f;
    return (big ? 0.785398163397448f : 0.0f) + z * p;
}

/* atan2(y, x) in (-pi, pi]. */
inline float atan2_f(float y, float x)
{
    float ax = abs_f(x), ay = abs_f(y);
    float mx = fmax_f(ax, ay), mn = fmin_f(ax, ay);
    float a = mx > 0.0f ? atan01_f(mn / mx) : 0.0f;
    if (ay > ax) a = 1.57079632679490f - a;
    if (x < 0.0f) a = 3.14159265358979f - a;
    return y < 0.0f ? -a : a;
}

#endif
