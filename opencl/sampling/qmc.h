/* A scrambled Sobol sequence per pixel for the light-sample dimensions of still RIS renders (setting `sampler`).
 *
 * Each dimension pair d of a pixel is its own copy of the first two Sobol dimensions, a (0,2)-sequence: any 2^k
 * consecutive points of an aligned block put one point in every elementary interval of area 2^-k. Every copy gets
 * an Owen scramble of both coordinates and a shuffle of the sample index, both drawn from a hash of (pixel, key,
 * d) (the nested uniform scramble of Burley 2020, "Practical Hash-based Owen Scrambling"). The scramble keeps the
 * stratification and makes every point uniform, so the estimator stays unbiased; the index shuffle maps the first
 * 2^k indices onto one aligned block of 2^k Sobol points (still a (0,k,2)-net) and decorrelates the pairs from
 * each other and the pixels from their neighbours, so no pair repeats another pair's pattern. A light candidate
 * takes a 4D group instead (qmc_quad_bits): four Sobol dimensions under one index shuffle, so that its pick and its
 * point on the light are stratified together.
 *
 * The index is the sample's number within its half buffer of a still render (render/still.py), the key differs between
 * the halves: each half is its own randomised QMC estimate, and their difference stays an honest error estimate. */
#ifndef RESTIRCL_QMC_H
#define RESTIRCL_QMC_H

#include "sampling/rng.h"

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

/* the seed of group (pair or quad) d of the pixel */
inline uint qmc_group_seed(const Qmc* q, uint d)
{
    return pcg_hash(q->seed ^ pcg_hash(d * 0x9e3779b9u + 0x7f4a7c15u));
}

/* the shuffled index of a group with seed s */
inline uint qmc_shuffled_index(const Qmc* q, uint s)
{
    return qmc_reverse_bits(qmc_lk_hash(qmc_reverse_bits(q->index), s));
}

/* Sobol dimensions 0 and 1 at shuffled index i, each Owen-scrambled, for a group with seed s */
inline uint2 qmc_dims01(uint i, uint s)
{
    return (uint2)(qmc_reverse_bits(qmc_lk_hash(i, pcg_hash(s ^ 0x2c1b3c6du))),
                   qmc_reverse_bits(qmc_lk_hash(sobol_dim1_reversed(i), pcg_hash(s ^ 0x297a2d39u))));
}

/* Point q->index of dimension pair d, as two 32-bit fractions. The Owen scramble of a fraction f is
 * reverse(lk(reverse(f))); Sobol dimension 0 is reverse(i) itself, and dimension 1 is built reversed, so each
 * coordinate costs one reversal. The index shuffle is an Owen scramble of the index's bits: a permutation within
 * every aligned block of indices. */
inline uint2 qmc_pair_bits(const Qmc* q, uint d)
{
    uint s = qmc_group_seed(q, d);
    return qmc_dims01(qmc_shuffled_index(q, s), s);
}

inline float2 qmc_pair(const Qmc* q, uint d)
{
    uint2 b = qmc_pair_bits(q, d);
    return (float2)(qmc_float(b.x), qmc_float(b.y));
}

/* Sobol dimensions 2 and 3 (primitive polynomials x^2 + x + 1 and x^3 + x + 1, Joe and Kuo's initial numbers 1, 3
 * and 1, 3, 1) as nibble tables: entry 16 n + v is the fraction (most significant bit first) that the value v of
 * index bits 4n .. 4n + 3 adds, the XOR of those bits' direction numbers. Eight lookups a point instead of a loop
 * over 32 bits with a branch on each. Checked against scipy's Sobol by tests/render/test_qmc.py. */
