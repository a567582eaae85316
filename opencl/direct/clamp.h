/* Cycles' Light Paths > Clamping > Direct Light (Settings.clamp_direct): a contribution of direct light whose rgb sum
 * exceeds 3x the clamp is scaled down to it, each on its own (Cycles' per-contribution clamp, whose limit is three
 * times the setting). Direct light is what Cycles counts at bounce 0: the emitters and the world the camera sees,
 * light samples at the first surface and the emitters its BSDF rays meet. Bounced light has Clamp Indirect
 * (path/walk.h path_clamp). */
#ifndef RESTIRCL_DIRECT_CLAMP_H
#define RESTIRCL_DIRECT_CLAMP_H

/* The factor that clamps contribution c (1: the clamp is off (0) or c is within it) */
inline float clamp_scale(float3 c, float clamp)
{
    float sum = c.x + c.y + c.z;
    return (clamp > 0.0f && sum > 3.0f * clamp) ? 3.0f * clamp / sum : 1.0f;
}

/* Contribution x of direct light at s from direction wi, clamped; where light passes are on, also split into the
 * diffuse (*d) and glossy (*g) direct light (film/light_passes.h) */
inline float3 direct_contribution(const Surface* s, float3 wi, float3 x, float clamp, float3* d, float3* g)
{
    x *= clamp_scale(x, clamp);
#ifdef HAS_LIGHT_PASSES
    light_pass_split(s, wi, x, d, g);
#else
    (void)s;
    (void)wi;
    (void)d;
    (void)g;
#endif
    return x;
}

/* The end of a direct estimator's pixel: where light passes are on, its direct light (d, g) and Clamp Direct's
 * scale k of what the camera sees go to the passes (film/light_passes.h light_pass_direct) */
inline void direct_passes(__global float4* lp, int pixels, int i, float3 d, float3 g, float k)
{
#ifdef HAS_LIGHT_PASSES
    light_pass_direct(lp, pixels, i, d, g, k);
#else
    (void)lp;
    (void)pixels;
    (void)i;
    (void)d;
    (void)g;
    (void)k;
#endif
}

#endif
