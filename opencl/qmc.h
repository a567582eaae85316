/* A scrambled Sobol sequence per pixel for the light-sample dimensions of still RIS renders (setting `sampler`).
 *
 * Each dimension pair d of a pixel is its own copy of the first two Sobol dimensions, a (0,2)-sequence: any 2^k
 * consecutive points of an aligned block put one point in every elementary interval of area 2^-k. Every copy gets
 * an Owen scramble of both coordinates and a shuffle of the sample index, both drawn from a hash of (pixel, key,
 * d) (the nested uniform scramble of Burley 2020, "Practical Hash-based Owen Scrambling"). The scramble keeps the
 * stratification and makes every point uniform, so the estimator stays unbiased; the index shuffle maps the first
 * 2^k indices onto one aligned block of 2^k Sobol points (still a (0,k,2)-net) and decorrelates the pairs from
 * each other and the pixels from their neighbours, so no pair repeats another pair's pattern.
 *
 * The index is the sample's number within its half buffer of a still render (still.py), the key differs between
 * the halves: each half is its own randomised QMC estimate, and their difference stays an honest error estimate. */
#ifndef RESTIRCL_QMC_H
#define RESTIRCL_QMC_H

#include "rng.h"

typedef struct {
    int on;     /* 0: the callers draw from their random stream as without QMC */
    uint index; /* the sample's number in the sequence */
    uint seed;  /* hash of the pixel and the key */
} Qmc;

/* The QMC stream of pixel i for this frame (FrameParams.qmc, qmc_index, qmc_key). */
inline Qmc qmc_stream(int on, uint index, uint key, uint pixel)
{
    Qmc q = {on, index, pcg_hash(pixel ^ pcg_hash(key ^ 0x51ed270bu))};
    return q;
}

inline uint qmc_reverse_bits(uint x)
{
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x >> 8) & 0x00ff00ffu);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
    x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
    return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

/* Sobol dimension 1 with its bits reversed (the lowest bit of the result is the fraction's first). Its direction
 * numbers (primitive polynomial x + 1) form the Pascal matrix mod 2: index bit k adds the binomial coefficients
 * C(k, j) mod 2, which by Lucas' theorem are 1 exactly where j is a sub-mask of k. So result bit j is the parity
 * of the index bits k that are super-masks of j: a superset-sum transform, five shift-and-xor steps. */
inline uint sobol_dim1_reversed(uint i)
{
    i ^= (i & 0xaaaaaaaau) >> 1;
    i ^= (i & 0xccccccccu) >> 2;
    i ^= (i & 0xf0f0f0f0u) >> 4;
    i ^= (i & 0xff00ff00u) >> 8;
    i ^= (i & 0xffff0000u) >> 16;
    return i;
}

/* A hash in which every bit depends only on the bits below it (multiplications by even constants, an addition),
 * so that applied to the bit-reversed value it is an Owen scramble: each bit of the fraction is flipped by a
 * function of the bits above it. Constants: Burley 2020's Laine-Karras variant. */
inline uint qmc_lk_hash(uint x, uint seed)
{
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/* 32-bit fixed point -> float in [0, 1) (24 bits, as rng_next). */
inline float qmc_float(uint x) { return (float)(x >> 8) * (1.0f / 16777216.0f); }

/* Point q->index of dimension pair d, as two 32-bit fractions. The Owen scramble of a fraction f is
 * reverse(lk(reverse(f))); Sobol dimension 0 is reverse(i) itself, and dimension 1 is built reversed, so each
 * coordinate costs one reversal. The index shuffle is an Owen scramble of the index's bits: a permutation within
 * every aligned block of indices. */
inline uint2 qmc_pair_bits(const Qmc* q, uint d)
{
    uint s = pcg_hash(q->seed ^ pcg_hash(d * 0x9e3779b9u + 0x7f4a7c15u));
    uint i = qmc_reverse_bits(qmc_lk_hash(qmc_reverse_bits(q->index), s));
    return (uint2)(qmc_reverse_bits(qmc_lk_hash(i, pcg_hash(s ^ 0x2c1b3c6du))),
                   qmc_reverse_bits(qmc_lk_hash(sobol_dim1_reversed(i), pcg_hash(s ^ 0x297a2d39u))));
}

inline float2 qmc_pair(const Qmc* q, uint d)
{
    uint2 b = qmc_pair_bits(q, d);
    return (float2)(qmc_float(b.x), qmc_float(b.y));
}

/* Dimension pairs of a RIS sample: light candidate k uses QMC_LIGHT_PICK(k) (the pick, and for k = 0 the
 * resampling choice) and QMC_LIGHT_POINT(k) (the point on the light); BSDF candidate k QMC_BSDF(k); the BSDF MIS
 * sample's direction (bsdf_mis.h) QMC_BSDF_MIS. */
#define QMC_LIGHT_PICK(k) (2u * (uint)(k))
#define QMC_LIGHT_POINT(k) (2u * (uint)(k) + 1u)
#define QMC_BSDF(k) (0x10000u + (uint)(k))
#define QMC_BSDF_MIS 0x20000u

#endif
