/* Lights: a sample y = (light, u, v) maps to a point on the light (a direction for the sun) that does not depend on
 * the shading point, so a sample can be re-evaluated at any pixel (ReSTIR reuse). Each light type has one measure:
 * area for triangle, quad, disk and sphere lights, solid angle for the sun, a delta for points (radius 0) and a
 * sun of angle 0. light_sample() draws (u, v) at a shading point with its pdf in that measure; light_eval() gives
 * the unshadowed contribution Le * cos_x * G in the same measure (the BRDF is applied by the caller).
 * A soft-falloff point light maps (u, v) to a disk facing the shading point: its measure is the disk's area, the
 * same for every pixel, so reuse across pixels stays valid (the point moves with the pixel, the measure does not).
 * Feature flags HAS_<TYPE>_LIGHTS (set by the host from the scene) compile only the types a scene has. */
#ifndef RESTIRCL_LIGHTS_H
#define RESTIRCL_LIGHTS_H

#include "numerics.h"

#define RESTIRCL_PI 3.14159265358979f
#define RESTIRCL_INV_PI 0.318309886183791f

typedef struct {
    float3 contrib;   /* Le * cos_x * G: cos_l / d^2 for area measure, 1 for solid angle, 1 / d^2 for points */
    float3 wi;        /* unit direction from the shading point towards the sample */
    float3 pos;       /* point on the light (shadow ray target); unused for the sun */
    float3 nl;        /* light normal at pos, facing the shading point (for offsetting the shadow ray end) */
    float dist;       /* distance to pos; INFINITY for the sun */
    float eps;        /* emissive triangles (lights that are also geometry): a bound of the float32 error of pos, by
                         which the shadow ray stops short of it (shading.h visible); 0 for every other light */
} LightEval;

/* Shadow ray ends are moved off their surfaces by RESTIRCL_OFFSET_ULPS float32 epsilons of the largest magnitude in
 * the sum that computed the point (p = v0 + u e1 + v e2): a bound of its rounding error with a margin, like pbrt's
 * error bounds (gamma(7) sum |b_i v_i|). */
#define RESTIRCL_OFFSET_ULPS 8.0f

inline float max_abs3(float3 v) { return fmax_f(abs_f(v.x), fmax_f(abs_f(v.y), abs_f(v.z))); }

inline int light_type(const __global Light* l) { return as_int(l->p.w); }

inline float luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

