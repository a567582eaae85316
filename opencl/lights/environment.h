/* The environment (Blender's World > Background): radiance from every direction, an equirectangular map of RGB
 * texels times a colour and strength, sampled proportionally to luminance x texel solid angle. A constant colour is
 * a 1x1 map. Its measure is solid angle: a sample (u, v) is the image coordinates of a direction (u across from
 * the azimuth, v down from the zenith), the same at every shading point, so reuse can re-evaluate it anywhere;
 * visibility is a ray to infinity.
 *
 * The map and its sampling table are not in the 64-byte record: they follow the light records in the same buffer
 * (the host puts them there, python/restircl/lights/environment.py), and the record holds their offsets in floats
 * from itself. That keeps every kernel's arguments as they are; a copy of the record elsewhere (a light tile) must
 * not be used to reach them (direct/ris.h reads the environment's record from the light buffer).
 *
 * Directions follow Blender's mapping of the World's default vector d (Z up): after the lookup rotation R (a
 * Mapping node), d' = R d, u = 1/2 - atan2(d'.y, d'.x) / (2 pi), v = acos(d'.z) / pi; row 0 of the map is the
 * zenith. Within a texel, directions are uniform in solid angle, so the density is constant over it:
 * pdf = P(texel) / solid angle(texel); a Linear map's density follows its blend instead (environment_sample_linear). */
#ifndef RESTIRCL_LIGHTS_ENVIRONMENT_H
#define RESTIRCL_LIGHTS_ENVIRONMENT_H

#include "codes.h"

#include "lights/eval.h"
#include "lights/record.h"
#include "sampling/warps.h"

/* L.w flags: camera rays that miss the geometry see it (Film > Transparent leaves alpha 0 either way) */
/* the sampling table is the pair of cumulative distributions (else the alias tables) */
/* the texels are RGB half floats (else float32): radiance / 2^k, the record's radiance holds the 2^k
 * (python/restircl/environment/pack.py) */

typedef struct {
    const __global float* texels;  /* p.x: offset in floats from the record; W x H RGB triples, row 0 up */
    const __global float* table;   /* a.w: offset of the sampling table (environment/table.py) */
    int width, height;             /* p.y, p.z */
    float3 r0, r1, r2;             /* a.xyz, b.xyz: rows of the lookup rotation; r2 = r0 x r1 */
    float norm;                    /* b.w: 1 / sum(luminance x solid angle): the alias tables' pdf per luminance */
    int cdf;                       /* the table is cumulative distributions */
    int half_texels;               /* the texels are half floats (vload_half3), else float32 */
    int linear;                    /* read with Linear interpolation (environment_lookup), else Closest */
} EnvLight;

inline EnvLight environment_light(const __global Light* l)
{
    const __global float* base = (const __global float*)l;
    EnvLight env = {base + as_int(l->p.x), base + as_int(l->a.w), as_int(l->p.y), as_int(l->p.z), l->a.xyz, l->b.xyz, cross3(l->a.xyz, l->b.xyz), l->b.w, (light_flags(l) & ENV_FLAG_CDF) != 0, (light_flags(l) & ENV_FLAG_HALF) != 0, (light_flags(l) & ENV_FLAG_LINEAR) != 0};
    return env;
}

/* (u, v) of world direction d (unit). */
inline float2 environment_uv(const EnvLight* env, float3 d)
{
    float3 r = (float3)(dot3(env->r0, d), dot3(env->r1, d), dot3(env->r2, d));
    float u = 0.5f - atan2(r.y, r.x) * (0.5f / RESTIRCL_PI);
    u -= floor(u);
    float v = acos(fmin_f(fmax_f(r.z, -1.0f), 1.0f)) * (1.0f / RESTIRCL_PI);
    return (float2)(u, v);
}

/* The world direction (unit) of image coordinates (u, v). */
inline float3 environment_dir(const EnvLight* env, float u, float v)
{
    float phi = RESTIRCL_PI * (1.0f - 2.0f * u);
    float theta = RESTIRCL_PI * v;
    float st = sin(theta);
    float3 r = (float3)(st * cos(phi), st * sin(phi), cos(theta));
    return env->r0 * r.x + env->r1 * r.y + env->r2 * r.z;  /* R^T r */
}

inline int2 environment_texel(const EnvLight* env, float u, float v)
{
    int col = clamp((int)(u * (float)env->width), 0, env->width - 1);
    int row = clamp((int)(v * (float)env->height), 0, env->height - 1);
    return (int2)(col, row);
}

/* The stored texel (times the record's radiance: radiance). Half floats are read with vload_half3, core in
 * OpenCL 1.2: a half pointer needs no cl_khr_fp16 when it is only loaded from. */
