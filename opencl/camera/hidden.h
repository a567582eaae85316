/* Objects the camera does not see (Mesh.camera_visible off: Blender's Ray Visibility > Camera, or a view layer's
 * Indirect Only collection; HAS_CAMERA_HIDDEN): a camera ray passes through them to what lies behind, while
 * shadow rays and bounces still meet them. The pass-through continues the ray from just beyond each hidden surface,
 * up to CAMERA_HIDDEN_LAYERS of them (a deeper stack is taken as seen). A seen surface in the plane of a hidden one
 * (a hidden box standing on a seen floor) is passed with it: the ray continues from beyond that plane. */
#ifndef RESTIRCL_CAMERA_HIDDEN_H
#define RESTIRCL_CAMERA_HIDDEN_H

#ifdef HAS_CAMERA_HIDDEN

#define CAMERA_HIDDEN_LAYERS 16

/* The first surface along the camera ray (o, d) that the camera sees, starting from its first hit `hit`; t is
 * the distance from o as trace_closest gives it. */
inline Hit camera_seen_hit(const __global BVHNode* nodes, const __global Tri* tris,
                           const __global ObjectInfo* objects, float3 o, float3 d, Hit hit)
{
    float3 start = o;
    for (int k = 0; k < CAMERA_HIDDEN_LAYERS && hit.prim >= 0; ++k) {
        Tri t = tris[hit.prim];
        if (!(as_int(objects[as_int(t.e2.w) & LINK_OBJECT_MASK].gen_mid.w) & OBJECT_CAMERA_HIDDEN)) break;
        float3 p = t.v0.xyz + hit.u * t.e1.xyz + hit.v * t.e2.xyz;
        float3 ng = norm3(cross(t.e1.xyz, t.e2.xyz));
        if (dot3(ng, d) < 0.0f) ng = -ng;  /* the side the ray leaves to */
        start = offset_ray_origin(p, ng);
        hit = trace_closest(nodes, tris, start, d, INFINITY);
        hit.t += dot3(start - o, d);  /* from the camera again */
    }
    return hit;
}

#endif
#endif