/* Orthonormal basis around unit n (Duff et al. 2017). */
inline void light_onb(float3 n, float3* s, float3* t)
{
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    *s = (float3)(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *t = (float3)(b, sign + n.y * n.y * a, -n.y);
}

/* Shirley-Chiu concentric map of [0,1)^2 to the unit disk. */
inline float2 concentric_disk(float u, float v)
{
    float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
    if (a == 0.0f && b == 0.0f) return (float2)(0.0f, 0.0f);
    float r, phi;
    if (abs_f(a) > abs_f(b)) { r = a; phi = (RESTIRCL_PI * 0.25f) * (b / a); }
    else { r = b; phi = (RESTIRCL_PI * 0.5f) - (RESTIRCL_PI * 0.25f) * (a / b); }
    return (float2)(r * cos(phi), r * sin(phi));
}

/* Unit sphere direction <-> (u, v): u = (z + 1) / 2, v = azimuth / 2pi. */
inline float3 sphere_dir(float u, float v)
{
    float z = 2.0f * u - 1.0f;
    float rxy = sqrt(fmax_f(0.0f, 1.0f - z * z));
    float phi = 2.0f * RESTIRCL_PI * v;
    return (float3)(rxy * cos(phi), rxy * sin(phi), z);
}

inline float2 sphere_uv(float3 d)
{
    float u = clamp_f(0.5f * (d.z + 1.0f), 0.0f, 1.0f);
    float v = atan2(d.y, d.x) * (0.5f * RESTIRCL_INV_PI);
    if (v < 0.0f) v += 1.0f;
    return (float2)(u, v >= 1.0f ? 0.0f : v);
}

/* Direction inside a cone around unit axis w with 1 - cos(half-angle) = omc, from (u, v) uniform in solid angle. */
inline float3 cone_dir(float3 w, float omc, float u, float v)
{
    float omc_t = u * omc;                              /* 1 - cos(theta), exact for tiny cones */
    float sin_t = sqrt(fmax_f(0.0f, omc_t * (2.0f - omc_t)));
    float phi = 2.0f * RESTIRCL_PI * v;
    float3 s, t;
    light_onb(w, &s, &t);
    return norm3(sin_t * cos(phi) * s + sin_t * sin(phi) * t + (1.0f - omc_t) * w);
}

/* Contribution of an emitter point y with normal ny (area measure) seen from x with normal n. */
inline bool area_contrib(float3 y, float3 ny, float3 Le, bool two_sided, float3 x, float3 n, LightEval* e)
{
    float3 d = y - x;
    float d2 = dot3(d, d);
    if (!(d2 > 1e-30f)) return false;
    float dist = sqrt(d2);
    float3 wi = d / dist;
    float cos_x = dot3(n, wi);
    float cos_l = -dot3(ny, wi);
    if (two_sided) { if (cos_l < 0.0f) { cos_l = -cos_l; ny = -ny; } }
    if (!(cos_x > 0.0f) || !(cos_l > 0.0f)) return false;
    e->contrib = Le * (cos_x * cos_l / d2);
    e->wi = wi;
    e->pos = y;
    e->nl = ny;
    e->dist = dist;
    return true;
}

/* The point of sample (u, v) on an area-like light, and its normal (emitting side). */
inline float3 light_point(const __global Light* l, int type, float u, float v, float3* ny)
{
    float3 a = l->a.xyz, b = l->b.xyz;
#ifdef HAS_TRIANGLE_LIGHTS
    if (type == LIGHT_TRIANGLE) {
        float su = sqrt(u);
        *ny = norm3(cross3(a, b));
        return l->p.xyz + a * (su * (1.0f - v)) + b * (su * v);
    }
#endif
#ifdef HAS_QUAD_LIGHTS
    if (type == LIGHT_QUAD) {
        *ny = norm3(cross3(a, b));
        return l->p.xyz + u * a + v * b;
    }
#endif
#ifdef HAS_DISK_LIGHTS
    if (type == LIGHT_DISK) {
        float2 q = concentric_disk(u, v);
        *ny = norm3(cross3(a, b));
        return l->p.xyz + q.x * a + q.y * b;
    }
#endif
    /* sphere and spot */
    float3 dir = sphere_dir(u, v);
    *ny = dir;
    return l->p.xyz + l->a.w * dir;
}

/* Spot cone mask at unit direction `out` from the light towards the shading point (Blender 4+: smoothstep). */
inline float spot_mask(const __global Light* l, float3 out)
{
    float c = dot3(out, l->a.xyz);
    float cos_half = l->b.x, smooth = l->b.y;
    if (c <= cos_half) return 0.0f;
    if (smooth <= 0.0f) return 1.0f;
    float t = clamp_f((c - cos_half) / smooth, 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

/* Unshadowed contribution of sample (u, v) of light l at shading point x with unit normal n. */
inline bool light_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    int type = light_type(l);
    float3 Le = l->L.xyz;
    e->eps = 0.0f;
#ifdef HAS_SUN_LIGHTS
    if (type == LIGHT_SUN) {
        float omc = l->b.y;
        float3 wi = omc > 0.0f ? cone_dir(l->a.xyz, omc, u, v) : l->a.xyz;
        float cos_x = dot3(n, wi);
        if (!(cos_x > 0.0f)) return false;
        e->contrib = Le * cos_x;
        e->wi = wi;
        e->pos = x + wi;
        e->nl = -wi;
        e->dist = INFINITY;
        return true;
    }
#endif
#if defined(HAS_SPHERE_LIGHTS) || defined(HAS_SPOT_LIGHTS)
    if (type == LIGHT_SPHERE || type == LIGHT_SPOT) {
        float mask = 1.0f;
        float3 c = l->p.xyz;
#ifdef HAS_SPOT_LIGHTS
        if (type == LIGHT_SPOT) {
            float3 out = x - c;
            float len = len3(out);
            if (!(len > 0.0f)) return false;
            mask = spot_mask(l, out / len);
            if (!(mask > 0.0f)) return false;
        }
#endif
        float r = l->a.w;
        if (r > 0.0f && (as_int(l->L.w) & LIGHT_FLAG_SOFT_FALLOFF)) {
            /* Blender's soft falloff: a disk of radius r facing the shading point */
            float3 w = c - x;
            float dc = len3(w);
            if (!(dc > 0.0f)) return false;
            w /= dc;
            float3 s, t;
            light_onb(w, &s, &t);
            float2 q = concentric_disk(u, v);
            return area_contrib(c + r * (q.x * s + q.y * t), -w, Le * mask, false, x, n, e);
        }
        if (r > 0.0f) {
            float3 ny;
            float3 y = light_point(l, type, u, v, &ny);
            return area_contrib(y, ny, Le * mask, false, x, n, e);
        }
        float3 d = c - x;
        float d2 = dot3(d, d);
        if (!(d2 > 1e-30f)) return false;
        float dist = sqrt(d2);
        float3 wi = d / dist;
        float cos_x = dot3(n, wi);
        if (!(cos_x > 0.0f)) return false;
        e->contrib = Le * (mask * cos_x / d2);
        e->wi = wi;
        e->pos = c;
        e->nl = -wi;
        e->dist = dist;
        return true;
    }
#endif
    float3 ny;
    float3 y = light_point(l, type, u, v, &ny);
#ifdef HAS_TRIANGLE_LIGHTS
    if (type == LIGHT_TRIANGLE)
        e->eps = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(l->p.xyz) + max_abs3(l->a.xyz) + max_abs3(l->b.xyz));
#endif
    return area_contrib(y, ny, Le, (as_int(l->L.w) & LIGHT_FLAG_TWO_SIDED) != 0, x, n, e);
}

/* Draw a sample (u, v) of light l for shading point x; *pdf is the density of the sampled point in the light's
 * measure (0: nothing could be sampled). Uniform in (u, v) except for spheres seen from outside (visible cone). */
inline float2 light_sample_typed(const __global Light* l, int type, float3 x, float r0, float r1, float* pdf)
{
#ifdef HAS_SUN_LIGHTS
    if (type == LIGHT_SUN) {
        float omc = l->b.y;
        *pdf = omc > 0.0f ? 1.0f / (2.0f * RESTIRCL_PI * omc) : 1.0f;
        return (float2)(r0, r1);
    }
#endif
#if defined(HAS_SPHERE_LIGHTS) || defined(HAS_SPOT_LIGHTS)
    if (type == LIGHT_SPHERE || type == LIGHT_SPOT) {
        float r = l->a.w;
        if (!(r > 0.0f)) { *pdf = 1.0f; return (float2)(r0, r1); }
        if (as_int(l->L.w) & LIGHT_FLAG_SOFT_FALLOFF) { *pdf = 1.0f / (RESTIRCL_PI * r * r); return (float2)(r0, r1); }
        float3 d = l->p.xyz - x;
        float dc2 = dot3(d, d);
        float r2 = r * r;
        if (dc2 <= r2 * 1.0001f) {  /* inside or touching: uniform over the sphere's area */
            *pdf = 1.0f / (4.0f * RESTIRCL_PI * r2);
            return (float2)(r0, r1);
        }
        float dc = sqrt(dc2);
        float3 wc = d / dc;
        float sin2max = r2 / dc2;
        float cosmax = sqrt(fmax_f(0.0f, 1.0f - sin2max));
        float omc = sin2max / (1.0f + cosmax);
        float omc_t = r0 * omc;
        float sin2_t = omc_t * (2.0f - omc_t);
        float cos_t = 1.0f - omc_t;
        float rho = fmin_f(sin2_t / sin2max, 1.0f);
        float cos_a = rho * sqrt(sin2max) + cos_t * sqrt(fmax_f(0.0f, 1.0f - rho));
        float sin_a = sqrt(fmax_f(0.0f, 1.0f - cos_a * cos_a));
        float phi = 2.0f * RESTIRCL_PI * r1;
        float3 s, t;
        light_onb(wc, &s, &t);
        float3 ny = -(sin_a * cos(phi) * s + sin_a * sin(phi) * t + cos_a * wc);
        ny = norm3(ny);
        /* area density of the point: pdf_omega * cos_l / dist^2 */
        float3 y = l->p.xyz + r * ny;
        float3 dy = x - y;
        float dist2 = dot3(dy, dy);
        float cos_l = dot3(ny, dy) * rsqrt(fmax_f(dist2, 1e-38f));
        *pdf = (cos_l > 0.0f && dist2 > 0.0f) ? cos_l / (dist2 * 2.0f * RESTIRCL_PI * omc) : 0.0f;
        return sphere_uv(ny);
    }
#endif
    *pdf = 1.0f / l->b.w;
    return (float2)(r0, r1);
}

/* light_sample with the light's type read here; light_sample_typed takes it from a caller that read it earlier. */
inline float2 light_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    return light_sample_typed(l, light_type(l), x, r0, r1, pdf);
}

#endif