inline float3 environment_texel_rgb(const EnvLight* env, int2 t)
{
    int i = t.y * env->width + t.x;
    if (env->half_texels) return vload_half3(i, (const __global half*)env->texels);
    return vload3(i, env->texels);
}

inline int environment_wrap(int i, int n) { return i < 0 ? i + n : (i >= n ? i - n : i); }

/* The map at image coordinates (u, v), as stored (times the record's radiance: radiance): the texel there
 * (Closest), or with Linear interpolation the blend of the four texel centres around it, wrapping across the seam
 * and over the poles as Cycles' Environment Texture does (its extension is Repeat both ways). A Linear map is
 * sampled by the blend's bilinear patches (environment_sample_linear). */
inline float3 environment_lookup(const EnvLight* env, float u, float v)
{
    if (!env->linear) return environment_texel_rgb(env, environment_texel(env, u, v));
    float x = u * (float)env->width - 0.5f, y = v * (float)env->height - 0.5f;
    float fx = floor(x), fy = floor(y);
    float tx = x - fx, ty = y - fy;
    int c0 = environment_wrap((int)fx, env->width), c1 = environment_wrap(c0 + 1, env->width);
    int r0 = environment_wrap((int)fy, env->height), r1 = environment_wrap(r0 + 1, env->height);
    float3 above = (1.0f - tx) * environment_texel_rgb(env, (int2)(c0, r0))
                   + tx * environment_texel_rgb(env, (int2)(c1, r0));
    float3 below = (1.0f - tx) * environment_texel_rgb(env, (int2)(c0, r1))
                   + tx * environment_texel_rgb(env, (int2)(c1, r1));
    return (1.0f - ty) * above + ty * below;
}

/* Radiance arriving from world direction d (unit): what a camera ray that misses sees. */
inline float3 environment_radiance(const __global Light* l, float3 d)
{
    EnvLight env = environment_light(l);
    float2 uv = environment_uv(&env, d);
    return light_radiance(l) * environment_lookup(&env, uv.x, uv.y);
}

/* The solid angle of one texel of row `row`. */
inline float environment_texel_solid_angle(const EnvLight* env, int row)
{
    float h = (float)env->height;
    return (cos(RESTIRCL_PI * (float)row / h) - cos(RESTIRCL_PI * (float)(row + 1) / h))
           * (2.0f * RESTIRCL_PI / (float)env->width);
}

/* The sampling density in solid angle of texel t: read from the tables themselves, so that it is the probability
 * with which they draw it (the cumulative distributions' steps; the alias tables draw luminance x solid angle x
 * norm, to float32 rounding). */
inline float environment_texel_pdf(const EnvLight* env, int2 t)
{
    if (env->cdf) {
        const __global float* marg = env->table;
        const __global float* row = env->table + (env->height + 1) + t.y * (env->width + 1);
        float p = (marg[t.y + 1] - marg[t.y]) * (row[t.x + 1] - row[t.x]);
        return p / environment_texel_solid_angle(env, t.y);
    }
    return luminance(environment_texel_rgb(env, t)) * env->norm;
}

/* Draw entry k from n with an alias table of (prob, alias) pairs; *r in [0, 1) is consumed and comes back as a
 * fresh uniform number for what follows. */
inline int environment_alias_draw(const __global float* pairs, int n, float* r)
{
    float x = *r * (float)n;
    int k = min((int)x, n - 1);
    float f = x - (float)k;
    float prob = pairs[2 * k];
    if (f < prob) {
        *r = f / prob;
        return k;
    }
    *r = (f - prob) / (1.0f - prob);
    return as_int(pairs[2 * k + 1]);
}

