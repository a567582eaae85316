/* Inline numeric helpers. PoCL 3.0 compiles isfinite() and fabs() to out-of-line calls; these bit tests are exact
 * and inline on every device (and, unlike x - x == 0, survive any floating-point contraction). */
#ifndef RESTIRCL_NUMERICS_H
#define RESTIRCL_NUMERICS_H

/* true for finite x (not NaN, not +-Inf) */
inline bool finite_f(float x) { return (as_uint(x) & 0x7f800000u) != 0x7f800000u; }

inline bool finite3_f(float3 c) { return finite_f(c.x) && finite_f(c.y) && finite_f(c.z); }

/* |x| */
inline float abs_f(float x) { return as_float(as_uint(x) & 0x7fffffffu); }

#endif
