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
 * point on the light are stratified together; the first candidate shares a 6D group with the camera ray's place in
 * its pixel (qmc_camera_light_bits, qmc_camera_jitter_bits).
 *
 * The index is the sample's number within its half buffer of a still render (render/still.py), the key differs between
 * the halves: each half is its own randomised QMC estimate, and their difference stays an honest error estimate. */
#ifndef RESTIRCL_QMC_H
#define RESTIRCL_QMC_H

#include "sampling/rng.h"
#include "sampling/sobol_table.h"

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

/* Owen scramble by seed of a fraction given with its bits reversed (dimension 0: the index itself; dimension 1:
 * sobol_dim1_reversed; 2 .. 5: sobol_reversed), as a fraction (most significant bit first): one reversal. */
inline uint qmc_owen_reversed(uint r, uint seed) { return qmc_reverse_bits(qmc_lk_hash(r, seed)); }

/* Sobol dimensions 0 and 1 at shuffled index i, each Owen-scrambled, for a group with seed s */
inline uint2 qmc_dims01(uint i, uint s)
{
    return (uint2)(qmc_owen_reversed(i, pcg_hash(s ^ 0x2c1b3c6du)),
                   qmc_owen_reversed(sobol_dim1_reversed(i), pcg_hash(s ^ 0x297a2d39u)));
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

/* Sobol dimensions 2 .. 5 with their bits reversed, from nibble tables (sampling/sobol_table.h, generated): eight
 * lookups a point instead of a loop over 32 bits with a branch on each. */
inline uint sobol_reversed(uint i, __constant const uint* t)
{
    return t[i & 15u] ^ t[16u + ((i >> 4) & 15u)] ^ t[32u + ((i >> 8) & 15u)] ^ t[48u + ((i >> 12) & 15u)]
           ^ t[64u + ((i >> 16) & 15u)] ^ t[80u + ((i >> 20) & 15u)] ^ t[96u + ((i >> 24) & 15u)]
           ^ t[112u + (i >> 28)];
}

/* Point q->index of group d: Sobol dimensions 0 and 1 (y, z) and two more from the tables tx, tw (x, w), each
 * scrambled with its own key (kx, kw), all at one shuffled index. */
inline uint4 qmc_group_bits(const Qmc* q, uint d, __constant const uint* tx, uint kx, __constant const uint* tw,
                            uint kw)
{
    uint s = qmc_group_seed(q, d);
    uint i = qmc_shuffled_index(q, s);
    uint2 p = qmc_dims01(i, s);  /* the point on the light: the same (0,2)-sequence as a pair's */
    return (uint4)(qmc_owen_reversed(sobol_reversed(i, tx), pcg_hash(s ^ kx)), p.x, p.y,
                   qmc_owen_reversed(sobol_reversed(i, tw), pcg_hash(s ^ kw)));
}

/* Point q->index of the 4D group d: Sobol dimensions 0 .. 3 under one index shuffle, each Owen-scrambled on its
 * own. Unlike pairs, whose index shuffles differ, the four coordinates of one point stay one Sobol point: a light
 * candidate's pick (x) and point on the light (y, z) are stratified together, so the frames that pick one light
 * still spread their points over it (in 3D the first 2^k points put 2 in every elementary box of volume 2^(1-k)). */
inline uint4 qmc_quad_bits(const Qmc* q, uint d)
{
    return qmc_group_bits(q, d, SOBOL_DIM2, 0x6a09e667u, SOBOL_DIM3, 0xbb67ae85u);
}

/* Dimension groups of a RIS sample: light candidate k >= 1 uses the 4D group QMC_LIGHT(k) (x: the pick, y and z:
 * the point on the light), candidate 0 the camera vertex's 6D group QMC_CAMERA (below); BSDF candidate k the pair
 * QMC_BSDF(k); the BSDF MIS sample's direction (direct/bsdf_mis.h) the pair QMC_BSDF_MIS. */
#define QMC_LIGHT(k) (2u * (uint)(k))
#define QMC_CAMERA QMC_LIGHT(0) /* the first candidate's group, grown to six dimensions */
#define QMC_BSDF(k) (0x10000u + (uint)(k))
#define QMC_BSDF_MIS 0x20000u
/* A path's dimensions (path/path.cl): the BSDF direction of its k-th scatter the pair QMC_PATH_BSDF(k), the NEE at
 * its k-th bounce vertex the 4D group QMC_PATH_LIGHT(k) (x: the pick, y and z: the point on the light). */
#define QMC_PATH_BSDF(k) (0x30000u + (uint)(k))
#define QMC_PATH_LIGHT(k) (0x40000u + 2u * (uint)(k))

/* The camera vertex's group QMC_CAMERA: Sobol dimensions 0 .. 5 at one shuffled index, each Owen-scrambled on its
 * own, shared by the camera ray's place in its pixel (dimensions 2, 3) and the first light candidate at the surface
 * it meets (0, 1: the point on the light; 4: the pick; 5: the resampling choice of the whole stream). Drawn from
 * independent groups, the pixel position and the light sample are each stratified alone but not together: in a pixel
 * that an edge cuts, the samples that meet the surface are a random subset of the light's strata, and its error falls
 * as 1/N. As one Sobol point, the 4D projection (jitter, point on the light) is a (t, 4)-net with t <= 3 over any
 * aligned block of 2^k samples (Sobol's t for these four dimensions): the samples in each part of the pixel still
 * spread over the light. The point on the light keeps its (0, 2)-net, the pick and the point form a 3D net with
 * t <= 2, the jitter a 2D one with t <= 2 (checked for k = 4, 8, 10 by tests/render/test_qmc_camera.py). Candidates
 * k >= 1 keep their own groups. */
inline uint2 qmc_camera_jitter_bits(const Qmc* q) { return qmc_quad_bits(q, QMC_CAMERA).xw; }

/* The first light candidate's dimensions of QMC_CAMERA, laid out as qmc_quad_bits' (x: the pick, y and z: the
 * point on the light, w: the resampling choice). */
inline uint4 qmc_camera_light_bits(const Qmc* q)
{
    return qmc_group_bits(q, QMC_CAMERA, SOBOL_DIM4, 0x3c6ef372u, SOBOL_DIM5, 0xa54ff53au);
}

#endif
