/* Fresnel terms of the Principled BSDF (Cycles 4.x/5.0's model): the unpolarised dielectric Fresnel, the Specular
 * IOR Level's remapping of F0, the F82-tint metal Fresnel, and the hemispherical averages (F_ss) that the
 * multiscatter energy compensation needs. */
#ifndef RESTIRCL_BSDF_FRESNEL_H
#define RESTIRCL_BSDF_FRESNEL_H

inline float sqr_f(float x) { return x * x; }

inline float3 mix3(float3 a, float3 b, float t) { return a + (b - a) * t; }

inline float3 saturate3(float3 c) { return (float3)(clamp_f(c.x, 0.0f, 1.0f), clamp_f(c.y, 0.0f, 1.0f),
                                                    clamp_f(c.z, 0.0f, 1.0f)); }

inline float max3_f(float3 c) { return fmax_f(c.x, fmax_f(c.y, c.z)); }

inline float f0_from_ior(float eta) { return sqr_f((eta - 1.0f) / (eta + 1.0f)); }

/* the IOR whose F0 is f0 (f0 clamped below 0.99: finite) */
inline float ior_from_f0(float f0)
{
    float r = sqrt(clamp_f(f0, 0.0f, 0.99f));
    return (1.0f + r) / (1.0f - r);
}

/* Reflectance of a dielectric interface of relative IOR eta >= 1 seen from outside at cosine cos_i (unpolarised;
 * 1 for total internal reflection, which eta >= 1 never has). */
inline float fresnel_dielectric(float cos_i, float eta)
{
    float c = abs_f(cos_i);
    float g2 = eta * eta - 1.0f + c * c;
    if (g2 <= 0.0f) return 1.0f;
    float g = sqrt(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    return 0.5f * a * a * (1.0f + b * b);
}

/* The Principled dielectric specular's Fresnel at cos_i: the real curve of eta, remapped from [F0(eta), 1] onto
 * [f0, 1], so that Specular Tint and the IOR level colour and scale it while keeping its shape. */
inline float3 fresnel_principled(float cos_i, float eta, float f0_eta, float3 f0)
{
    float s = f0_eta < 1.0f ? clamp_f((fresnel_dielectric(cos_i, eta) - f0_eta) / (1.0f - f0_eta), 0.0f, 1.0f)
                            : 1.0f;
    return mix3(f0, (float3)(1.0f), s);
}

/* The hemispherical average of fresnel_dielectric (a rational fit, Kulla and Conty 2017, for eta >= 1) */
inline float fresnel_dielectric_avg(float eta) { return (eta - 1.0f) / (4.08567f + 1.00071f * eta); }

/* F82-tint (Kutz et al., "Novel aspects of the Adobe Standard Material"): Schlick's curve from f0 minus
 * b cos (1 - cos)^6, with b chosen so that at cos = 1/7 (about 82 degrees) it is Schlick's value times the tint. */
inline float3 fresnel_f82(float cos_i, float3 f0, float3 b)
{
    float m = clamp_f(1.0f - cos_i, 0.0f, 1.0f);
    float m5 = sqr_f(sqr_f(m)) * m;
    return saturate3(mix3(f0, (float3)(1.0f), m5) - b * (cos_i * m5 * m));
}

inline float3 fresnel_f82_b(float3 f0, float3 tint)
{
    const float m = 6.0f / 7.0f;
    float m5 = sqr_f(sqr_f(m)) * m;
    return mix3(f0, (float3)(1.0f), m5) * (7.0f / (m5 * m)) * ((float3)(1.0f) - tint);
}

/* the hemispherical (cosine-weighted) average of fresnel_f82 without its clamp: closed form */
inline float3 fresnel_f82_avg(float3 f0, float3 b)
{
    return mix3(f0, (float3)(1.0f), 1.0f / 21.0f) - b * (1.0f / 126.0f);
}

#endif
