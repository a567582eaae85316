/* Numerical guards: NaN/Inf never reaches an output; each replacement is counted (GUARD_*, types.h) for the host
 * to report. */
#ifndef RESTIRCL_GUARDS_H
#define RESTIRCL_GUARDS_H

inline void guard_count(volatile __global int* guards, int which) { atomic_inc(&guards[which]); }

/* Replace a NaN/Inf colour by 0 and count it. */
inline float3 guard_finite(float3 c, volatile __global int* guards, int which)
{
    if (finite3_f(c)) return c;
    guard_count(guards, which);
    return (float3)(0.0f);
}

#endif
