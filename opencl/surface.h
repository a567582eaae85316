/* The surface a pixel shows, as the shading code reads it from the G-buffer: where it is, which way it faces, and
 * its material (what the BSDF, bsdf.h, reads). Private to a kernel; the G-buffer (GSample, types.h) is the stored
 * form. */
#ifndef RESTIRCL_SURFACE_H
#define RESTIRCL_SURFACE_H

/* The material parameters of a surface, for the BSDF. The diffuse BSDF reads the albedo only; a BSDF with more
 * parameters (base colour, roughness, metallic, ...) adds them here and surface_load fills them, so resampling and
 * the shading sites, which pass the Surface along, do not change. */
typedef struct {
    float3 albedo;  /* diffuse reflectance, rgb in [0, 1] */
} SurfaceMaterial;

typedef struct {
    float3 x;       /* world position */
    float3 n;       /* shading normal facing the camera */
    float3 ng;      /* geometric normal facing the camera */
    float3 wo;      /* unit direction towards the viewer: NOT stored in this G-buffer layout, so set to n. Only the
                       diffuse BSDF reads surfaces yet and it ignores wo; a BSDF that reads it needs the G-buffer to
                       carry it first (or the camera position to derive it from x). */
    SurfaceMaterial mat;
    float depth;    /* view depth */
    int valid;      /* 0: the primary ray missed */
    int prim;       /* the triangle hit (leaf order; < 0: none), for the shadow ray offset */
} Surface;

inline Surface surface_load(const __global GSample* g, int i)
{
    Surface s;
    GSample gs = g[i];
    s.prim = as_int(gs.normal.w);
    s.valid = s.prim >= 0;
    s.x = gs.pos.xyz;
    s.depth = gs.pos.w;
    s.n = gs.normal.xyz;
    s.ng = gs.gnormal.xyz;
    s.wo = s.n;
    s.mat.albedo = gs.albedo.xyz;
    return s;
}

/* Whether the materials of two surfaces are alike enough for one to reuse the other's light samples (temporal and
 * spatial reuse): a glossy target at one is not the other's when roughness or metallic differ much. */
inline bool surface_material_similar(const Surface* a, const Surface* b)
{
    (void)a;
    (void)b;
    return true;
}

#endif
