/* ReSTIR pass 6: one shadow ray to the pixel's final sample (restir_shade.h). Runs where no spatial pass does:
 * the last spatial pass shades as it goes. */

__kernel void restir_shade(const __global GSample* gbuf, const __global GlossySample* glossy, const __global BVHNode* nodes, const __global Tri* tris,
                           const __global Light* lights, const __global Reservoir* res,
                           volatile __global int* guards, __global float4* out, FrameParams frame_params,
                           ShadeParams params)
{
    const int pixel_count = frame_params.pixels;
    int i = get_global_id(0);
    if (i >= pixel_count) return;
    Surface s = surface_load(gbuf, glossy, i);
    Reservoir r = res[i];
    out[i] = restir_shade_pixel(gbuf, &s, &r, i, nodes, tris, lights, params.visible_known, guards);
}
