/* Where in its pixel a camera ray starts. In a still render from the Sobol sampler with pixel jitter
 * (FrameParams.qmc & QMC_PIXEL_JITTER, render/still.py): dimensions 2 and 3 of the pixel's camera vertex group
 * (sampling/qmc.h QMC_CAMERA), whose other dimensions draw the first light candidate at the surface the ray meets, so
 * that the place in the pixel and the light sample are stratified together. Elsewhere the frame's offset
 * Camera.jitter.xy, the same for every pixel (a Halton point per frame, or 0). */
#ifndef RESTIRCL_CAMERA_JITTER_H
#define RESTIRCL_CAMERA_JITTER_H

#include "sampling/qmc.h"

/* The continuous pixel position of pixel (x, y) = i's camera ray in this frame. */
inline float2 camera_ray_position(const __global Camera* cam, const FrameParams* fp, int x, int y, int i)
{
    if (fp->qmc & QMC_PIXEL_JITTER) {
        Qmc q = qmc_stream(fp->qmc, fp->qmc_index, fp->qmc_key, (uint)i);
        uint2 j = qmc_camera_jitter_bits(&q);
        return (float2)((float)x + qmc_float(j.x), (float)y + qmc_float(j.y));
    }
    return (float2)((float)x + 0.5f + cam->jitter.x, (float)y + 0.5f + cam->jitter.y);
}

#endif
