/* Sphere lights (Blender's point light): radius 0 is a point, a delta in position, and L holds its intensity;
 * otherwise L is the radiance of the sphere's surface. Blender's default soft falloff maps (u, v) to a disk of the
 * sphere's radius facing the shading point: its measure is the disk's area, the same for every pixel, so reuse
 * across pixels stays valid (the point moves with the pixel, the measure does not). Without it the sphere is
 * sampled in the cone it subtends, seen from outside. The soft-falloff disk is sampled uniformly in its area or,
 * where the host flags it (area_sampling), in the cone it subtends (soft_disk_sample). */
#ifndef RESTIRCL_LIGHTS_SPHERE_H
#define RESTIRCL_LIGHTS_SPHERE_H

#include "lights/eval.h"
#include "lights/record.h"
#include "lights/solid_angle.h"
#include "sampling/warps.h"

typedef struct {
    float3 centre;       /* p.xyz */
    float radius;        /* a.w; 0: a point */
    bool soft_falloff;   /* flags & LIGHT_FLAG_SOFT_FALLOFF */
} SphereLight;

inline SphereLight sphere_light(const __global Light* l)
{
    SphereLight s = {l->p.xyz, l->a.w, (light_flags(l) & LIGHT_FLAG_SOFT_FALLOFF) != 0};
    return s;
}

/* Sample (u, v) of sphere sp emitting Le, times mask: a spot's cone (spot.h), 1 for a sphere. */
inline bool sphere_emit(SphereLight sp, float3 Le, float mask, float u, float v, float3 x, float3 n, LightEval* e)
{
    float3 c = sp.centre;
    float r = sp.radius;
    if (r > 0.0f && sp.soft_falloff) {
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
        float3 ny = sphere_dir(u, v);
        return area_contrib(c + r * ny, ny, Le * mask, false, x, n, e);
    }
    float3 wi;
    float dist, d2;
    if (!towards(c, x, &wi, &dist, &d2)) return false;
    float cos_x = dot3(n, wi);
    if (!(cos_x > 0.0f)) return false;
    e->contrib = Le * (mask * cos_x / d2);
    e->wi = wi;
    e->pos = c;
    e->nl = -wi;
    e->dist = dist;
    return true;
}

inline bool sphere_eval(const __global Light* l, float u, float v, float3 x, float3 n, LightEval* e)
{
    return sphere_emit(sphere_light(l), light_radiance(l), 1.0f, u, v, x, n, e);
}

/* The cone (unit axis *w towards the centre, 1 - cos = *omc) that the soft-falloff disk of sp subtends at x, when
 * it is sampled by solid angle there (solid_angle.h); *dc: the distance to the centre. */
inline bool soft_disk_cone(const __global Light* l, SphereLight sp, float3 x, float3* w, float* dc, float* omc)
{
    float3 d = sp.centre - x;
    float dc2 = dot3(d, d), r2 = sp.radius * sp.radius;
    if (!(dc2 > 0.0f) || !sa_wanted(l, r2, dc2)) return false;
    *dc = sqrt(dc2);
    *w = d / *dc;
    float h = sqrt(dc2 + r2);  /* the distance to the rim */
    *omc = r2 / (h * (h + *dc));
    return *omc > 0.0f && finite_f(*omc);
}

/* The soft-falloff disk's sample (u, v) for (r0, r1) uniform in its cone, and its area density. The cone and the
 * concentric map are both radially symmetric: the map's angle is kept, and its radius, whose square is uniform,
 * picks 1 - cos in the cone; then the point's radius on the disk scales the (u, v) about the centre, which the map
 * takes to the same scale of the point (no transcendental: they cost PoCL far more than the rest here). */
inline float2 soft_disk_sample(SphereLight sp, float dc, float omc, float r0, float r1, float* pdf)
{
    float a = 2.0f * r0 - 1.0f, b = 2.0f * r1 - 1.0f;
    float rad = fmax_f(abs_f(a), abs_f(b));  /* the concentric map's radius */
    float omc_t = rad * rad * omc;
    float cos_t = 1.0f - omc_t, sin_t = sqrt(fmax_f(0.0f, omc_t * (2.0f - omc_t)));
    float rho = fmin_f(dc * sin_t / (cos_t * sp.radius), 1.0f);  /* the point's distance from the centre, in radii */
    float k = rad > 0.0f ? rho / rad : 0.0f;
    /* cos_l = cos_t at distance dc / cos_t */
    *pdf = cos_t * cos_t * cos_t / (dc * dc * 2.0f * RESTIRCL_PI * omc);
    return (float2)(clamp_f(0.5f + 0.5f * k * a, 0.0f, 0.99999994f), clamp_f(0.5f + 0.5f * k * b, 0.0f, 0.99999994f));
}

/* The area density of a point at distance dist seen under cos_l, drawn uniformly in a cone of 1 - cos = omc. */
inline float cone_area_pdf(float cos_l, float dist, float omc)
{
    return cos_l > 0.0f ? cos_l / (dist * dist * 2.0f * RESTIRCL_PI * omc) : 0.0f;
}

