/* What a shading normal that is not the geometric one needs, as Cycles handles it (its kernel/closure/bsdf.h and
 * bsdf_util.h, Blender 4.x/5.0 with the material's Bump Map Correction on, the default):
 * - the diffuse part shades with the normal as given (smooth or normal-mapped), unbent;
 * - the specular lobes use it bent towards the geometric normal until the view's mirror image leaves the surface
 *   (shading_normal_guard), else a grazing view would reflect into the surface;
 * - under a normal map, light from behind the smooth normal it perturbs gives nothing, and the diffuse part is
 *   softened towards that normal's horizon by a GGX shadowing term (bump_shadowing; Conty Estevez et al., "A
 *   Microfacet-Based Shadowing Function to Solve the Bump Terminator Problem", Ray Tracing Gems 2019).
 * Unbent and unshadowed, a 48-degree normal map came out 7 % brighter than Cycles
 * (tests/blender/test_blender_textures.py). The G-buffer keeps the smooth normal of a normal-mapped pixel in
 * GSample.emission.w (normal_pack). */
#ifndef RESTIRCL_SHADING_NORMAL_H
#define RESTIRCL_SHADING_NORMAL_H

/* Bend a shading normal towards the geometric one until the mirror image of the view direction leaves the
 * surface (smooth normals near a silhouette, strong normal maps): else the view would reflect into the surface.
 * Bisection on the blend factor; the geometric normal itself always passes. */
inline float3 shading_normal_guard(float3 n, float3 ng, float3 wi)
{
    float cos_g = dot3(ng, wi);
    float eps = fmin_f(0.01f, 0.5f * cos_g);
    if (2.0f * dot3(n, wi) * dot3(n, ng) - cos_g >= eps) return n;
    float lo = 0.0f, hi = 1.0f;
    for (int k = 0; k < 12; ++k) {
        float mid = 0.5f * (lo + hi);
        float3 m = norm3(n + mid * (ng - n));
        if (2.0f * dot3(m, wi) * dot3(m, ng) - cos_g >= eps) hi = mid; else lo = mid;
    }
    float3 m = n + hi * (ng - n);
    return dot3(m, m) > 0.0f ? norm3(m) : ng;
}

/* The factor on a part's f for light from wi at a pixel whose normal n comes from a normal map over the smooth
 * normal nb: 0 where wi and n lie on different sides of the smooth surface than they should (light through the
 * surface), else 1 for a specular lobe and, for the diffuse part, GGX's G1 at wi's angle to nb with alpha^2 =
 * tan^2(n, nb) / 8 (Conty Estevez's choice): a bump tilted far from the surface is shadowed near its horizon. */
inline float bump_shadowing(float3 nb, float3 n, float3 wi, bool diffuse)
{
    float c_bi = dot3(nb, wi), c_bn = dot3(nb, n), c_ni = dot3(n, wi);
    if (c_bi * c_bn * c_ni < 0.0f) return 0.0f;
    if (!diffuse) return 1.0f;
    float ci = abs_f(c_bi), cd = abs_f(c_bn);
    if (cd >= 1.0f || ci >= 1.0f) return 1.0f;
    if (ci < 1e-6f) return 0.0f;
    float a2 = clamp_f(0.125f * (1.0f / (cd * cd) - 1.0f), 0.0f, 1.0f);
    return 2.0f / (1.0f + sqrt(1.0f + a2 * (1.0f / (ci * ci) - 1.0f)));
}

/* A unit vector in 32 bits (octahedral map, 16 bits per coordinate, codes 1 .. 65535: 0 stays free for "none"). */
inline int normal_pack(float3 n)
{
    float s = abs_f(n.x) + abs_f(n.y) + abs_f(n.z);
    float px = n.x / s, py = n.y / s;
    if (n.z < 0.0f) {
        float qx = (1.0f - abs_f(py)) * (px >= 0.0f ? 1.0f : -1.0f);
        py = (1.0f - abs_f(px)) * (py >= 0.0f ? 1.0f : -1.0f);
        px = qx;
    }
    int ix = 1 + (int)rint(clamp_f(0.5f * px + 0.5f, 0.0f, 1.0f) * 65534.0f);
    int iy = 1 + (int)rint(clamp_f(0.5f * py + 0.5f, 0.0f, 1.0f) * 65534.0f);
    return (ix << 16) | iy;
}

inline float3 normal_unpack(int bits)
{
    float px = (float)(((uint)bits >> 16) - 1u) * (2.0f / 65534.0f) - 1.0f;
    float py = (float)(((uint)bits & 0xffffu) - 1u) * (2.0f / 65534.0f) - 1.0f;
    float pz = 1.0f - abs_f(px) - abs_f(py);
    if (pz < 0.0f) {
        float qx = (1.0f - abs_f(py)) * (px >= 0.0f ? 1.0f : -1.0f);
        py = (1.0f - abs_f(px)) * (py >= 0.0f ? 1.0f : -1.0f);
        px = qx;
    }
    return norm3((float3)(px, py, pz));
}

#endif
