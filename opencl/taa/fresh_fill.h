/* The colour TAA shows for a pixel without history on a moving camera (disoccluded, or new at the image's border):
 * the mean of the samples of its 3x3 neighbourhood that see the same surface as it (view depth, normal and material,
 * the tests of ReSTIR's spatial reuse), the pixel's own sample among them, in place of its one sample. Such a pixel
 * has nothing else: its one sample's noise is many times a history pixel's, and a one-frame 3x3 blur within one
 * surface is of the kind the bilinear history fetch and the clip box apply to every moving pixel. The history
 * starts from the filled value with n = 1, so the next frames weigh it as a single sample (1/n) and clip it to their
 * neighbourhood like any history. Misses and lights the camera sees are not filled (their one sample is exact up
 * to the jitter). */
#ifndef RESTIRCL_TAA_FRESH_FILL_H
#define RESTIRCL_TAA_FRESH_FILL_H

/* key: the material key of pixel (x, y)'s surface (taa.cl has loaded it); a neighbour's material is read only
 * where its depth and normal already pass */
inline float3 taa_fresh_fill(const __global float4* sample, const __global GSample* gbuf,
                             const __global GlossySample* glossy, int x, int y, int width, int height,
                             float depth_tol, float normal_cos, const MaterialKey* key, float3 s)
{
    int i = y * width + x;
    GSample c = gbuf[i];
    if (as_int(c.normal.w) < 0) return s;
    float3 acc = s;
    float cnt = 1.0f;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            int j = ny * width + nx;
            GSample g = gbuf[j];
            if (as_int(g.normal.w) < 0) continue;
            if (!(abs_f(g.pos.w - c.pos.w) <= depth_tol * abs_f(c.pos.w))) continue;
            if (dot3(g.normal.xyz, c.normal.xyz) < normal_cos) continue;
            SurfaceMaterial m = surface_material_load(gbuf, glossy, j, 1);
            MaterialKey kn = material_key(&m);
            if (!material_keys_similar(key, &kn)) continue;
            float3 v = sample[j].xyz;
            if (!finite3_f(v)) continue;
            acc += v;
            cnt += 1.0f;
        }
    return acc / cnt;
}

#endif
