/* Running sum of a still render's samples, and of the samples of its half buffer 1 (python/restircl/render/still.py):
 * the two halves are independent estimates of the pixel, whose difference estimates the error. */

__kernel void accumulate(const __global float4* sample, __global float4* sum, __global float4* sum_half,
                         FrameParams frame_params, int in_half)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    float4 v = sample[i];
    sum[i] += v;
    if (in_half) sum_half[i] += v;
}

/* The still render's running sums of the light passes' planes (film/light_passes.h): light and colours summed
 * alike, so that the host's division of a light by its colour is a ratio of sums, as Cycles divides. The count of
 * planes is an argument, not LPASS_PLANES: this kernel is in the film program, which no feature flag changes. */
__kernel void accumulate_light_passes(const __global float4* light_passes, __global float4* sums,
                                      FrameParams frame_params, int planes)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels * planes) return;  /* planes: LPASS_PLANES of the main program (film/light_groups.h) */
    sums[i] += light_passes[i];
}
