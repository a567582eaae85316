/* The number with which a camera ray chooses at the first transparent surface it meets whether it stops there
 * (bvh/transparent.h trace_camera: it stops where the number is below the surface's coverage).
 *
 * In a still render that draws from the Sobol sequence: the pixel's own scrambled Sobol dimension (the first of
 * the pair QMC_COVERAGE), stratified over the samples of its half buffer, so that a pixel behind a half-transparent
 * pane sees pane and floor in even turns, and its index shuffled per pixel, so that it is not tied to the pixel
 * jitter. The jitter is one Halton point for all pixels; a number that is a fixed function of the frame (as the
 * frames' own sequence below) is then tied to the jitter's point, and where the coverage varies across the pixel
 * (a cut-out's rim, bilinear alpha between texels) the pixel's error stopped falling: its samples met the rim's
 * coverage and the number in the same pattern in every block of frames.
 *
 * Elsewhere (animation and viewport frames, the random sampler): the frame's point of the camera's golden-ratio
 * sequence (Camera.jitter.z) turned by a hash of the pixel. */
#ifndef RESTIRCL_CAMERA_COVERAGE_NUMBER_H
#define RESTIRCL_CAMERA_COVERAGE_NUMBER_H

#include "sampling/qmc.h"

#define QMC_COVERAGE 0x60000u  /* the dimension pair of the camera's first choice (below it: qmc.h's and lens.h's) */

inline float camera_coverage_number(const __global Camera* cam, const FrameParams* fp, uint pixel)
{
    Qmc q = qmc_stream(fp->qmc, fp->qmc_index, fp->qmc_key, pixel);
    if (q.on) return qmc_pair(&q, QMC_COVERAGE).x;
    float u0 = cam->jitter.z + (float)(pcg_hash(pixel ^ 0x6a09e667u) >> 8) * (1.0f / 16777216.0f);
    return u0 >= 1.0f ? u0 - 1.0f : u0;
}

#endif
