/* The converter nodes of PBR node graphs (textures/nodes.h runs them): Separate / Combine Color in RGB, HSV and HSL,
 * Math and Vector Math, Invert, and the Mix blend modes beyond the nine of tex_mix. Each follows the definition
 * Blender's manual gives for the node; where an operation has no value (a division by zero, the root of a negative
 * number) the result is 0, as Blender's "safe" operations give. */
#ifndef RESTIRCL_TEXTURE_CONVERTERS_H
#define RESTIRCL_TEXTURE_CONVERTERS_H

inline float tex_safe_div(float a, float b) { return b != 0.0f ? a / b : 0.0f; }

/* the hue in [0, 1) of an rgb triple whose largest and smallest components are hi and lo (hi > lo) */
inline float tex_hue(float3 c, float hi, float lo)
{
    float d = hi - lo, h;
    if (c.x == hi) h = (c.y - c.z) / d;
    else if (c.y == hi) h = 2.0f + (c.z - c.x) / d;
    else h = 4.0f + (c.x - c.y) / d;
    h *= 1.0f / 6.0f;
    return h < 0.0f ? h + 1.0f : h;
}

inline float3 tex_rgb_to_hsv(float3 c)
{
    float hi = fmax_f(c.x, fmax_f(c.y, c.z)), lo = fmin_f(c.x, fmin_f(c.y, c.z));
    float s = hi != 0.0f ? (hi - lo) / hi : 0.0f;
    return (float3)(s != 0.0f ? tex_hue(c, hi, lo) : 0.0f, s, hi);
}

/* the rgb of hue h (any real: its fraction is used) at full saturation and value */
inline float3 tex_hue_rgb(float h)
{
    h = 6.0f * (h - floor(h));
    float r = clamp_f(fabs(h - 3.0f) - 1.0f, 0.0f, 1.0f);
    float g = clamp_f(2.0f - fabs(h - 2.0f), 0.0f, 1.0f);
    float b = clamp_f(2.0f - fabs(h - 4.0f), 0.0f, 1.0f);
    return (float3)(r, g, b);
}

inline float3 tex_hsv_to_rgb(float3 hsv)
{
    return hsv.z * (1.0f + hsv.y * (tex_hue_rgb(hsv.x) - 1.0f));
}

inline float3 tex_rgb_to_hsl(float3 c)
{
    float hi = fmax_f(c.x, fmax_f(c.y, c.z)), lo = fmin_f(c.x, fmin_f(c.y, c.z));
    float l = 0.5f * (hi + lo);
    if (hi == lo) return (float3)(0.0f, 0.0f, l);
    float d = hi - lo;
    float s = l > 0.5f ? d / (2.0f - hi - lo) : d / (hi + lo);
    return (float3)(tex_hue(c, hi, lo), s, l);
}

inline float3 tex_hsl_to_rgb(float3 hsl)
{
    float chroma = (1.0f - fabs(2.0f * hsl.z - 1.0f)) * hsl.y;
    return hsl.z + chroma * (tex_hue_rgb(hsl.x) - 0.5f);
}

/* Hue/Saturation/Value: c turned by hsv.x - 0.5 in hue, its saturation scaled by hsv.y (clamped to [0, 1]) and its
 * value by hsv.z, blended with c by t and clamped at 0 (an oversaturated colour can go negative) */
inline float3 tex_hsv_adjust(float3 c, float3 hsv, float t)
{
    float3 h = tex_rgb_to_hsv(c);
    h.x += hsv.x + 0.5f;
    h.x -= floor(h.x);
    h.y = clamp_f(h.y * hsv.y, 0.0f, 1.0f);
    h.z *= hsv.z;
    return fmax(c + t * (tex_hsv_to_rgb(h) - c), (float3)(0.0f));
}

/* Separate Color: channel k of c in mode (TEXCOLOR_*) */
inline float tex_separate(int mode, int k, float3 c)
{
    if (mode == TEXCOLOR_HSV) c = tex_rgb_to_hsv(c);
    if (mode == TEXCOLOR_HSL) c = tex_rgb_to_hsl(c);
    return k == 0 ? c.x : (k == 1 ? c.y : c.z);
}

inline float3 tex_combine(int mode, float3 c)
{
    if (mode == TEXCOLOR_HSV) return tex_hsv_to_rgb(c);
    if (mode == TEXCOLOR_HSL) return tex_hsl_to_rgb(c);
    return c;
}

inline float tex_math(int op, float a, float b, float c)
{
    switch (op) {
    case TEXMATH_ADD: return a + b;
    case TEXMATH_SUBTRACT: return a - b;
    case TEXMATH_MULTIPLY: return a * b;
    case TEXMATH_DIVIDE: return tex_safe_div(a, b);
    case TEXMATH_MULTIPLY_ADD: return a * b + c;
    case TEXMATH_POWER: return (a < 0.0f && b != floor(b)) ? 0.0f : pow(a, b);
    case TEXMATH_LOGARITHM: return (a > 0.0f && b > 0.0f) ? tex_safe_div(log(a), log(b)) : 0.0f;
    case TEXMATH_SQRT: return a > 0.0f ? sqrt(a) : 0.0f;
    case TEXMATH_INVERSE_SQRT: return a > 0.0f ? 1.0f / sqrt(a) : 0.0f;
    case TEXMATH_ABSOLUTE: return fabs(a);
    case TEXMATH_EXPONENT: return exp(a);
    case TEXMATH_MINIMUM: return fmin_f(a, b);
    case TEXMATH_MAXIMUM: return fmax_f(a, b);
    case TEXMATH_LESS_THAN: return a < b ? 1.0f : 0.0f;
    case TEXMATH_GREATER_THAN: return a > b ? 1.0f : 0.0f;
    case TEXMATH_SIGN: return a > 0.0f ? 1.0f : (a < 0.0f ? -1.0f : 0.0f);
    case TEXMATH_COMPARE: return fabs(a - b) <= fmax_f(c, 1e-5f) ? 1.0f : 0.0f;
    case TEXMATH_ROUND: return floor(a + 0.5f);
    case TEXMATH_FLOOR: return floor(a);
    case TEXMATH_CEIL: return ceil(a);
    case TEXMATH_TRUNC: return a >= 0.0f ? floor(a) : ceil(a);
    case TEXMATH_FRACT: return a - floor(a);
    case TEXMATH_MODULO: return b != 0.0f ? fmod(a, b) : 0.0f;
    case TEXMATH_FLOORED_MODULO: return b != 0.0f ? a - floor(a / b) * b : 0.0f;
    case TEXMATH_SNAP: return b != 0.0f ? floor(a / b) * b : 0.0f;
    case TEXMATH_SINE: return sin(a);
    case TEXMATH_COSINE: return cos(a);
    case TEXMATH_TANGENT: return tan(a);
    case TEXMATH_ARCTAN2: return atan2(a, b);
    case TEXMATH_RADIANS: return a * (M_PI_F / 180.0f);
    case TEXMATH_DEGREES: return a * (180.0f / M_PI_F);
    default: return 0.0f;
    }
}

