/* A still render's running count of the camera rays that met a holdout (x) and of those that met nothing (y), per
 * pixel (python/restircl/render/still.py, every still): their means over the samples are the shares of the pixel
 * the holdout and the world cover, so that the film's alpha at a holdout's edge, and a transparent film's alpha at
 * an object's edge against the world, is the pixel's covered share (1 - x, or 1 - x - y on a transparent film)
 * rather than what the last sample saw. The samples' colour is already 0 where they met the holdout
 * (camera/primary.cl); without HAS_HOLDOUT no miss names a holdout, and x stays 0. */
__kernel void accumulate_holdout(const __global GSample* gbuf, __global float2* shares, FrameParams frame_params)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    GSample g = gbuf[i];
    if (as_int(g.normal.w) != -1) return;  /* a surface, or a light seen (lights/camera_visible.h) */
    bool hole = as_int(g.albedo.w) >= 0;  /* a miss that names the holdout it met */
    shares[i] += hole ? (float2)(1.0f, 0.0f) : (float2)(0.0f, 1.0f);
}