/* Uniform in (u, v) for points, soft-falloff disks and shading points inside the sphere; from outside (touching
 * included: area sampling there weighs a point by 1 / d^2, unbounded where a receiver touches the sphere), uniform in
 * the solid angle of the visible cap, with *pdf converted to the sphere's area measure at the point that (u, v) maps
 * back to, which sphere_eval evaluates: the weight contribution / pdf is then Le cos_x 2 pi omc however close to the
 * cap's rim (cos_l -> 0) the point is. */
inline float2 sphere_sample(const __global Light* l, float3 x, float r0, float r1, float* pdf)
{
    SphereLight sp = sphere_light(l);
    float r = sp.radius;
    if (!(r > 0.0f)) { *pdf = 1.0f; return (float2)(r0, r1); }
    if (sp.soft_falloff) {
        float3 w;
        float dc, omc;
        if (soft_disk_cone(l, sp, x, &w, &dc, &omc)) return soft_disk_sample(sp, dc, omc, r0, r1, pdf);
        *pdf = 1.0f / (RESTIRCL_PI * r * r);
        return (float2)(r0, r1);
    }
    float3 d = sp.centre - x;
    float dc2 = dot3(d, d);
    float r2 = r * r;
    if (!(dc2 > r2)) {  /* inside: uniform over the sphere's area */
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
    float2 uv = sphere_uv(norm3(ny));
    ny = sphere_dir(uv.x, uv.y);  /* the point sphere_eval will evaluate, and its density as area_contrib sees it */
    float3 wi;
    float dist, d2;
    *pdf = towards(sp.centre + r * ny, x, &wi, &dist, &d2) ? cone_area_pdf(-dot3(ny, wi), dist, omc) : 0.0f;
    return uv;
}

/* The sample (u, v) of l that the ray x + t wi (t > 0) hits: the nearer point of the sphere, or, with soft
 * falloff, a point of the disk facing x. False for a miss and for points (radius 0: a delta no ray hits). */
inline bool sphere_hit(const __global Light* l, float3 x, float3 wi, float2* uv)
{
    SphereLight sp = sphere_light(l);
    float r = sp.radius;
    if (!(r > 0.0f)) return false;
    float3 oc = sp.centre - x;
    float b = dot3(oc, wi);
    float3 perp = oc - b * wi;  /* the discriminant from the ray's closest approach: no cancellation far away */
    float perp2 = dot3(perp, perp);
    if (sp.soft_falloff) {
        /* Every point of the disk lies within r of the centre, so a line passing farther misses it: most of the
         * lights a BSDF ray is tested against end here, before the disk's frame is built. The margin (a bound of
         * both tests' float32 error, relative to r and to the magnitudes in the sums) keeps this test from
         * rejecting a ray the exact test below accepts. */
        float mag = max_abs3(x) + max_abs3(sp.centre) + 2.0f * max_abs3(oc);
        if (perp2 > 1.002f * (r * r) + 1e-9f * (mag * mag)) return false;
        float dc = len3(oc);
        if (!(dc > 0.0f)) return false;
        float3 w = oc / dc;
        float cw = dot3(wi, w);
        if (!(cw > 0.0f)) return false;
        float3 q = x + (dc / cw) * wi - sp.centre;
        float3 s, t;
        light_onb(w, &s, &t);
        float2 ab = (float2)(dot3(q, s), dot3(q, t)) / r;
        if (!(ab.x * ab.x + ab.y * ab.y <= 1.0f)) return false;
        *uv = concentric_disk_inverse(ab);
        return true;
    }
    float disc = r * r - perp2;
    if (!(disc >= 0.0f)) return false;
    float h = sqrt(disc);
    float t = b - h > 0.0f ? b - h : b + h;
    if (!(t > 0.0f)) return false;
    *uv = sphere_uv(norm3(x + t * wi - sp.centre));
    return true;
}

/* The density in area of sphere_sample producing the evaluated point e (its normal e->nl, outward) from x. */
inline float sphere_point_pdf(const __global Light* l, float3 x, const LightEval* e)
{
    SphereLight sp = sphere_light(l);
    float r = sp.radius;
    if (!(r > 0.0f)) return 0.0f;
    if (sp.soft_falloff) {
        float3 w;
        float dc, omc;
        if (!soft_disk_cone(l, sp, x, &w, &dc, &omc)) return 1.0f / (RESTIRCL_PI * r * r);
        return cone_area_pdf(-dot3(e->nl, e->wi), e->dist, omc);
    }
    float3 d = sp.centre - x;
    float dc2 = dot3(d, d), r2 = r * r;
    if (!(dc2 > r2)) return 1.0f / (4.0f * RESTIRCL_PI * r2);
    float sin2max = r2 / dc2;
    float omc = sin2max / (1.0f + sqrt(fmax_f(0.0f, 1.0f - sin2max)));
    return cone_area_pdf(-dot3(e->nl, e->wi), e->dist, omc);
}

/* A point (radius 0) is a delta no ray meets. The host's half of this rule is python/restircl/lights/sphere.py
 * has_shape (which lights the camera sees). */
inline bool sphere_hittable(const __global Light* l) { return sphere_light(l).radius > 0.0f; }

/* The surface's radiance, uniform (Blender draws the sphere so out to its silhouette). */
inline float3 sphere_hit_radiance(const __global Light* l, float3 x, float2 uv)
{
    (void)x;
    (void)uv;
    return light_radiance(l);
}

#endif
