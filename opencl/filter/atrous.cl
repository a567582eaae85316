/* The real-time filter (Settings.realtime_filter): an edge-aware a-trous wavelet filter in the style of SVGF
 * (Schied et al., HPG 2017) on the TAA output of the animation path. Each iteration k takes the 5x5 B3-spline
 * taps 2^k pixels apart, each weighted by how alike it is to the centre: view depth (relative), shading normal
 * (cos^128) and luminance relative to the centre's estimated standard deviation. That variance is estimated per
 * pixel (filter_variance) from the spatial variance of this frame's 1-sample estimates in the 3x3 neighbourhood,
 * divided by the pixel's TAA history length n: the TAA output averages about n such samples. It is filtered along
 * with the colour (weights squared), so later, wider iterations trust the luminance more. The TAA history itself is
 * never filtered (no feedback): the filter only changes what is shown. Misses pass through unfiltered. */

inline float atrous_lum(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

__kernel void filter_variance(const __global float4* sample, const __global float4* taa, __global float4* out,
                              FrameParams frame_params)
{
    const int width = frame_params.width, height = frame_params.height;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    float m1 = 0.0f, m2 = 0.0f, cnt = 0.0f;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int nx = clamp(x + dx, 0, width - 1), ny = clamp(y + dy, 0, height - 1);
            float l = atrous_lum(sample[ny * width + nx].xyz);
            if (!finite_f(l)) continue;
            m1 += l;
            m2 += l * l;
            cnt += 1.0f;
        }
    int i = y * width + x;
    float4 c = taa[i];
    float var = cnt > 1.0f ? fmax_f(m2 / cnt - (m1 / cnt) * (m1 / cnt), 0.0f) : 0.0f;
    float n = fmax_f(c.w, 1.0f);
    out[i] = (float4)(c.xyz, var / n);
}

__kernel void atrous(const __global float4* input, __global float4* out, const __global GSample* gbuf,
                     FrameParams frame_params, AtrousParams params)
{
    const AtrousParams p = params;
    const int width = frame_params.width, height = frame_params.height;
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    int i = y * width + x;
    float4 c = input[i];
    GSample g = gbuf[i];
    if (as_int(g.normal.w) < 0 || !finite3_f(c.xyz)) { out[i] = c; return; }
    const float h[3] = {3.0f / 8.0f, 1.0f / 4.0f, 1.0f / 16.0f};
    float lc = atrous_lum(c.xyz);
    float sigma_l = p.sigma_l * sqrt(fmax_f(c.w, 0.0f)) + 1e-4f;
    float3 sum = (float3)(0.0f);
    float wsum = 0.0f, vsum = 0.0f;
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            int nx = x + dx * p.step, ny = y + dy * p.step;
            if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            int j = ny * width + nx;
            GSample q = gbuf[j];
            float4 v = input[j];
            if (as_int(q.normal.w) < 0 || !finite3_f(v.xyz)) continue;
            float wz = exp(-abs_f(q.pos.w - g.pos.w) / (p.sigma_z * fmax_f(g.pos.w, 1e-6f) * (float)p.step));
            float cn = fmax_f(dot3(g.normal.xyz, q.normal.xyz), 0.0f);
            float cn2 = cn * cn, cn4 = cn2 * cn2, cn8 = cn4 * cn4, cn16 = cn8 * cn8, cn32 = cn16 * cn16;
            float wn = cn32 * cn32 * cn32 * cn32;  /* cos^128 */
            float wl = exp(-abs_f(atrous_lum(v.xyz) - lc) / sigma_l);
            float w = h[abs(dx)] * h[abs(dy)] * wz * wn * wl;
            sum += w * v.xyz;
            wsum += w;
            vsum += w * w * fmax_f(v.w, 0.0f);
        }
    /* the centre tap always counts (weight h0^2 > 0), so wsum > 0 */
    out[i] = (float4)(sum / wsum, vsum / (wsum * wsum));
}
