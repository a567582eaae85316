/* Random numbers: a PCG hash for seeding and a PCG-style LCG stream per work-item. */
#ifndef RESTIRCL_RNG_H
#define RESTIRCL_RNG_H

inline uint pcg_hash(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* A stream for (pixel, frame, seed, pass): distinct passes of one frame draw independent numbers. */
inline uint rng_seed(uint pixel, uint frame, uint seed, uint pass)
{
    return pcg_hash(pixel ^ pcg_hash(frame ^ pcg_hash(seed ^ pcg_hash(pass))));
}

/* Uniform 32-bit integer. */
inline uint rng_next_uint(uint* state)
{
    *state = *state * 747796405u + 2891336453u;
    uint word = ((*state >> ((*state >> 28u) + 4u)) ^ *state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* Uniform integer in [0, n): multiply-high, off from uniform by at most n / 2^32 relative. */
inline uint rng_below(uint* state, uint n)
{
    return (uint)(((ulong)rng_next_uint(state) * (ulong)n) >> 32);
}

/* Uniform float in [0, 1). */
inline float rng_next(uint* state)
{
    return (float)(rng_next_uint(state) >> 8) * (1.0f / 16777216.0f);
}

#endif
