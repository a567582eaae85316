/* Inline numeric helpers. PoCL 3.0 compiles isfinite() and fabs() to out-of-line calls; these bit tests are exact
 * and inline on every device (and, unlike x - x == 0, survive any floating-point contraction). */
#ifndef RESTIRCL_NUMERICS_H
#define RESTIRCL_NUMERICS_H

/* true for finite x (not NaN, not +-Inf) */
inline bool finite_f(float x) { return (as_uint(x) & 0x7f800000u) != 0x7f800000u; }

inline bool finite3_f(float3 c) { return finite_f(c.x) && finite_f(c.y) && finite_f(c.z); }

/* fmax, fmin and clamp of floats, inline (PoCL 3.0 calls its builtins out of line), with fmax/fmin's NaN rule: a NaN
 * operand gives the other operand. */
inline float fmax_f(float a, float b) { return (a >= b || b != b) ? a : b; }

inline float fmin_f(float a, float b) { return (a <= b || b != b) ? a : b; }

inline float clamp_f(float x, float lo, float hi) { return fmin_f(fmax_f(x, lo), hi); }

/* |x| */
inline float abs_f(float x) { return as_float(as_uint(x) & 0x7fffffffu); }

/* float3 dot, cross, length and normalize: PoCL 3.0 calls its builtins for these out of line (inlining dot saved
 * 4 % of a ReSTIR frame: 275 -> 264 ms, docs/measurements/benchmarks.md); these inline forms are the plain formulas.
 * norm3 of a zero or non-finite vector gives NaN, as normalize may: callers test lengths first. */
inline float dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

inline float3 cross3(float3 a, float3 b)
{
    return (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

inline float len3(float3 v) { return sqrt(dot3(v, v)); }

inline float3 norm3(float3 v) { return v * (1.0f / sqrt(dot3(v, v))); }

#endif
