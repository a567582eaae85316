/* A vertex of a path after the primary hit: the surface a bounce ray from x in unit direction d met (the G-buffer's
 * record of it, surface/hit.h, turned into a Surface facing the ray). Textures are read at their finest level: a
 * bounce has no ray cone. */
#ifndef RESTIRCL_PATH_VERTEX_H
#define RESTIRCL_PATH_VERTEX_H

/* The ray's origin off surface s towards direction d, as a shadow ray leaves it (direct/visibility.h). */
inline float3 path_ray_origin(const __global Tri* tris, const Surface* s, float3 d)
{
    Tri tri = tris[s->prim];
    float err = RESTIRCL_OFFSET_ULPS * FLT_EPSILON * (max_abs3(s->x) + max_abs3(tri.e1.xyz) + max_abs3(tri.e2.xyz));
    return s->x + err * (dot3(s->ng, d) >= 0.0f ? s->ng : -s->ng);
}

/* The surface of hit h (h.prim >= 0) of the ray in unit direction d. */
inline Surface path_vertex(const SceneSurfaces* sc, Hit h, float3 d)
{
    GSample g;
    GlossySample gx;
    hit_gsample(sc, h, d, 0.0f, &g, &gx);
    g.pos.w = h.t;
#ifndef HAS_GLOSSY
    gx.wo = (float4)(-d, as_float(0));
#endif
    return surface_of(&g, &gx);
}

#endif
