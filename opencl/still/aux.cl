/* The still render's running sums of the denoiser's guide images (python/restircl/render/denoise.py): the surface's
 * albedo and shading normal, summed over the jittered samples as the colour is, so that at edges they mix the two
 * sides in the colour's proportions; and the emission the camera sees, which the denoiser leaves out (it is no
 * noise, and a small bright lamp smeared over its dark neighbours is a large error). The albedo of a glossy surface
 * adds its lobes' reflectance at normal incidence (F0 times weight): a metal's diffuse albedo is 0, and a guide of 0
 * would tell the denoiser the surface is black. */
__kernel void accumulate_aux(const __global GSample* gbuf, const __global GlossySample* glossy,
                             __global float4* albedo_sum, __global float4* normal_sum, __global float4* emission_sum,
                             FrameParams frame_params)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    GSample g = gbuf[i];
    if (finite3_f(g.emission.xyz)) emission_sum[i] += (float4)(g.emission.xyz, 0.0f);
    if (as_int(g.normal.w) < 0) return;  /* a miss: black albedo, zero normal */
    float4 a = (float4)(g.albedo.xyz, 0.0f);
#ifdef HAS_GLOSSY
    GlossySample gx = glossy[i];
    int lobes = as_int(gx.wo.w);
    if (lobes > 0) a.xyz += lobe_albedo(&gx.lobe0);
    if (lobes > 1) a.xyz += lobe_albedo(&gx.lobe1);
#endif
    albedo_sum[i] += (float4)(clamp_f(a.x, 0.0f, 1.0f), clamp_f(a.y, 0.0f, 1.0f), clamp_f(a.z, 0.0f, 1.0f), 0.0f);
    normal_sum[i] += (float4)(g.normal.xyz, 0.0f);
}