/* Draw entry k from n with a cumulative distribution cdf[0..n] (0 to 1); *r as in environment_alias_draw. */
inline int environment_cdf_draw(const __global float* cdf, int n, float* r)
{
    int lo = 0, hi = n;  /* cdf[lo] <= r < cdf[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) >> 1;
        if (cdf[mid] <= *r) lo = mid; else hi = mid;
    }
    float c0 = cdf[lo], c1 = cdf[lo + 1];
    *r = c1 > c0 ? (*r - c0) / (c1 - c0) : 0.5f;
    return lo;
}

inline float environment_unit(float r) { return fmin_f(fmax_f(r, 0.0f), 0.99999994f); }

/* A Linear map's dual cell (k, j): the bilinear patch of the blend between centre rows k - 1 and k and centre
 * columns j and j + 1 (wrapped as the lookup wraps; rows k = 0 and k = H are the half-rows at the poles,
 * python/restircl/environment/interpolation.py). The tables (H + 1 rows of W) draw it by its mean luminance x its
 * band's solid angle; inside it (tx, ty) is drawn proportionally to the patch, so the density in (u, v) follows the
 * blend's luminance. */
typedef struct {
    float a00, a01, a10, a11;  /* corner luminances: (row k - 1, column j), (k - 1, j + 1), (k, j), (k, j + 1) */
    float t0, t1;              /* the cell's extent in ty: [1/2, 1] for k = 0, [0, 1/2] for k = H, else [0, 1] */
} EnvDualCell;

inline EnvDualCell environment_dual_cell(const EnvLight* env, int k, int j)
{
    int h = env->height, w = env->width;
    int r0 = environment_wrap(k - 1, h), r1 = environment_wrap(k, h), c1 = environment_wrap(j + 1, w);
    EnvDualCell c;
    c.a00 = luminance(environment_texel_rgb(env, (int2)(j, r0)));
    c.a01 = luminance(environment_texel_rgb(env, (int2)(c1, r0)));
    c.a10 = luminance(environment_texel_rgb(env, (int2)(j, r1)));
    c.a11 = luminance(environment_texel_rgb(env, (int2)(c1, r1)));
    c.t0 = k == 0 ? 0.5f : 0.0f;
    c.t1 = k == h ? 0.5f : 1.0f;
    return c;
}

/* The density in solid angle of the point (tx, ty) of dual cell (k, j) whose direction has sin(theta) = st: the
 * table's probability of the cell x patch / (its mean x its extent in (u, v)), over the Jacobian 2 pi^2 sin(theta)
 * of (u, v). */
inline float environment_dual_pdf(const EnvLight* env, const EnvDualCell* c, int k, int j, float tx, float ty,
                                  float st)
{
    int w = env->width, rows = env->height + 1;
    float tm = 0.5f * (c->t0 + c->t1);
    float mean = 0.5f * ((1.0f - tm) * (c->a00 + c->a01) + tm * (c->a10 + c->a11));
    if (!(mean > 0.0f)) return 0.0f;
    const __global float* row = env->table + (rows + 1) + k * (w + 1);
    float p = (env->table[k + 1] - env->table[k]) * (row[j + 1] - row[j]);
    float patch = (1.0f - ty) * ((1.0f - tx) * c->a00 + tx * c->a01) + ty * ((1.0f - tx) * c->a10 + tx * c->a11);
    st = fmax_f(st, 1e-7f);
    return p * patch * (float)(w * env->height)
           / (mean * (c->t1 - c->t0) * (2.0f * RESTIRCL_PI * RESTIRCL_PI) * st);
}

/* The density in solid angle of a Linear map's sampling at image coordinates (u, v), sin(theta) = st (given apart:
 * near the poles v, from an acos, has lost the digits that sin(theta) needs). */
inline float environment_linear_pdf(const EnvLight* env, float u, float v, float st)
{
    float x = u * (float)env->width - 0.5f, y = v * (float)env->height - 0.5f;
    float fx = floor(x), fy = floor(y);
    int j = environment_wrap((int)fx, env->width);
    int k = clamp((int)fy + 1, 0, env->height);
    EnvDualCell c = environment_dual_cell(env, k, j);
    float tx = fmin_f(fmax_f(x - fx, 0.0f), 1.0f);
    float ty = fmin_f(fmax_f(y - (float)(k - 1), c.t0), c.t1);
    return environment_dual_pdf(env, &c, k, j, tx, ty, st);
}

/* t in [0, 1] drawn from r with density proportional to (1 - t) p0 + t p1 (p0, p1 >= 0): the root of the quadratic
 * cumulative distribution, written so that it neither cancels nor divides by p1 - p0. */
inline float environment_linear_warp(float r, float p0, float p1)
{
    if (!(p0 + p1 > 0.0f)) return r;
    float t = r * (p0 + p1) / (p0 + sqrt(fmax_f(p0 * p0 + r * (p1 * p1 - p0 * p0), 0.0f)));
    return fmin_f(fmax_f(t, 0.0f), 1.0f);
}

/* A Linear map's sample: a dual cell from the tables, then ty from the patch's marginal (linear in ty) and tx
 * from its conditional (linear in tx). */
inline float2 environment_sample_linear(const EnvLight* env, float r0, float r1, float* pdf)
{
    int w = env->width, h = env->height, rows = h + 1;
    int k = environment_cdf_draw(env->table, rows, &r0);
    int j = environment_cdf_draw(env->table + (rows + 1) + k * (w + 1), w, &r1);
    EnvDualCell c = environment_dual_cell(env, k, j);
    r0 = environment_unit(r0);
    r1 = environment_unit(r1);
    float m0 = (1.0f - c.t0) * (c.a00 + c.a01) + c.t0 * (c.a10 + c.a11);
    float m1 = (1.0f - c.t1) * (c.a00 + c.a01) + c.t1 * (c.a10 + c.a11);
    float ty = c.t0 + (c.t1 - c.t0) * environment_linear_warp(r0, m0, m1);
    float tx = environment_linear_warp(r1, (1.0f - ty) * c.a00 + ty * c.a10, (1.0f - ty) * c.a01 + ty * c.a11);
    float u = ((float)j + 0.5f + tx) / (float)w;
    u -= floor(u);
    float v = fmin_f(fmax_f(((float)k - 0.5f + ty) / (float)h, 0.0f), 1.0f);
    *pdf = environment_dual_pdf(env, &c, k, j, tx, ty, sin(RESTIRCL_PI * v));
    return (float2)(u, v);
}

/* (u, v) of a direction drawn from the tables with two uniform numbers; *pdf its density in solid angle. */
inline float2 environment_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    (void)x;
    EnvLight env = environment_light(l);
    if (env.linear) return environment_sample_linear(&env, r0, r1, pdf);
    int w = env.width, h = env.height;
    int row, col;
    if (env.cdf) {
        row = environment_cdf_draw(env.table, h, &r0);
        col = environment_cdf_draw(env.table + (h + 1) + row * (w + 1), w, &r1);
    } else {
        row = environment_alias_draw(env.table, h, &r0);
        col = environment_alias_draw(env.table + 2 * h + 2 * row * w, w, &r1);
    }
    r0 = environment_unit(r0);
    r1 = environment_unit(r1);
    /* uniform in solid angle inside the texel: u uniform in the column, cos(theta) uniform in the row */
    float c0 = cos(RESTIRCL_PI * (float)row / (float)h), c1 = cos(RESTIRCL_PI * (float)(row + 1) / (float)h);
    float v = acos(fmin_f(fmax_f(c0 + r0 * (c1 - c0), -1.0f), 1.0f)) * (1.0f / RESTIRCL_PI);
    /* keep the point in its texel against the rounding of acos */
    float v_lo = (float)row / (float)h, v_hi = (float)(row + 1) / (float)h;
    v = fmin_f(fmax_f(v, v_lo), v_hi - 0.5f * (v_hi - v_lo) * FLT_EPSILON * (float)h);
    float u = ((float)col + r1) / (float)w;
    *pdf = environment_texel_pdf(&env, (int2)(col, row));
    return (float2)(u, v);
}