__constant uint SOBOL_DIM2[128] = {
    0x00000000u, 0x80000000u, 0xc0000000u, 0x40000000u, 0x60000000u, 0xe0000000u, 0xa0000000u, 0x20000000u,
    0x90000000u, 0x10000000u, 0x50000000u, 0xd0000000u, 0xf0000000u, 0x70000000u, 0x30000000u, 0xb0000000u,
    0x00000000u, 0xe8000000u, 0x5c000000u, 0xb4000000u, 0x8e000000u, 0x66000000u, 0xd2000000u, 0x3a000000u,
    0xc5000000u, 0x2d000000u, 0x99000000u, 0x71000000u, 0x4b000000u, 0xa3000000u, 0x17000000u, 0xff000000u,
    0x00000000u, 0x68800000u, 0x9cc00000u, 0xf4400000u, 0xee600000u, 0x86e00000u, 0x72a00000u, 0x1a200000u,
    0x55900000u, 0x3d100000u, 0xc9500000u, 0xa1d00000u, 0xbbf00000u, 0xd3700000u, 0x27300000u, 0x4fb00000u,
    0x00000000u, 0x80680000u, 0xc09c0000u, 0x40f40000u, 0x60ee0000u, 0xe0860000u, 0xa0720000u, 0x201a0000u,
    0x90550000u, 0x103d0000u, 0x50c90000u, 0xd0a10000u, 0xf0bb0000u, 0x70d30000u, 0x30270000u, 0xb04f0000u,
    0x00000000u, 0xe8808000u, 0x5cc0c000u, 0xb4404000u, 0x8e606000u, 0x66e0e000u, 0xd2a0a000u, 0x3a202000u,
    0xc5909000u, 0x2d101000u, 0x99505000u, 0x71d0d000u, 0x4bf0f000u, 0xa3707000u, 0x17303000u, 0xffb0b000u,
    0x00000000u, 0x6868e800u, 0x9c9c5c00u, 0xf4f4b400u, 0xeeee8e00u, 0x86866600u, 0x7272d200u, 0x1a1a3a00u,
    0x5555c500u, 0x3d3d2d00u, 0xc9c99900u, 0xa1a17100u, 0xbbbb4b00u, 0xd3d3a300u, 0x27271700u, 0x4f4fff00u,
    0x00000000u, 0x8000e880u, 0xc0005cc0u, 0x4000b440u, 0x60008e60u, 0xe00066e0u, 0xa000d2a0u, 0x20003a20u,
    0x9000c590u, 0x10002d10u, 0x50009950u, 0xd00071d0u, 0xf0004bf0u, 0x7000a370u, 0x30001730u, 0xb000ffb0u,
    0x00000000u, 0xe8006868u, 0x5c009c9cu, 0xb400f4f4u, 0x8e00eeeeu, 0x66008686u, 0xd2007272u, 0x3a001a1au,
    0xc5005555u, 0x2d003d3du, 0x9900c9c9u, 0x7100a1a1u, 0x4b00bbbbu, 0xa300d3d3u, 0x17002727u, 0xff004f4fu
};
__constant uint SOBOL_DIM3[128] = {
    0x00000000u, 0x80000000u, 0xc0000000u, 0x40000000u, 0x20000000u, 0xa0000000u, 0xe0000000u, 0x60000000u,
    0x50000000u, 0xd0000000u, 0x90000000u, 0x10000000u, 0x70000000u, 0xf0000000u, 0xb0000000u, 0x30000000u,
    0x00000000u, 0xf8000000u, 0x74000000u, 0x8c000000u, 0xa2000000u, 0x5a000000u, 0xd6000000u, 0x2e000000u,
    0x93000000u, 0x6b000000u, 0xe7000000u, 0x1f000000u, 0x31000000u, 0xc9000000u, 0x45000000u, 0xbd000000u,
    0x00000000u, 0xd8800000u, 0x25400000u, 0xfdc00000u, 0x59e00000u, 0x81600000u, 0x7ca00000u, 0xa4200000u,
    0xe6d00000u, 0x3e500000u, 0xc3900000u, 0x1b100000u, 0xbf300000u, 0x67b00000u, 0x9a700000u, 0x42f00000u,
    0x00000000u, 0x78080000u, 0xb40c0000u, 0xcc040000u, 0x82020000u, 0xfa0a0000u, 0x360e0000u, 0x4e060000u,
    0xc3050000u, 0xbb0d0000u, 0x77090000u, 0x0f010000u, 0x41070000u, 0x390f0000u, 0xf50b0000u, 0x8d030000u,
    0x00000000u, 0x208f8000u, 0x51474000u, 0x71c8c000u, 0xfbea2000u, 0xdb65a000u, 0xaaad6000u, 0x8a22e000u,
    0x75d93000u, 0x5556b000u, 0x249e7000u, 0x0411f000u, 0x8e331000u, 0xaebc9000u, 0xdf745000u, 0xfffbd000u,
    0x00000000u, 0xa0858800u, 0x914e5400u, 0x31cbdc00u, 0xdbe79e00u, 0x7b621600u, 0x4aa9ca00u, 0xea2c4200u,
    0x25db6d00u, 0x855ee500u, 0xb4953900u, 0x1410b100u, 0xfe3cf300u, 0x5eb97b00u, 0x6f72a700u, 0xcff72f00u,
    0x00000000u, 0x58800080u, 0xe54000c0u, 0xbdc00040u, 0x79e00020u, 0x216000a0u, 0x9ca000e0u, 0xc4200060u,
    0xb6d00050u, 0xee5000d0u, 0x53900090u, 0x0b100010u, 0xcf300070u, 0x97b000f0u, 0x2a7000b0u, 0x72f00030u,
    0x00000000u, 0x800800f8u, 0xc00c0074u, 0x4004008cu, 0x200200a2u, 0xa00a005au, 0xe00e00d6u, 0x6006002eu,
    0x50050093u, 0xd00d006bu, 0x900900e7u, 0x1001001fu, 0x70070031u, 0xf00f00c9u, 0xb00b0045u, 0x300300bdu
};

