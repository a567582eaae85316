/* The surface a pixel shows, as the shading code reads it from the G-buffer: where it is, which way it faces, where
 * the viewer is, and its material (what the BSDF, bsdf/bsdf.h, reads). Private to a kernel; the G-buffer (GSample, and
 * GlossySample in glossy scenes, types.h) is the stored form. */
#ifndef RESTIRCL_SURFACE_H
#define RESTIRCL_SURFACE_H

#include "bsdf/lobes.h"
#include "surface/shading_normal.h"

/* The material parameters of a surface, for the BSDF: the diffuse albedo and, in glossy builds, the lobes the
 * primary pass resolved for this pixel's view (bsdf/resolve.h). */
typedef struct {
    float3 albedo;  /* diffuse reflectance, rgb in [0, 1] (under the specular layer: already scaled for it) */
#ifdef HAS_GLOSSY
    int lobes;      /* lobes in use beyond the diffuse part, 0 .. MAX_LAYERS */
    Lobe lobe[MAX_LAYERS];
#endif
} SurfaceMaterial;

typedef struct {
    float3 x;       /* world position */
    float3 n;       /* shading normal facing the camera: the diffuse part's and the lights' cosine */
    float3 ng;      /* geometric normal facing the camera */
#ifdef HAS_GLOSSY
    float3 nl;      /* the specular lobes' normal: n, bent on normal-mapped pixels (shading_normal_guard) */
#endif
#ifdef HAS_TEXTURES
    float3 nb;      /* on normal-mapped pixels the smooth normal under the map (bump_shadowing), else n */
    int bumped;     /* 1: n comes from a normal map */
#endif
    float3 wo;      /* unit direction towards the viewer. Glossy builds store it per pixel (GlossySample.wo); a
                       diffuse-only build, whose Lambert BSDF ignores it, sets it to n and stores nothing */
    SurfaceMaterial mat;
    float depth;    /* view depth */
    int valid;      /* 0: the primary ray missed */
    int prim;       /* the triangle hit (leaf order; < 0: none), for the shadow ray offset */
#ifdef HAS_LIGHT_LINKING
    int receiver;   /* the receiver light set of its object (lights/linking.h) */
#endif
#ifdef HAS_TRANSPARENCY
    int passed;     /* the transparent surfaces the path passed to reach it (GSample.layer.x), off its shadow rays'
                       allowance (direct/visibility.h shadow_allowance) */
#endif
} Surface;

/* The material of pixel i of the G-buffer g and its extension gx (valid: the pixel shows a surface); the lobes
 * from m.lobes on are left unset. */
inline SurfaceMaterial surface_material_load(const __global GSample* g, const __global GlossySample* gx, int i,
                                             int valid)
{
    SurfaceMaterial m;
    m.albedo = g[i].albedo.xyz;
#ifdef HAS_GLOSSY
    const __global GlossySample* q = gx + i;
    m.lobes = valid ? min(as_int(q->wo.w), MAX_LAYERS) : 0;
    /* only the lobes in use: every reader stops at m.lobes, and a diffuse pixel (most of a scene's) then reads one
     * of the sample's three cache lines (the passes are bound by these reads more than by their arithmetic) */
    if (m.lobes > 0) m.lobe[0] = q->lobe0;
    if (m.lobes > 1) m.lobe[1] = q->lobe1;
#else
    (void)gx;
    (void)valid;
#endif
    return m;
}

/* The surface of G-sample gs with material m seen from unit direction wo (glossy builds; others set wo = n). */
inline Surface surface_make(const GSample* gs, SurfaceMaterial m, float3 wo)
{
    Surface s;
    s.prim = as_int(gs->normal.w);
    s.valid = s.prim >= 0;
    s.x = gs->pos.xyz;
    s.depth = gs->pos.w;
    s.n = gs->normal.xyz;
    s.ng = gs->gnormal.xyz;
#ifdef HAS_LIGHT_LINKING
    s.receiver = (as_int(gs->albedo.w) >> LINK_RECEIVER_SHIFT) & LINK_SET_MASK;
#endif
#ifdef HAS_TRANSPARENCY
    s.passed = as_int(gs->layer.x);
#endif
#ifdef HAS_TEXTURES
    int nb = as_int(gs->emission.w);
    s.bumped = s.valid && nb != 0;
    s.nb = s.bumped ? normal_unpack(nb) : s.n;
#endif
    s.mat = m;
#ifdef HAS_GLOSSY
    s.wo = wo;
    s.nl = s.n;
#ifdef HAS_TEXTURES
    if (s.bumped) s.nl = shading_normal_guard(s.n, s.ng, s.wo);
#endif
#else
    (void)wo;
    s.wo = s.n;
#endif
    return s;
}

