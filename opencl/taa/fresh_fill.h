/* The colour TAA shows for a pixel without history on a moving camera (disoccluded, or new at the image's border):
 * the mean of the samples of its 3x3 neighbourhood that see the same surface as it (view depth, normal and material,
 * the tests of ReSTIR's spatial reuse), the pixel's own sample among them, in place of its one sample. Such a pixel
 * has nothing else: its one sample's noise is many times a history pixel's, and a one-frame 3x3 blur within one
 * surface is of the kind the bilinear history fetch and the clip box apply to every moving pixel. The history
 * starts from the filled value with n = 1, so the next frames weigh it as a single sample (1/n) and clip it to their
 * neighbourhood like any history. Misses and lights the camera sees are not filled (their one sample is exact up
 * to the jitter).
 * The mean is of raw samples, so one firefly among them would reach every fresh pixel around it at a ninth of its
 * value, where TAA shows it in one pixel at the blend weight. So with three samples or more the brightest one
 * (luminance) counts for no more than all the others together: where it is brighter than their sum, its colour is
 * scaled down to that sum, and the fill shows at most twice the others' mean. A neighbourhood without such a sample
 * keeps its plain mean; a sparse bright light seen by one sample of nine is darkened with the firefly, as no 3x3
 * can tell the two apart (docs/measurements/temporal-stability.md, "The fill's mean and outliers"). A non-finite
 * sample (the pixel's own is zeroed where it is shown) is left out of the mean, not counted as 0. */
#ifndef RESTIRCL_TAA_FRESH_FILL_H
#define RESTIRCL_TAA_FRESH_FILL_H

/* 1: the brightest sample bounded as above; 0: the plain mean (a probe knob for the measurements) */
#ifndef TAA_FRESH_FILL_ROBUST
#define TAA_FRESH_FILL_ROBUST 1
#endif

/* The mean of the n samples v (luminances l), the brightest bounded by the others' summed luminance. */
inline float3 fill_mean(const float3* v, const float* l, int n)
{
    float3 acc = v[0];
    int top = 0;
    for (int k = 1; k < n; ++k) {
        acc += v[k];
        if (l[k] > l[top]) top = k;
    }
    float rest = 0.0f;
    float3 others = (float3)(0.0f);
    for (int k = 0; k < n; ++k)
        if (k != top) { rest += l[k]; others += v[k]; }
    if (!TAA_FRESH_FILL_ROBUST || n < 3 || !(l[top] > rest)) return acc / (float)n;
    return (others + v[top] * (rest / l[top])) / (float)n;
}

/* key: the material key of pixel (x, y)'s surface (taa.cl has loaded it); a neighbour's material is read only
 * where its depth and normal already pass; s: what the pixel shows where it is not filled (a miss, or no finite
 * sample to fill from) */
inline float3 taa_fresh_fill(const __global float4* sample, const __global GSample* gbuf,
                             const __global GlossySample* glossy, int x, int y, int width, int height,
                             float depth_tol, float normal_cos, const MaterialKey* key, float3 s)
{
    int i = y * width + x;
    GSample c = gbuf[i];
    if (as_int(c.normal.w) < 0) return s;
    float3 v[9];
    float l[9];
    int n = 0;
    for (int t = -1; t < 9; ++t) {  /* the pixel's own sample first, then its neighbours */
        int dx = t < 0 ? 0 : t % 3 - 1, dy = t < 0 ? 0 : t / 3 - 1;
        int nx = x + dx, ny = y + dy;
        if ((t >= 0 && dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        int j = ny * width + nx;
        if (t >= 0) {
            GSample g = gbuf[j];
            if (as_int(g.normal.w) < 0) continue;
            if (!(abs_f(g.pos.w - c.pos.w) <= depth_tol * abs_f(c.pos.w))) continue;
            if (dot3(g.normal.xyz, c.normal.xyz) < normal_cos) continue;
            SurfaceMaterial m = surface_material_load(gbuf, glossy, j, 1);
            MaterialKey kn = material_key(&m);
            if (!material_keys_similar(key, &kn)) continue;
        }
        float3 u = sample[j].xyz;
        if (!finite3_f(u)) continue;
        v[n] = u;
        l[n] = fmax_f(luminance(u), 0.0f);
        ++n;
    }
    return n > 0 ? fill_mean(v, l, n) : s;
}

#endif