inline uint sobol_matrix(uint i, __constant const uint* t)
{
    return t[i & 15u] ^ t[16u + ((i >> 4) & 15u)] ^ t[32u + ((i >> 8) & 15u)] ^ t[48u + ((i >> 12) & 15u)]
           ^ t[64u + ((i >> 16) & 15u)] ^ t[80u + ((i >> 20) & 15u)] ^ t[96u + ((i >> 24) & 15u)]
           ^ t[112u + (i >> 28)];
}

/* Owen scramble of a fraction f (most significant bit first) by seed */
inline uint qmc_owen(uint f, uint seed) { return qmc_reverse_bits(qmc_lk_hash(qmc_reverse_bits(f), seed)); }

/* Point q->index of the 4D group d: Sobol dimensions 0 .. 3 under one index shuffle, each Owen-scrambled on its
 * own. Unlike pairs, whose index shuffles differ, the four coordinates of one point stay one Sobol point: a light
 * candidate's pick (x) and point on the light (y, z) are stratified together, so the frames that pick one light
 * still spread their points over it (in 3D the first 2^k points put 2 in every elementary box of volume 2^(1-k)). */
inline uint4 qmc_quad_bits(const Qmc* q, uint d)
{
    uint s = qmc_group_seed(q, d);
    uint i = qmc_shuffled_index(q, s);
    uint2 p = qmc_dims01(i, s);  /* the point on the light: the same (0,2)-sequence as a pair's */
    return (uint4)(qmc_owen(sobol_matrix(i, SOBOL_DIM2), pcg_hash(s ^ 0x6a09e667u)), p.x, p.y,
                   qmc_owen(sobol_matrix(i, SOBOL_DIM3), pcg_hash(s ^ 0xbb67ae85u)));
}

/* Dimension groups of a RIS sample: light candidate k uses the 4D group QMC_LIGHT(k) (x: the pick, y and z: the
 * point on the light, w: for k = 0 the resampling choice); BSDF candidate k the pair QMC_BSDF(k); the BSDF MIS
 * sample's direction (direct/bsdf_mis.h) the pair QMC_BSDF_MIS. */
#define QMC_LIGHT(k) (2u * (uint)(k))
#define QMC_BSDF(k) (0x10000u + (uint)(k))
#define QMC_BSDF_MIS 0x20000u
/* A path's dimensions (path/path.cl): the BSDF direction of its k-th scatter the pair QMC_PATH_BSDF(k), the NEE at
 * its k-th bounce vertex the 4D group QMC_PATH_LIGHT(k) (x: the pick, y and z: the point on the light). */
#define QMC_PATH_BSDF(k) (0x30000u + (uint)(k))
#define QMC_PATH_LIGHT(k) (0x40000u + 2u * (uint)(k))

#endif