inline bool environment_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    EnvLight env = environment_light(l);
    float3 wi = environment_dir(&env, u, v);
    float cos_x = dot3(n, wi);
    if (!(cos_x > 0.0f)) return false;
    e->contrib = light_radiance(l) * environment_lookup(&env, u, v) * cos_x;
    e->wi = wi;
    e->pos = x + wi;
    e->nl = -wi;
    e->dist = INFINITY;
    return true;
}

/* light_sample's density of the direction e->wi (solid angle). */
inline float environment_point_pdf(const __global Light* l, float3 x, const LightEval* e)
{
    (void)x;
    EnvLight env = environment_light(l);
    float2 uv = environment_uv(&env, e->wi);
    if (env.linear) {
        float3 d = e->wi;
        float rx = dot3(env.r0, d), ry = dot3(env.r1, d);
        return environment_linear_pdf(&env, uv.x, uv.y, sqrt(rx * rx + ry * ry));
    }
    return environment_texel_pdf(&env, environment_texel(&env, uv.x, uv.y));
}

/* Does the environment emit at all (a map of zeros or a strength of 0 is never sampled nor hit)? */
inline bool environment_emits(const __global Light* l) { return environment_light(l).norm > 0.0f; }

/* Every ray that leaves the scene meets the environment: the sample (u, v) of direction wi. Occluders are left
 * to the shadow ray, as for the sun, so the BSDF's density of the direction is exact. */
inline bool environment_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    (void)x;
    if (!environment_emits(l)) return false;
    EnvLight env = environment_light(l);
    *uv = environment_uv(&env, wi);
    return true;
}

inline bool environment_hittable(const __global Light* l) { return environment_emits(l); }

/* The radiance arriving from the direction of sample (u, v). */
inline float3 environment_hit_radiance(const __global Light* l, float3 x, float2 uv)
{
    (void)x;
    EnvLight env = environment_light(l);
    return light_radiance(l) * environment_lookup(&env, uv.x, uv.y);
}

/* What a camera ray of direction d that meets no geometry sees: the environment when the scene has one that
 * camera rays see (the host puts it first in the light buffer), else black. The type is read first: a scene
 * without lights has a 16-byte placeholder buffer. */
inline float3 environment_seen(const __global Light* lights, float3 d)
{
    const __global Light* l = &lights[0];
    if (light_type(l) != LIGHT_ENVIRONMENT || !(light_flags(l) & ENV_FLAG_CAMERA)) return (float3)(0.0f);
    return environment_radiance(l, d);
}

#endif
