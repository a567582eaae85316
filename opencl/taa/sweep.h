/* Motion blur in TAA: the shutter's sweep. An animation frame with motion blur is the scene at one time of its
 * shutter (render/shutter.py); TAA averages frames at other times into the blurred image. What a pixel shows over
 * the shutter is every surface whose path on the image passes over it while the shutter is open: where that is a
 * moving object over a still background (the blur's band), the pixel's own surface is the background, whose motion
 * (none) would keep the band where it was, and whose 3x3 neighbourhood (background only) would clip it away. So a
 * blurred frame reprojects a pixel by the fastest motion whose sweep crosses it (the band moves with its object),
 * without the same-surface test (a blurred pixel's history is several surfaces), and clips the history to a box
 * that also spans the colours the current frame shows along that sweep (docs/design.md, "Depth of field and motion blur in motion"). */
#ifndef RESTIRCL_TAA_SWEEP_H
#define RESTIRCL_TAA_SWEEP_H

/* How far (pixels) a sweep is looked for around a pixel, on a grid of that step: a blur longer than the radius
 * from its object's edge at this frame's time is clipped there. */
#ifndef TAA_SWEEP_RADIUS
#define TAA_SWEEP_RADIUS 6
#endif
#define TAA_SWEEP_STEP 3
#define TAA_SWEEP_TAPS 6  /* taps of the clip box along the sweep */
/* The shortest path over the shutter (pixels) taken by these rules: a shorter blur lies within the 3x3 clip box of
 * a sharp frame, whose rules keep it. Under them the history is not tested for the pixel's own surface, and TAA's
 * clipping of a history kept over surface changes drains sub-pixel lights (a lamp hit by some frames' samples):
 * the far lamps of many_lights under the flying camera lost half their light with every path taken. */
#ifndef TAA_SWEEP_MIN
#define TAA_SWEEP_MIN 3.0f
#endif

/* Distance from point p to the segment a..b. */
inline float taa_segment_distance(float2 p, float2 a, float2 b)
{
    float2 ab = b - a, ap = p - a;
    float l2 = dot(ab, ab);
    float t = l2 > 0.0f ? clamp(dot(ap, ab) / l2, 0.0f, 1.0f) : 0.0f;
    return length(ap - t * ab);
}

/* The motion (previous minus current position, pixels per frame) of the fastest surface whose path over the shutter
 * [s0, s1] (frames from this frame's time) passes over pixel (x, y); the pixel's own when none moves faster; false
 * when neither has a previous position. A surface at q now is at q - m s at time s. */
inline bool taa_sweep_motion(const __global GSample* gbuf, int x, int y, int width, int height, float s0, float s1,
                             float2* motion)
{
    float4 own = gbuf[y * width + x].motion;
    bool found = own.z != 0.0f;
    float2 best = found ? own.xy : (float2)(0.0f);
    float best_len = length(best);
    float2 p = (float2)((float)x, (float)y);
    const float reach = 0.5f * (float)TAA_SWEEP_STEP + 0.5f;
    for (int dy = -TAA_SWEEP_RADIUS; dy <= TAA_SWEEP_RADIUS; dy += TAA_SWEEP_STEP)
        for (int dx = -TAA_SWEEP_RADIUS; dx <= TAA_SWEEP_RADIUS; dx += TAA_SWEEP_STEP) {
            int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            float4 m = gbuf[ny * width + nx].motion;
            if (m.z == 0.0f || !finite_f(m.x) || !finite_f(m.y)) continue;
            float len = length(m.xy);
            if (!(len > best_len)) continue;
            float2 q = (float2)((float)nx, (float)ny);
            if (taa_segment_distance(p, q - m.xy * s0, q - m.xy * s1) > reach) continue;
            best = m.xy;
            best_len = len;
            found = true;
        }
    *motion = best;
    return found;
}

/* Tap k of TAA_SWEEP_TAPS of the current frame along the sweep of `motion` through pixel (x, y), for the clip box:
 * what the pixel sees at time s is what is now at its position + motion * s. */
inline float3 taa_sweep_tap(const __global float4* sample, int x, int y, int width, int height, float2 motion,
                            float s0, float s1, int k)
{
    float s = s0 + (s1 - s0) * ((float)k + 0.5f) / (float)TAA_SWEEP_TAPS;
    float2 q = (float2)((float)x + 0.5f, (float)y + 0.5f) + motion * s;
    int nx = clamp((int)floor(q.x), 0, width - 1), ny = clamp((int)floor(q.y), 0, height - 1);
    return sample[ny * width + nx].xyz;
}

#endif
