/* Fill the presampled light tiles of this frame (lights/tiles.h): entry k holds a light drawn from the light array,
 * its record and its pick probability. */

__kernel void light_tiles_fill(const __global Light* lights, const __global int* slots, const __global float* light_pdf,
                               __global Light* tile_rec, __global int2* tile_info, FrameParams frame_params,
                               SamplerParams sampler)
{
    const int slot_count = sampler.slot_count, entries = sampler.tile_count * sampler.tile_size;
    const uint frame = frame_params.sample, seed = frame_params.seed;
    int k = get_global_id(0);
    if (k >= entries) return;
    uint rng = rng_seed((uint)k, frame, seed, 16u);
    float pdf;
    int light = light_array_pick(slots, slot_count, light_pdf, &rng, &pdf);
    light_tile_write(lights, light, pdf, k, tile_rec, tile_info);
}
