/* Pass 1: camera rays into the G-buffer (position, normals, albedo, emission seen directly, motion vectors).
 * motion.xy: previous minus current pixel position of the hit (jitter removed); motion.z: 1 if the hit has a
 * previous position on the previous camera's image plane; motion.w: its view depth in the previous camera.
 * vector (the Vector pass): xy as motion.xy, zw the next frame's position minus the current one (pixels, y down).
 * object_motion: per object, 3 rows of M_prev M_cur^-1, then 3 rows of M_next M_cur^-1. */

inline float3 motion_apply(const __global float4* m, float3 p)
{
    float4 p4 = (float4)(p, 1.0f);
    return (float3)(dot(m[0], p4), dot(m[1], p4), dot(m[2], p4));
}

__kernel void primary(const __global Camera* cam, const __global Camera* prev_cam, const __global Camera* next_cam,
                      const __global BVHNode* nodes, const __global Tri* tris,
                      const __global Material* materials, const __global float4* object_motion,
                      const __global TriAttr* tri_attr, const __global ObjectInfo* objects,
                      const __global Closure* closures, const __global TexNode* tex_nodes,
                      const __global TexImage* tex_images, const __global float4* texels,
                      const __global float* ggx_tables,
                      const __global Light* lights, const __global float4* camera_lights,
                      __global GSample* gbuf, __global GlossySample* glossy, __global float4* vector,
                      __global float4* light_passes, FrameParams frame_params,
                      __global float4* layers, volatile __global int* layers_continuing, int layer)
{
    int x = get_global_id(0), y = get_global_id(1);
    int w = cam->width, h = cam->height;
    if (x >= w || y >= h) return;
    int i = y * w + x;
    float2 ray_px = camera_ray_position(cam, &frame_params, x, y, i);
    float3 o, d;
#ifdef HAS_DOF
    if (cam->aperture.x > 0.0f)  /* the ray's own lens point; its hit is reprojected as a pinhole sees it */
        camera_lens_ray(cam, ray_px.x, ray_px.y, lens_uv(&frame_params, i), &o, &d);
    else
        camera_ray(cam, ray_px.x, ray_px.y, &o, &d);
#else
    camera_ray(cam, ray_px.x, ray_px.y, &o, &d);
#endif
#ifdef HAS_TRANSPARENCY
    /* layer >= 0: the weighted layers of a still (camera/layers.h); else the first surface the ray does not pass
     * (bvh/transparent.h) */
    CameraLayer lay = camera_layer(layers, i, layer, o);
    if (layer > 0 && !(lay.weight > 0.0f)) {
        camera_layer_none(gbuf + i);
        return;
    }
    o = lay.o;
    Hit hit = layer >= 0 ? camera_layer_trace(nodes, tris, &lay, d)
                         : trace_camera(nodes, tris, o, d, INFINITY, camera_coverage_number(cam, &frame_params, (uint)i));
#else
    (void)layers;
    (void)layers_continuing;
    (void)layer;
    Hit hit = trace_closest(nodes, tris, o, d, INFINITY);
#endif
#ifdef HAS_CAMERA_HIDDEN
    hit = camera_seen_hit(nodes, tris, objects, o, d, hit);
#endif
    float3 sun_seen = (float3)(0.0f);  /* the suns a ray that misses sees (lights/camera_visible.h) */
#ifdef HAS_CAMERA_LIGHTS
    if (camera_light_pixel(lights, camera_lights, cam, prev_cam, next_cam, o, d, hit.t,
                           gbuf + i, glossy + i, vector + i, &sun_seen)) {
#ifdef HAS_TRANSPARENCY  /* a light is opaque: the layer takes what reached it, and the pixel's layers end */
        if (layer >= 0)
            gbuf[i].layer.y = camera_layer_next(tris, layers, layers_continuing + (layer & 1), i, &lay, hit, d, 1.0f);
#endif
#ifdef HAS_LIGHT_PASSES  /* a light the camera sees is emission (Cycles' Emission pass) */
        light_pass_seen(light_passes, w * h, i, gbuf[i].emission.xyz, (float3)(0.0f), (float3)(0.0f),
                        (float3)(0.0f));
#endif
#ifdef HAS_LIGHT_GROUPS  /* ... of its light's group (camera_visible.h: prim = CAMERA_LIGHT_PRIM(light)) */
        int seen = -2 - as_int(gbuf[i].normal.w);
        light_groups_seen(light_passes, w * h, i, light_group(lights, &lights[seen]), gbuf[i].emission.xyz);
#endif
        return;
    }
#else
    (void)lights;
    (void)camera_lights;
#endif
    GSample g;
    g.motion = (float4)(0.0f);
    g.layer = (float4)(0.0f);
#ifdef HAS_TRANSPARENCY  /* the surfaces passed, and the layer's weight (0 outside the weighted layers) */
    if (layer >= 0)
        g.layer.y = camera_layer_next(tris, layers, layers_continuing + (layer & 1), i, &lay, hit, d,
                                      hit.prim >= 0 ? surface_coverage(tris, hit.prim, hit.u, hit.v) : 1.0f);
    g.layer.x = as_float(max(hit.passed, 0));
#endif
#ifdef HAS_TRANSPARENCY
    if (hit.prim == TRANSPARENT_ENDED) {  /* past Transparent Max Bounces: the path ends here, black and opaque */
        float3 p = o + hit.t * d;
        g.pos = (float4)(p, camera_depth(cam, p));
        g.normal = (float4)(-d, as_float(TRANSPARENT_ENDED));  /* below -1: not shaded */
        g.gnormal = (float4)(-d, as_float(-1));
        g.albedo = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
        g.emission = (float4)(0.0f);
        gbuf[i] = g;  /* motion.z = 0: no previous position */
        vector[i] = (float4)(0.0f);
#ifdef HAS_GLOSSY
        glossy[i].wo = (float4)(-d, as_float(0));
#endif
#ifdef HAS_LIGHT_PASSES
        light_pass_seen(light_passes, w * h, i, (float3)(0.0f), (float3)(0.0f), (float3)(0.0f), (float3)(0.0f));
#endif
        return;
    }
#endif
    int holdout = -1;  /* the holdout object the ray met (Mesh.holdout): the pixel is a hole, as a miss of nothing */
#ifdef HAS_HOLDOUT
    /* the object id without its light sets (lights/linking.h) */
    int hit_obj = hit.prim >= 0 ? (as_int(tris[hit.prim].e2.w) & LINK_OBJECT_MASK) : -1;
    if (hit_obj >= 0 && (as_int(objects[hit_obj].gen_mid.w) & OBJECT_HOLDOUT)) {
        holdout = hit_obj;
        sun_seen = (float3)(0.0f);
    }
#endif
    if (hit.prim < 0 || holdout >= 0) {
        g.pos = (float4)(0.0f, 0.0f, 0.0f, INFINITY);
        g.normal = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
        g.gnormal = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
        g.albedo = (float4)(0.0f, 0.0f, 0.0f, as_float(holdout));  /* w: -1, or the holdout's object (its alpha 0) */
        g.emission = (float4)(sun_seen, 0.0f);  /* a sun the ray sees is in front of the world */
        float3 world_seen = (float3)(0.0f);
#ifdef HAS_ENVIRONMENT
        if (holdout < 0) world_seen = environment_seen(lights, d);
        g.emission.xyz += world_seen;
#endif
#ifdef HAS_LIGHT_PASSES  /* the suns are lights (Emission), the world is the Environment */
        light_pass_seen(light_passes, w * h, i, sun_seen, world_seen, (float3)(0.0f), (float3)(0.0f));
#endif
#ifdef HAS_LIGHT_GROUPS  /* the world (the first light record) in its group; a sun's disk seen in none */
#ifdef HAS_ENVIRONMENT
        light_groups_seen(light_passes, w * h, i, light_group(lights, &lights[0]), world_seen);
#else
        light_groups_seen(light_passes, w * h, i, -1, world_seen);
#endif
#endif
        g.motion = (float4)(0.0f, 0.0f, 1.0f, INFINITY);  /* the background: reprojected by direction */
        float4 vec = (float4)(0.0f);
#ifdef HAS_MOTION
        float2 delta;
        if (camera_dir_motion(cam, prev_cam, d, ray_px, &delta))
            g.motion.xy = vec.xy = delta;
        else
            g.motion.z = 0.0f;
        if (camera_dir_motion(cam, next_cam, d, ray_px, &delta)) vec.zw = delta;
#endif
        gbuf[i] = g;
        vector[i] = vec;
#ifdef HAS_GLOSSY
        glossy[i].wo = (float4)(-d, as_float(0));
#endif
        return;
    }
    const SceneSurfaces sc = {tris, materials, tri_attr, objects, closures, tex_nodes, tex_images, texels, ggx_tables};
    /* smooth shading and texture coordinates, textures filtered over the pixel's ray cone, or read at full
     * resolution (a footprint of 0: level 0) where the frame's samples are averaged (render/plan.py texture_full) */
    GlossySample gx;
    hit_gsample(&sc, hit, d, cam->texture_full ? 0.0f : camera_footprint(cam, d, hit.t), &g, &gx);
    float3 p = g.pos.xyz;
    int obj = as_int(g.albedo.w) & LINK_OBJECT_MASK;
    g.pos.w = camera_depth(cam, p);
#ifdef HAS_GLOSSY
    if (materials[as_int(g.gnormal.w)].info.y > 0)  /* a material with closures: its resolved record, whole */
        glossy[i] = gx;
    else
        glossy[i].wo = gx.wo;
#else
    (void)glossy;
#endif
    g.motion = (float4)(0.0f, 0.0f, 1.0f, g.pos.w);  /* nothing moves: the previous position is this one */
    float4 vec = (float4)(0.0f);
#ifdef HAS_MOTION
    float3 pp = p, pn = p;
#ifdef HAS_MOVING_OBJECTS
    pp = motion_apply(object_motion + 6 * obj, p);
    pn = motion_apply(object_motion + 6 * obj + 3, p);
#endif
    float2 cur_px, prev_px, next_px;
    bool cur_ok = camera_project(cam, p, &cur_px);
    if (cur_ok && camera_project(prev_cam, pp, &prev_px))
        g.motion = (float4)(prev_px - cur_px, 1.0f, camera_depth(prev_cam, pp));
    else
        g.motion = (float4)(0.0f, 0.0f, 0.0f, 0.0f);  /* z = 0: no valid previous position */
    vec.xy = g.motion.xy;
    if (cur_ok && camera_project(next_cam, pn, &next_px)) vec.zw = next_px - cur_px;
#endif
    gbuf[i] = g;
    vector[i] = vec;
#ifdef HAS_LIGHT_PASSES
    float3 gloss_colour = (float3)(0.0f);
#ifdef HAS_GLOSSY
    if (materials[as_int(g.gnormal.w)].info.y > 0) {  /* as accumulate_aux reads the lobes (still/aux.cl) */
        int lobes = as_int(gx.wo.w);
        if (lobes > 0) gloss_colour += lobe_albedo(&gx.lobe0);
        if (lobes > 1) gloss_colour += lobe_albedo(&gx.lobe1);
    }
#endif
    light_pass_seen(light_passes, w * h, i, g.emission.xyz, (float3)(0.0f), g.albedo.xyz, gloss_colour);
#if defined(HAS_GLOSSY) && defined(HAS_TRANSMISSION)  /* the colour of what it lets through */
    if (materials[as_int(g.gnormal.w)].info.y > 0) {
        Surface ts = surface_of(&g, &gx);
        light_pass_transmission_colour(light_passes, w * h, i, &ts);
    }
#endif
#ifdef HAS_LIGHT_GROUPS  /* an emissive surface in its object's group (ObjectInfo.gen_scale.w) */
    light_groups_seen(light_passes, w * h, i, as_int(objects[obj].gen_scale.w), g.emission.xyz);
#endif
#else
    (void)light_passes;
#endif
}
