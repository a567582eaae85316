/* The weighted layers of a still (camera/layers.h, python/restircl/render/layers.py): the pixel's sample of a frame
 * is the sum over its layers of the layer's sample times its weight (GSample.layer.y; 0 where the pixel's layers
 * were done), colour and w alike, so that w's mean stays the film's coverage. */
__kernel void layer_add(const __global GSample* gbuf, const __global float4* sample, __global float4* layered,
                        __global int* continuing, FrameParams frame_params, int layer)
{
    int i = get_global_id(0);
    if (i == 0) continuing[(layer + 1) & 1] = 0;  /* the count of the next layer's primary pass (camera/layers.h) */
    if (i >= frame_params.pixels) return;
    float w = gbuf[i].layer.y;
    float4 v = w > 0.0f ? w * sample[i] : (float4)(0.0f);
    layered[i] = layer == 0 ? v : layered[i] + v;
}
