/* TAA's noise-aware blend weight (Settings.taa_noise_blend). On a moving frame the weight a of the new sample in
 * o = a s + (1 - a) h is the one that minimises o's expected squared error (1 - a)^2 e_h + a^2 v_s, that is
 * a = e_h / (e_h + v_s), where, in luminance (YCoCg's Y, as the clip box's):
 * - v_s is the variance of the pixel's sample, from the differences of successive samples along its reprojected
 *   path: E[(y - y')^2] = v_s (1 + sum w^2) for a sample y and last frame's y' fetched with the bilinear weights w
 *   (which average the noise of their taps), both of the same variance. The squared difference, so scaled, is
 *   averaged over a window in a history of its own, this frame's included, so that a firefly raises it at once;
 *   where the history is younger than TAA_BLEND_MIN_FRAMES frames, v_s is at least the variance of the 3x3
 *   neighbourhood's samples. Successive samples differ by one fetch's blur, not by what the blur of many frames has
 *   done to a running mean: a variance about such a mean (SVGF's two moments) counts the image's own detail under
 *   sub-pixel motion as noise, and takes the blur this blend is to undo for a reason to keep it;
 * - e_h is the (clipped) history's expected squared error, whatever its cause (its noise, the bilinear fetch's blur,
 *   lag): a sample is independent of the history before it, so E[(s - h)^2] = v_s + e_h. The moments history
 *   carries D, the mean of (s - h)^2 over the same window as the moments, and e_h = D - (1 + TAA_BLEND_MARGIN) v_s
 *   (at least 0). D is last frame's, without this frame's sample, and the margin takes off what the two estimates'
 *   own noise would let through: on a noisy sample e_h stays near 0 and the weight at the fixed blend's.
 * a never falls below the fixed blend's max(1/n, alpha_min): a noisy input keeps the history as long as before; a
 * quiet one whose history has drifted from it (blurred, lagging) is trusted more. A still scene keeps the fixed
 * blend (its history is sharp and 1/n the optimum) but carries the moments, so that later motion finds them.
 *
 * The moments history holds (y, v_s, D, a) per pixel: the sample's luminance, the two windowed means, and the
 * weight this frame took (for tests and probes). A new term takes the weight max(1/m, TAA_BLEND_MOMENT_ALPHA) on a
 * moving frame (a window of about ten frames, so that they follow a path whose surface changes), 1/m on a still one,
 * m the number of terms (the history's length less one: its first frame has no difference and no history). */
#ifndef RESTIRCL_TAA_BLEND_WEIGHT_H
#define RESTIRCL_TAA_BLEND_WEIGHT_H

#ifndef TAA_BLEND_MOMENT_ALPHA
#define TAA_BLEND_MOMENT_ALPHA 0.2f
#endif
#ifndef TAA_BLEND_MIN_FRAMES
#define TAA_BLEND_MIN_FRAMES 4.0f
#endif
#ifndef TAA_BLEND_MARGIN
#define TAA_BLEND_MARGIN 1.0f
#endif

inline float taa_luma(float3 c)
{
    return 0.25f * c.x + 0.5f * c.y + 0.25f * c.z;
}

/* The weight of the newest of m terms in a window mean. */
inline float taa_moment_weight(float m, int moving)
{
    return moving ? fmax_f(1.0f / m, TAA_BLEND_MOMENT_ALPHA) : 1.0f / m;
}

/* The moments of a pixel without history: its sample alone, no evidence on its noise or a history yet, weight 1. */
inline float4 taa_moments_start(float y)
{
    return (float4)(y, 0.0f, 0.0f, 1.0f);
}

/* The sample's variance v_s with this frame's sample luminance y: mom fetched with the colour (mom.x last frame's
 * sample, fetched with taps whose weights sum to w2 in squares), n the history's length with this frame;
 * spatial_var: the 3x3 neighbourhood's. */
inline float taa_sample_variance(float4 mom, float y, float w2, float n, int moving, float spatial_var)
{
    float d = y - mom.x;
    float v = mom.y + taa_moment_weight(n - 1.0f, moving) * (d * d / (1.0f + w2) - mom.y);
    return n < TAA_BLEND_MIN_FRAMES ? fmax_f(v, spatial_var) : v;
}

/* The blend weight a = e_h / (e_h + v_s), at least a_fixed; d2: D, the mean of (s - h)^2 before this frame. */
inline float taa_blend_weight(float v_s, float d2, float a_fixed)
{
    float e_h = fmax_f(d2 - (1.0f + TAA_BLEND_MARGIN) * v_s, 0.0f);
    float a = e_h + v_s > 0.0f ? e_h / (e_h + v_s) : a_fixed;
    return clamp_f(a, a_fixed, 1.0f);
}

/* The moments history this frame leaves: its sample's luminance y, v_s, D with this frame's (s - h)^2 (d: the
 * luminance of s - h, h clipped; n the history's length with this frame), and the weight a taken. */
inline float4 taa_moments_leave(float4 mom, float y, float v_s, float d, float n, int moving, float a)
{
    return (float4)(y, v_s, mom.z + taa_moment_weight(n - 1.0f, moving) * (d * d - mom.z), a);
}

#endif
