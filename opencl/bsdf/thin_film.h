/* Thin-film interference (iridescence): the Fresnel reflectance, per rgb channel, of a surface under a dielectric film
 * of thickness d (nm) and IOR n_f, seen from a medium of IOR 1 at cosine ci, as Cycles 4.2+ has it on the Principled,
 * Glass and Metallic BSDFs (Thin Film Thickness and IOR). Belcour and Barla 2017 ("A practical extension to
 * microfacet theory for the modeling of varying iridescence"): per polarisation (s, p), the light reflected at the
 * top (R12) and the light that went through the film and back any number of times interfere; summed in closed form
 * over the bounces (Airy), the reflectance at one wavelength is
 *     R = R12 + Rs + 2 sum_{m >= 1} C_m cos(m (2 pi OPD / lambda + phi)),
 *     Rs = (1 - R12)^2 R23 / (1 - R12 R23),  C_m = (Rs - (1 - R12)) (R12 R23)^(m/2),
 * OPD = 2 n_f d cos(theta in the film), phi the phase shifts of reflection (film -> substrate, and film -> top seen
 * from inside). A channel's value integrates that against its colour matching function: the constant terms stay,
 * each cosine becomes a sample of the channel's spectral sensitivity S_c at m OPD (the Fourier transform of the
 * matching function, upload/thin_film_table.py), read from a table; the series stops at m = 3, as Cycles does.
 * The average of s and p is the reflectance, clamped to [0, 1]; total internal reflection at either interface is 1.
 *
 * The substrate is a dielectric of IOR eta (the Glass BSDF, the Principled's specular and transmission), or a metal:
 * Cycles' F82-tint metal, whose complex IOR n + ik per channel it estimates from f0 and its value g at 82 degrees
 * (Gulbrandsen 2014, "Artist friendly metallic Fresnel"), the film then changing the metal's reflectance through the
 * phase of that complex IOR while the magnitude of its reflection stays the F82 curve (with f0 taken relative to the
 * film). Films thinner than 1 nm blend their IOR towards the outer medium's (no film at thickness 0), and a thickness
 * of at most THIN_FILM_CUTOFF is no film: the resolves leave the film out there altogether. */
#ifndef RESTIRCL_BSDF_THIN_FILM_H
#define RESTIRCL_BSDF_THIN_FILM_H

#include "bsdf/fresnel.h"
#include "bsdf/thin_film_table.h"

/* the sensitivities S_c(opd) of the three channels: *re, *im */
inline void thin_film_sensitivity(float opd, float3* re, float3* im)
{
    float p = clamp_f(opd * (1.0f / THIN_FILM_OPD_MAX), 0.0f, 1.0f) * (float)(THIN_FILM_SIZE - 1);
    int i = min((int)p, THIN_FILM_SIZE - 2);
    float t = p - (float)i;
    float v[6];
    for (int row = 0; row < 6; ++row) {
        __constant const float* r = THIN_FILM_TABLE + row * THIN_FILM_SIZE + i;
        v[row] = r[0] + (r[1] - r[0]) * t;
    }
    *re = (float3)(v[0], v[1], v[2]);
    *im = (float3)(v[3], v[4], v[5]);
}

/* Light meeting a dielectric interface at cosine ci > 0, the far side eta times denser: the reflectances (s, p)
 * returned, the signs of the reflected amplitudes in *sign (+1 or -1: the phase shift 0 or pi) and the cosine of
 * the refracted direction (> 0) in *ct; (1, 1) for total internal reflection (*sign and *ct then unset). */
inline float2 thin_film_interface(float ci, float eta, float2* sign, float* ct)
{
    float st2 = (1.0f - ci * ci) / (eta * eta);
    if (st2 >= 1.0f) return (float2)(1.0f);
    float c = sqrt(1.0f - st2);
    float rs = (ci - eta * c) / (ci + eta * c);
    float rp = (eta * ci - c) / (eta * ci + c);
    *sign = (float2)(rs >= 0.0f ? 1.0f : -1.0f, rp >= 0.0f ? 1.0f : -1.0f);
    *ct = c;
    return (float2)(rs * rs, rp * rp);
}

/* One polarisation's reflectance per channel: the Airy series to m = 3 with top reflectance r12, bottom
 * reflectance r23 (per channel) and the round trip's phase shift exp(i phi) = (ph_re, ph_im) (per channel), the
 * sensitivities at m OPD in s_re[m - 1], s_im[m - 1]. */
