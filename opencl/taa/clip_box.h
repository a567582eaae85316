/* TAA's clipping box: the YCoCg mean and standard deviation of the current samples around a pixel, which the
 * reprojected history is clipped to (mean +- gamma * sigma). By default every neighbour counts. With the setting
 * taa_clip_surface only the neighbours that show the pixel's own surface do (the reuse's tests: both misses, or
 * both hits within the view-depth tolerance and the normal angle), the pixel itself always: at a silhouette or a
 * crease a 3x3 box otherwise spans both surfaces, and a history blurred across the edge passes it. That lowers TAA's
 * own error without noise by 7-10 % on the orbits, but the smaller sample of a noisy frame makes the box narrower
 * and noisier there, and both estimators' error through TAA rises (docs/measurements/temporal-stability.md, "Where
 * TAA's own error sits"): off by default. */
#ifndef RESTIRCL_TAA_CLIP_BOX_H
#define RESTIRCL_TAA_CLIP_BOX_H

/* Half-width of the neighbourhood the clipping box is built from: 1 (3x3). A compile-time knob for the measurements
 * of docs/measurements/temporal-stability.md ("The moving camera's level"). */
#ifndef TAA_CLIP_RADIUS
#define TAA_CLIP_RADIUS 1
#endif

inline float3 rgb_to_ycocg(float3 c)
{
    return (float3)(0.25f * c.x + 0.5f * c.y + 0.25f * c.z, 0.5f * c.x - 0.5f * c.z, -0.25f * c.x + 0.5f * c.y - 0.25f * c.z);
}

inline float3 ycocg_to_rgb(float3 c)
{
    return (float3)(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

/* Does neighbour g show the surface of pixel c (both misses, or hits alike in view depth and normal)? */
inline bool taa_clip_same_surface(const GSample* c, const GSample* g, float depth_tol, float normal_cos)
{
    int pc = as_int(c->normal.w), pn = as_int(g->normal.w);
    if ((pc == -1) != (pn == -1)) return false;
    if (pc == -1) return true;
    return abs_f(g->pos.w - c->pos.w) <= depth_tol * abs_f(c->pos.w)
        && dot3(g->normal.xyz, c->normal.xyz) >= normal_cos;
}

/* Mean and standard deviation (YCoCg) of the finite samples around pixel (x, y) (clamped at the image's edges);
 * `surface`: of those on the pixel's surface only. */
inline void taa_clip_box(const __global float4* sample, const __global GSample* gbuf, int x, int y, int width,
                         int height, int surface, float depth_tol, float normal_cos, float3* mean, float3* sigma)
{
    float3 m1 = (float3)(0.0f), m2 = (float3)(0.0f);
    float cnt = 0.0f;
    GSample c;
    if (surface) c = gbuf[y * width + x];
    for (int dy = -TAA_CLIP_RADIUS; dy <= TAA_CLIP_RADIUS; ++dy)
        for (int dx = -TAA_CLIP_RADIUS; dx <= TAA_CLIP_RADIUS; ++dx) {
            int nx = clamp(x + dx, 0, width - 1), ny = clamp(y + dy, 0, height - 1);
            if (surface && (dx != 0 || dy != 0)) {
                GSample g = gbuf[ny * width + nx];
                if (!taa_clip_same_surface(&c, &g, depth_tol, normal_cos)) continue;
            }
            float3 v = sample[ny * width + nx].xyz;
            if (!finite3_f(v)) continue;
            v = rgb_to_ycocg(v);
            m1 += v;
            m2 += v * v;
            cnt += 1.0f;
        }
    *mean = m1 / cnt;
    *sigma = sqrt(fmax(m2 / cnt - *mean * *mean, (float3)(0.0f)));
}

#endif
