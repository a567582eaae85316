/* Uniform sampling of the solid angle a rectangle subtends (Urena, Fajardo and King, "An area-preserving
 * parametrization for spherical rectangles", EGSR 2013). The rectangle is corner + s eu + t ev, s, t in [0, 1], eu
 * and ev orthogonal. In the rectangle's frame (x along eu, y along ev, z away from the shading point's side) the
 * rectangle spans [x0, x1] x [y0, y1] at height z0 < 0. Each interior angle is pi/2 - theta_i, and the four theta_i
 * are summed as the arguments of unit complex numbers (cos theta_i, sin theta_i), both parts from exact closed
 * forms: S = -sum theta_i needs one atan2 and has no cancellation against 2 pi for small or far rectangles, and no
 * cos near 0 is lost when the shading point grazes the plane. (The map needs one atan2, one sin and one cos:
 * trig.h.) */
#ifndef RESTIRCL_LIGHTS_SPHERICAL_RECT_H
#define RESTIRCL_LIGHTS_SPHERICAL_RECT_H

#include "lights/trig.h"
#include "sampling/warps.h"

/* complex product and length of float2s */
inline float2 cmul(float2 a, float2 b) { return (float2)(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

inline float len2(float2 a) { return sqrt(a.x * a.x + a.y * a.y); }

typedef struct {
    float3 ex, ey, ez;   /* the rectangle's frame, ez pointing from the plane away from the shading point's side */
    float lu, lv;        /* edge lengths */
    float x0, x1, y0, y1, z0;
    float b0, b1;        /* z of the normals of the planes through the shading point and the edges y = y0, y = y1 */
    float cos_phi0, sin_phi0;  /* the first angle of the sweep (less pi): theta_2 + theta_3 */
    float S;             /* solid angle */
} SphRect;

/* The spherical rectangle of (corner, eu, ev) seen from x; false when x lies on its plane. */
inline bool sph_rect_setup(float3 corner, float3 eu, float3 ev, float3 x, SphRect* r)
{
    r->lu = len3(eu);
    r->lv = len3(ev);
    if (!(r->lu > 0.0f) || !(r->lv > 0.0f)) return false;
    r->ex = eu / r->lu;
    r->ey = ev / r->lv;
    r->ez = cross3(r->ex, r->ey);
    float3 d = corner - x;
    float z0 = dot3(d, r->ez);
    if (z0 > 0.0f) { r->ez = -r->ez; z0 = -z0; }
    if (!(z0 < 0.0f)) return false;
    float x0 = dot3(d, r->ex), y0 = dot3(d, r->ey);
    float x1 = x0 + r->lu, y1 = y0 + r->lv;
    float z2 = z0 * z0, az = -z0;
    /* lengths of the (unnormalised) normals of the planes through x and each edge: (0, z0, -y0), (-z0, 0, x1),
     * (0, -z0, y1), (z0, 0, -x0); sin theta_i = -n_i.n_j (normalised), cos theta_i = |z0| |corner| / (m_i m_j) */
    float m0 = sqrt(z2 + y0 * y0), m1 = sqrt(z2 + x1 * x1), m2 = sqrt(z2 + y1 * y1), m3 = sqrt(z2 + x0 * x0);
    float d00 = sqrt(z2 + x0 * x0 + y0 * y0), d10 = sqrt(z2 + x1 * x1 + y0 * y0);
    float d11 = sqrt(z2 + x1 * x1 + y1 * y1), d01 = sqrt(z2 + x0 * x0 + y1 * y1);
    float k01 = 1.0f / (m0 * m1), k12 = 1.0f / (m1 * m2), k23 = 1.0f / (m2 * m3), k30 = 1.0f / (m3 * m0);
    float2 w0 = (float2)(az * d10 * k01, x1 * y0 * k01), w1 = (float2)(az * d11 * k12, -x1 * y1 * k12);
    float2 w2 = (float2)(az * d01 * k23, x0 * y1 * k23), w3 = (float2)(az * d00 * k30, -x0 * y0 * k30);
    float2 q23 = cmul(w2, w3);
    float2 all = cmul(cmul(w0, w1), q23);
    float S = atan2_f(-all.y, all.x);
    r->S = S > 0.0f ? S : S + 2.0f * RESTIRCL_PI;  /* over pi: a shading point close to the plane */
    float lq = len2(q23);
    r->cos_phi0 = q23.x / lq;
    r->sin_phi0 = q23.y / lq;
    r->b0 = -y0 / m0;
    r->b1 = y1 / m2;
    r->x0 = x0; r->x1 = x1; r->y0 = y0; r->y1 = y1; r->z0 = z0;
    return r->S > 0.0f;
}

/* The point of the rectangle for (u, v) in [0,1)^2, uniform in solid angle, as rectangle coordinates (s, t) in
 * [0, 1]^2 (point = corner + s eu + t ev). */
inline float2 sph_rect_sample(const SphRect* r, float u, float v)
{
    /* the sweep angle au = pi + phi: cos(au) = -cos(phi), sin(au) = -sin(phi), phi small for small rectangles */
    float2 sc = sincos_f(u * r->S);
    float su = sc.x, cu_s = sc.y;
    float sp = r->sin_phi0 * cu_s + r->cos_phi0 * su, cp = r->cos_phi0 * cu_s - r->sin_phi0 * su;
    float fu = (cp * r->b0 + r->b1) / sp;
    float cu = (fu >= 0.0f ? 1.0f : -1.0f) * rsqrt(fu * fu + r->b0 * r->b0);
    cu = clamp_f(cu, -1.0f, 1.0f);
    float xu = -(cu * r->z0) * rsqrt(fmax_f(1.0f - cu * cu, 1e-30f));
    xu = clamp_f(xu, r->x0, r->x1);
    if (!finite_f(xu)) xu = r->x0;
    float d2 = xu * xu + r->z0 * r->z0;
    float h0 = r->y0 * rsqrt(d2 + r->y0 * r->y0), h1 = r->y1 * rsqrt(d2 + r->y1 * r->y1);
    float hv = h0 + v * (h1 - h0), hv2 = hv * hv;
    float yv = hv2 < 1.0f - 1e-6f ? hv * sqrt(d2) * rsqrt(1.0f - hv2) : r->y1;
    yv = clamp_f(yv, r->y0, r->y1);
    return (float2)(clamp_f((xu - r->x0) / r->lu, 0.0f, 0.99999994f),
                    clamp_f((yv - r->y0) / r->lv, 0.0f, 0.99999994f));
}

#endif