inline float3 thin_film_airy(float r12, float3 r23, float3 ph_re, float3 ph_im, const float3* s_re,
                             const float3* s_im)
{
    float t121 = 1.0f - r12;
    float3 r123 = r12 * r23;
    float3 amp = sqrt(r123);
    float3 rs = t121 * t121 * r23 / ((float3)(1.0f) - r123);
    float3 out = (float3)(r12) + rs;
    float3 c = rs - (float3)(t121);
    float3 a_re = ph_re, a_im = ph_im;  /* exp(i m phi) */
    for (int m = 0; m < 3; ++m) {
        c *= amp;
        out += 2.0f * c * (a_re * s_re[m] + a_im * s_im[m]);
        float3 re = a_re * ph_re - a_im * ph_im;
        a_im = a_re * ph_im + a_im * ph_re;
        a_re = re;
    }
    return out;
}

/* the sensitivities at 1, 2 and 3 times opd */
inline void thin_film_orders(float opd, float3* s_re, float3* s_im)
{
    for (int m = 0; m < 3; ++m) thin_film_sensitivity((float)(m + 1) * opd, &s_re[m], &s_im[m]);
}

/* The film's IOR as the series sees it: blended towards the outer medium's (1) below 1 nm */
inline float thin_film_ior(float d, float n_f)
{
    if (d >= 1.0f) return n_f;
    float t = clamp_f(d, 0.0f, 1.0f);
    return 1.0f + (n_f - 1.0f) * (t * t * (3.0f - 2.0f * t));
}

/* Reflectance (rgb) at cosine ci of a dielectric of relative IOR eta under a film of thickness d and IOR n_f */
inline float3 thin_film_dielectric(float ci, float eta, float d, float n_f)
{
    n_f = thin_film_ior(d, n_f);
    float2 sign12, sign23;
    float c2, c3;
    float2 r12 = thin_film_interface(clamp_f(ci, 0.0f, 1.0f), n_f, &sign12, &c2);
    if (r12.x >= 1.0f && r12.y >= 1.0f) return (float3)(1.0f);
    float2 r23 = thin_film_interface(c2, eta / n_f, &sign23, &c3);
    if (r23.x >= 1.0f && r23.y >= 1.0f) return (float3)(1.0f);
    float3 s_re[3], s_im[3];
    thin_film_orders(2.0f * n_f * d * c2, s_re, s_im);
    /* the round trip's phase: reflection at the substrate and, seen from inside, at the top (-r12) */
    float3 rs = thin_film_airy(r12.x, (float3)(r23.x), (float3)(-sign12.x * sign23.x), (float3)(0.0f), s_re, s_im);
    float3 rp = thin_film_airy(r12.y, (float3)(r23.y), (float3)(-sign12.y * sign23.y), (float3)(0.0f), s_re, s_im);
    return saturate3(0.5f * (rs + rp));
}

/* b of the F82 curve (bsdf/fresnel.h fresnel_f82) through f0 with the value g at cos = 1/7 */
inline float3 thin_film_f82_b(float3 f0, float3 g)
{
    const float m = 6.0f / 7.0f;
    float m5 = sqr_f(sqr_f(m)) * m;
    return (mix3(f0, (float3)(1.0f), m5) - g) * (7.0f / (m5 * m));
}

/* The complex IOR n + ik (per channel) of Cycles' F82-tint metal of f0 (clamped Base Color) and 82-degree value g
 * (Gulbrandsen: f0 = F0 of n + ik; g blends n between its two extremes): n returned, k in *k. It depends on the
 * metal only, so a lobe computes it once, when it is resolved (bsdf/thin_film_reflection.h). */
inline float3 thin_film_metal_ior(float3 f0, float3 g, float3* k)
{
    float3 r = fmin(f0, (float3)(0.999f));
    float3 sr = sqrt(r);
    float3 n_max = ((float3)(1.0f) + sr) / ((float3)(1.0f) - sr);
    float3 n = n_max + (((float3)(1.0f) - r) / ((float3)(1.0f) + r) - n_max) * g;
    *k = sqrt(fmax((r * (n + 1.0f) * (n + 1.0f) - (n - 1.0f) * (n - 1.0f)) / ((float3)(1.0f) - r), (float3)(0.0f)));
    return n;
}

/* Reflectance (rgb) at cosine ci of that metal, of complex IOR n + ik and 82-degree value g, under a film of
 * thickness d and IOR n_f */