/* Vector Math on a, b (s: Scale); the operations that give a number return it in every component */
inline float3 tex_vector_math(int op, float3 a, float3 b, float s)
{
    switch (op) {
    case TEXVEC_ADD: return a + b;
    case TEXVEC_SUBTRACT: return a - b;
    case TEXVEC_MULTIPLY: return a * b;
    case TEXVEC_DIVIDE: return (float3)(tex_safe_div(a.x, b.x), tex_safe_div(a.y, b.y), tex_safe_div(a.z, b.z));
    case TEXVEC_SCALE: return a * s;
    case TEXVEC_ABSOLUTE: return fabs(a);
    case TEXVEC_MINIMUM: return (float3)(fmin_f(a.x, b.x), fmin_f(a.y, b.y), fmin_f(a.z, b.z));
    case TEXVEC_MAXIMUM: return (float3)(fmax_f(a.x, b.x), fmax_f(a.y, b.y), fmax_f(a.z, b.z));
    case TEXVEC_FLOOR: return floor(a);
    case TEXVEC_CEIL: return ceil(a);
    case TEXVEC_FRACTION: return a - floor(a);
    case TEXVEC_NORMALIZE: {
        float l = sqrt(dot3(a, a));
        return l > 0.0f ? a / l : (float3)(0.0f);
    }
    case TEXVEC_CROSS_PRODUCT: return cross3(a, b);
    case TEXVEC_DOT_PRODUCT: return (float3)(dot3(a, b));
    case TEXVEC_LENGTH: return (float3)(sqrt(dot3(a, a)));
    case TEXVEC_DISTANCE: return (float3)(sqrt(dot3(a - b, a - b)));
    default: return (float3)(0.0f);
    }
}

inline float tex_burn(float t, float a, float b)
{
    float d = 1.0f - t + t * b;
    return d <= 0.0f ? 0.0f : clamp_f(1.0f - (1.0f - a) / d, 0.0f, 1.0f);
}

inline float tex_dodge(float t, float a, float b)
{
    if (a == 0.0f) return 0.0f;
    float d = 1.0f - t * b;
    return d <= 0.0f ? 1.0f : fmin_f(a / d, 1.0f);
}

/* the blend modes of Blender's Mix (Color) that tex_mix leaves to this function; a and b as in tex_mix */
inline float3 tex_mix_more(int blend, float t, float3 a, float3 b)
{
    float tm = 1.0f - t;
    switch (blend) {
    case TEXMIX_BURN: return (float3)(tex_burn(t, a.x, b.x), tex_burn(t, a.y, b.y), tex_burn(t, a.z, b.z));
    case TEXMIX_DODGE: return (float3)(tex_dodge(t, a.x, b.x), tex_dodge(t, a.y, b.y), tex_dodge(t, a.z, b.z));
    case TEXMIX_DIVIDE:
        return (float3)(b.x != 0.0f ? tm * a.x + t * a.x / b.x : a.x, b.y != 0.0f ? tm * a.y + t * a.y / b.y : a.y,
                        b.z != 0.0f ? tm * a.z + t * a.z / b.z : a.z);
    case TEXMIX_SOFT_LIGHT: {
        float3 screen = 1.0f - (1.0f - b) * (1.0f - a);
        return tm * a + t * ((1.0f - a) * b * a + a * screen);
    }
    case TEXMIX_LINEAR_LIGHT: return a + t * (2.0f * b - 1.0f);
    case TEXMIX_EXCLUSION: return fmax(a + t * (b - 2.0f * a * b), (float3)(0.0f));
    default: break;
    }
    float3 ha = tex_rgb_to_hsv(a), hb = tex_rgb_to_hsv(b);
    switch (blend) {
    case TEXMIX_HUE:
        if (hb.y == 0.0f) return a;
        return a + t * (tex_hsv_to_rgb((float3)(hb.x, ha.y, ha.z)) - a);
    case TEXMIX_SATURATION:
        if (ha.y == 0.0f) return a;
        return tex_hsv_to_rgb((float3)(ha.x, tm * ha.y + t * hb.y, ha.z));
    case TEXMIX_VALUE: return tex_hsv_to_rgb((float3)(ha.x, ha.y, tm * ha.z + t * hb.z));
    case TEXMIX_COLOR:
        if (hb.y == 0.0f) return a;
        return a + t * (tex_hsv_to_rgb((float3)(hb.x, hb.y, ha.z)) - a);
    default: return b;
    }
}

#endif