/* Pixel i of the G-buffer g and its extension gx (read only in glossy builds; a placeholder buffer otherwise). */
inline Surface surface_load(const __global GSample* g, const __global GlossySample* gx, int i)
{
    GSample gs = g[i];
    int valid = as_int(gs.normal.w) >= 0;
#ifdef HAS_GLOSSY
    float3 wo = gx[i].wo.xyz;
#else
    float3 wo = gs.normal.xyz;
#endif
    return surface_make(&gs, surface_material_load(g, gx, i, valid), wo);
}

/* The surface of a private G-sample and glossy record (a path vertex: path/vertex.h). */
inline Surface surface_of(const GSample* gs, const GlossySample* gx)
{
    SurfaceMaterial m;
    m.albedo = gs->albedo.xyz;
#ifdef HAS_GLOSSY
    m.lobes = min(as_int(gx->wo.w), MAX_LAYERS);
    if (m.lobes > 0) m.lobe[0] = gx->lobe0;
    if (m.lobes > 1) m.lobe[1] = gx->lobe1;
    return surface_make(gs, m, gx->wo.xyz);
#else
    (void)gx;
    return surface_make(gs, m, gs->normal.xyz);
#endif
}

/* A surface built by hand (tests) with normal n everywhere and no normal map. */
inline void surface_set_normal(Surface* s, float3 n)
{
    s->n = s->ng = n;
#ifdef HAS_GLOSSY
    s->nl = n;
#endif
#ifdef HAS_TEXTURES
    s->nb = n;
    s->bumped = 0;
#endif
}

/* How far two surfaces' materials may differ for one to reuse the other's light samples (temporal and spatial
 * reuse): a glossy target at one is not the other's when roughness or the metallic share differ much. */
#define SIMILAR_ROUGHNESS 0.15f   /* |roughness difference| of a lobe */
#define SIMILAR_METALLIC 0.25f    /* |difference| of the share of the metallic part in the reflectance */

/* What surface_material_similar compares of a material: per lobe its roughness (sqrt of alpha) and metallic share.
 * The spatial pass computes it for each candidate neighbour straight from the G-buffer (surface_material_load),
 * without the rest of its surface. */
typedef struct {
#ifdef HAS_GLOSSY
    int lobes;
    float2 lobe[MAX_LAYERS];  /* x: roughness, y: metallic share */
#else
    int unused;
#endif
} MaterialKey;

#ifdef HAS_GLOSSY
/* the share of a lobe's metallic (F82-tint: metal or Glossy) part in its and the diffuse reflectance */
inline float surface_metal_share(const SurfaceMaterial* m, int k)
{
    float2 w = lobe_weights(&m->lobe[k]);
    float mw = w.x;
    float dw = w.y + m->albedo.x + m->albedo.y + m->albedo.z;
    return mw / fmax_f(mw + dw, 1e-6f);
}
#endif

inline MaterialKey material_key(const SurfaceMaterial* m)
{
    MaterialKey key;
#ifdef HAS_GLOSSY
    key.lobes = m->lobes;
    for (int k = 0; k < MAX_LAYERS; ++k) {
        const Lobe* l = &m->lobe[k];
        key.lobe[k] = k < m->lobes ? (float2)(sqrt(lobe_alpha(l)), surface_metal_share(m, k)) : (float2)(0.0f);
    }
#else
    (void)m;
    key.unused = 0;
#endif
    return key;
}

/* Whether two materials are alike enough for one surface to reuse the other's light samples: the same number of
 * lobes, each of similar roughness and metallic share. Diffuse-only builds: always. */
inline bool material_keys_similar(const MaterialKey* a, const MaterialKey* b)
{
#ifdef HAS_GLOSSY
    if (a->lobes != b->lobes) return false;
    for (int k = 0; k < a->lobes; ++k) {
        if (abs_f(a->lobe[k].x - b->lobe[k].x) > SIMILAR_ROUGHNESS) return false;
        if (abs_f(a->lobe[k].y - b->lobe[k].y) > SIMILAR_METALLIC) return false;
    }
#else
    (void)a;
    (void)b;
#endif
    return true;
}

/* material_keys_similar of two surfaces */
inline bool surface_material_similar(const Surface* a, const Surface* b)
{
    MaterialKey ka = material_key(&a->mat), kb = material_key(&b->mat);
    return material_keys_similar(&ka, &kb);
}

#endif