inline float3 thin_film_metal_nk(float ci, float3 n, float3 k, float3 g, float d, float n_f)
{
    n_f = thin_film_ior(d, n_f);
    float2 sign12;
    float c2;
    float2 r12 = thin_film_interface(clamp_f(ci, 0.0f, 1.0f), n_f, &sign12, &c2);
    if (r12.x >= 1.0f && r12.y >= 1.0f) return (float3)(1.0f);
    /* light in the film (IOR n_f) meeting the metal at c2: sqrt(N^2 - n_f^2 sin^2) = u + iv */
    float e = n_f, ec = e * c2;
    float3 nk2 = 2.0f * n * k, n2k2 = n * n - k * k;
    float3 t1 = n2k2 - (float3)(e * e * (1.0f - c2 * c2));
    float3 t2 = sqrt(t1 * t1 + nk2 * nk2);
    float3 u2 = fmax(0.5f * (t2 + t1), (float3)(0.0f)), v2 = fmax(0.5f * (t2 - t1), (float3)(0.0f));
    float3 u = sqrt(u2), v = sqrt(v2);
    /* the phases of the reflected amplitudes: arg((ec - w)(ec + conj w)) for s, the same with N^2 for p */
    float3 s_re = (float3)(ec * ec) - u2 - v2, s_im = -2.0f * ec * v;
    float3 p_re = (n * n + k * k) * (n * n + k * k) * (c2 * c2) - e * e * (u2 + v2);
    float3 p_im = 2.0f * ec * (nk2 * u - n2k2 * v);
    float3 s_len = sqrt(s_re * s_re + s_im * s_im), p_len = sqrt(p_re * p_re + p_im * p_im);
    s_re = select(s_re / s_len, (float3)(1.0f), isequal(s_len, (float3)(0.0f)));
    s_im = select(s_im / s_len, (float3)(0.0f), isequal(s_len, (float3)(0.0f)));
    p_re = select(p_re / p_len, (float3)(1.0f), isequal(p_len, (float3)(0.0f)));
    p_im = select(p_im / p_len, (float3)(0.0f), isequal(p_len, (float3)(0.0f)));
    /* the magnitude: the F82 curve, f0 of n + ik relative to the film, through the same g */
    float3 nr = n / e, kr = k / e;
    float3 f0r = ((nr - 1.0f) * (nr - 1.0f) + kr * kr) / ((nr + 1.0f) * (nr + 1.0f) + kr * kr);
    float3 r23 = fresnel_f82(c2, f0r, thin_film_f82_b(f0r, g));
    float3 o_re[3], o_im[3];
    thin_film_orders(2.0f * n_f * d * c2, o_re, o_im);
    float3 rs = thin_film_airy(r12.x, r23, -sign12.x * s_re, -sign12.x * s_im, o_re, o_im);
    float3 rp = thin_film_airy(r12.y, r23, -sign12.y * p_re, -sign12.y * p_im, o_re, o_im);
    return saturate3(0.5f * (rs + rp));
}

/* Reflectance (rgb) at cosine ci of Cycles' F82-tint metal of f0 (clamped Base Color) and 82-degree value g under a
 * film of thickness d and IOR n_f */
inline float3 thin_film_metal(float ci, float3 f0, float3 g, float d, float n_f)
{
    float3 k;
    float3 n = thin_film_metal_ior(f0, g, &k);
    return thin_film_metal_nk(ci, n, k, g, d, n_f);
}

/* The Principled and Glass BSDFs' specular with a film: the film's reflectance over a dielectric of relative IOR
 * eta, then each channel scaled towards f0_c / F0(eta) (Specular IOR Level and Specular Tint) the more, the nearer
 * it is to F0(eta) (at 1 it stays 1), as Cycles scales it */
inline float3 thin_film_specular(float ci, float eta, float3 f0, float d, float n_f)
{
    float3 F = thin_film_dielectric(ci, eta, d, n_f);
    float f0_eta = f0_from_ior(eta);
    if (f0_eta > 1e-5f && !(F.x == 1.0f && F.y == 1.0f && F.z == 1.0f)) {
        float3 s = saturate3((F - (float3)(1.0f)) / (f0_eta - 1.0f));
        F *= (float3)(1.0f) + (f0 / f0_eta - (float3)(1.0f)) * s;
    }
    return F;
}

#endif
