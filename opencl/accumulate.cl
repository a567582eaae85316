/* Running sum of a still render's samples, and of the samples of its half buffer 1 (python/restircl/still.py):
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
