/* The surface a ray hit, as the G-buffer records it: position, normals, the material's albedo and emission with
 * textures evaluated over a footprint, and (glossy builds) its closures resolved for the ray's direction into the
 * diffuse albedo and lobes. The primary pass writes it for camera rays; a path vertex (path/vertex.h) reads it for
 * a bounce ray. */
#ifndef RESTIRCL_SURFACE_HIT_H
#define RESTIRCL_SURFACE_HIT_H

/* The scene's buffers a surface is read from. */
typedef struct {
    const __global Tri* tris;
    const __global Material* materials;
    const __global TriAttr* tri_attr;
    const __global ObjectInfo* objects;
    const __global Closure* closures;
    const __global TexNode* tex_nodes;
    const __global TexImage* tex_images;
    const __global float4* texels;
    const __global float* ggx_tables;
} SceneSurfaces;

/* The G-sample (all but pos.w, the view depth, motion, and the layer's lanes but x, the surfaces passed: the
 * primary pass keeps a still's layer weight in layer.y) and the glossy record of the surface that the ray in unit
 * direction d hit (hit.prim >= 0), textures filtered over `footprint` (texture_point). *gx is filled in glossy
 * builds: its wo always, its lobes where the material has closures. */
inline void hit_gsample(const SceneSurfaces* sc, Hit hit, float3 d, float footprint, GSample* g, GlossySample* gx)
{
    Tri t = sc->tris[hit.prim];
    float3 p = t.v0.xyz + hit.u * t.e1.xyz + hit.v * t.e2.xyz;
    float3 ng = norm3(cross3(t.e1.xyz, t.e2.xyz));
    int backfacing = dot3(ng, d) > 0.0f;
    if (backfacing) ng = -ng;
    int mat = as_int(t.v0.w);
    int obj_bits = as_int(t.e2.w);  /* the object id, and its light sets where lights are linked */
    int obj = obj_bits & LINK_OBJECT_MASK;
    Material m = sc->materials[mat];
    TexPoint tp = texture_point(sc->tri_attr, sc->objects, hit.prim, obj, hit.u, hit.v, d, ng, backfacing, footprint);
    tp.e1 = t.e1.xyz;
    tp.e2 = t.e2.xyz;
    float3 albedo = m.albedo.xyz, emission = m.emission.xyz;
#ifdef HAS_TEXTURES
    texture_material(sc->materials + mat, sc->closures, sc->tex_nodes, sc->tex_images, sc->texels, &tp, &albedo,
                     &emission);
#endif
    g->pos.xyz = p;
    g->normal = (float4)(tp.ns, as_float(hit.prim));
    g->gnormal = (float4)(ng, as_float(mat));
    g->albedo = (float4)(albedo, as_float(obj_bits));
#ifdef HAS_GLOSSY
    /* the material's closures resolved for this view at the shading normal: the diffuse albedo under the specular
     * layer, and the lobes */
    int count = min(m.info.y, MAX_LAYERS);
    if (count > 0) {
        ClosureInputs cin[MAX_LAYERS];
        for (int k = 0; k < count; ++k) {
#ifdef HAS_TEXTURES
            cin[k] = closure_inputs(&sc->closures[m.info.x + k], sc->tex_nodes, sc->tex_images, sc->texels, &tp);
#else
            cin[k] = closure_constants(&sc->closures[m.info.x + k]);
#endif
            cin[k].backfacing = backfacing;
        }
        /* the lobes' normal, as surface_load derives it again */
        float3 nl = tp.bumped ? shading_normal_guard(tp.ns, ng, -d) : tp.ns;
        g->albedo.xyz = surface_resolve(cin, count, nl, -d, sc->ggx_tables, gx);
    } else {
        gx->wo = (float4)(-d, as_float(0));
    }
#else
    (void)gx;
#endif
    g->emission = (float4)(emission, as_float(tp.bumped ? normal_pack(tp.nb) : 0));
#ifdef HAS_TRANSPARENCY
    g->layer.x = as_float(hit.passed);
#else
    g->layer.x = 0.0f;
#endif
}

#endif
