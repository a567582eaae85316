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

/* A pixel's direct light as the light passes split it (film/light_passes.h): diffuse, glossy, transmission */
typedef struct {
    float3 d;
    float3 g;
    float3 t;
} DirectSplit;

inline DirectSplit direct_split_zero(void)
{
    DirectSplit z = {(float3)(0.0f), (float3)(0.0f), (float3)(0.0f)};
    return z;
}

/* Contribution x of direct light at s from direction wi, clamped; where light passes are on, also added to the
 * split *p of the direct light (film/light_passes.h) */
inline float3 direct_contribution(const Surface* s, float3 wi, float3 x, float clamp, DirectSplit* p)
{
    x *= clamp_scale(x, clamp);
#ifdef HAS_LIGHT_PASSES
    light_pass_split(s, wi, x, &p->d, &p->g, &p->t);
#else
    (void)s;
    (void)wi;
    (void)p;
#endif
    return x;
}

/* The end of a direct estimator's pixel: where light passes are on, its direct light p and Clamp Direct's scale k
 * of what the camera sees go to the passes (film/light_passes.h light_pass_direct) */
inline void direct_passes(__global float4* lp, int pixels, int i, const DirectSplit* p, float k)
{
#ifdef HAS_LIGHT_PASSES
    light_pass_direct(lp, pixels, i, p->d, p->g, p->t, k);
#else
    (void)lp;
    (void)pixels;
    (void)i;
    (void)p;
    (void)k;
#endif
}

#endif
