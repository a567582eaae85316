/* Every struct shared between the host and the device, and nothing else.
 * Mirrored by numpy dtypes in python/restircl/core/layouts.py; tests/core/test_layouts.py compares sizeof/offsetof.
 * Rules: no float3 (16 bytes here, 12 in numpy); float4 members first; sizes multiples of 16. */
#ifndef RESTIRCL_TYPES_H
#define RESTIRCL_TYPES_H

#include "codes.h"  /* the codes and constants these structs hold (generated: python/restircl/upload/codes.py) */

/* ---- geometry -------------------------------------------------------------------------------- */

/* One triangle in world space, in BVH leaf order. */
typedef struct {
    float4 v0;   /* xyz: vertex 0; w: material id (int bits) */
    float4 e1;   /* xyz: v1 - v0;  w: original triangle index (int bits) */
    float4 e2;   /* xyz: v2 - v0;  w: object id (int bits; with light linking its light sets in the high bits:
                    lights/linking.h) */
} Tri;           /* 48 bytes */

/* 4-wide BVH node: the boxes of up to four children in SoA form, tested together with float4 operations.
 * Node 0 is the root; nodes are numbered depth first. Child reference c = child[k]: c >= 0 is the inner node c;
 * c < 0 is a leaf holding the triangles tris[~c .. ~c + count[k] - 1] (~c == -c - 1); with leaf packets
 * (BVH_TRI4, python/restircl/bvh/packets.py) ~c is the leaf's packet in the Tri array and count[k] its first
 * triangle. An unused slot is a leaf of count 0 whose box is empty (min +inf, max -inf), so no ray enters it.
 * count[k] is 0 for inner children. */
typedef struct {
    float4 minx;   /* lane k: child k's box */
    float4 maxx;
    float4 miny;
    float4 maxy;
    float4 minz;
    float4 maxz;
    int4 child;
    int4 count;
} BVHNode;         /* 128 bytes */

/* ---- materials and lights -------------------------------------------------------------------- */

/* A material: what the diffuse-only kernels read (albedo, emission) first; then where its closures are. A material
 * is 1..MAX_LAYERS closures (python/restircl/materials/material.py), summed with their weights (Mix / Add Shader). */
typedef struct {
    float4 albedo;     /* rgb: diffuse albedo of diffuse-only builds (the closures' constant colours summed with
                          their weights); w: unused */
    float4 emission;   /* rgb: emitted radiance (colour * strength); w: 1 if emissive */
    int4 info;         /* x: first closure in the closure table; y: closure count; z: emission texture node (-1:
                          constant); w: MATERIAL_* flags (informative: each closure carries its own weight) */
} Material;            /* 48 bytes */

/* One closure's inputs: a constant each, replaced by a texture node's value where its index in tex / tex2 is not
 * TEX_NONE (opencl/textures/closure_inputs.h evaluates them). */
typedef struct {
    float4 base;       /* rgb: Base Color / Color; w: Metallic */
    float4 spec;       /* x: Roughness; y: IOR; z: Specular IOR Level; w: weight (Mix factor, 1 for Add) */
    float4 tint;       /* rgb: Specular Tint; w: unused */
    int4 kind;         /* x: CLOSURE_*; y: 1 = multiscatter GGX, 0 = GGX; z: 1 = weigh by 1 - weight (the first
                          closure of a Mix); w: unused */
    int4 tex;          /* texture node of x: base colour, y: metallic, z: roughness, w: specular level */
    int4 tex2;         /* x: specular tint, y: normal map, z: weight, w: unused */
    float4 glass;      /* x: Transmission Weight (Principled); y: Thin Film Thickness (nm); z: Thin Film IOR; w: 1 = Thin Wall (Principled) */
} Closure;             /* 112 bytes */

/* ---- surface attributes and textures (opencl/texture_*.h, python/restircl/upload/textures.py) ---------- */

/* Per triangle, in BVH leaf order (python/restircl/upload/tri_attributes.py): what the primary hit interpolates for
 * smooth shading and texture coordinates. Uploaded only when some mesh has normals or some material a texture. */
typedef struct {
    float4 n0;         /* xyz: world-space shading normal at corner 0 (Mesh.normals; the geometric one if none) */
    float4 n1;
    float4 n2;
    float4 u;          /* xyz: UV u at corners 0, 1, 2; w: 0.5 log2(UV area / world area), for the mip level */
    float4 v;          /* xyz: UV v at corners 0, 1, 2; w: bitangent sign of the UV tangent frame */
    float4 o0;         /* xyz: object-space position of corner 0; w: 0.5 log2(object area / world area) */
    float4 oe1;        /* xyz: object-space edge corner 1 - corner 0; w: 0.5 log2(generated area / world area) */
    float4 oe2;        /* xyz: object-space edge corner 2 - corner 0; w: unused */
    float4 tangent;    /* xyz: world-space UV tangent (dP/du); w: offset of its colour attributes (int bits) */
} TriAttr;             /* 144 bytes */

/* Per object (mesh): how its texture space and attributes are set up. */
typedef struct {
    float4 gen_mid;    /* xyz: centre of the object-space bounding box (Blender's texture space); w: OBJECT_* flags
                          (int bits) */
    float4 gen_scale;  /* xyz: 1 / (2 half size): generated = (p - mid) * scale + 0.5; w: its light group (int bits,
                          -1: none; film/light_groups.h) */
} ObjectInfo;          /* 32 bytes */

/* One node of a texture program. An input refers to an earlier node (in) or holds a constant (a, b, p.x). A
 * material input's program is the contiguous run of nodes blk.x .. its own index, evaluated in order. */
typedef struct {
    float4 a;          /* rgb: constant of input a (Checker color1, Mix a, Normal Map color) */
    float4 b;          /* rgb: constant of input b (Checker color2, Mix b) */
    float4 p;          /* x: factor constant (Mix) / scale (Checker) / strength (Normal Map); y: log2 of the mapping's
                          scale (mip level); zw: unused */
    float4 m0;         /* rows of the coordinate mapping (Mapping node, Point): c' = (m0.c, m1.c, m2.c) + w */
    float4 m1;
    float4 m2;
    int4 op;           /* x: TEXNODE_*; y: Mix blend (TEXMIX_*) / image interpolation (TEXINTERP_*) / colour mode
                          (TEXCOLOR_*) / operation (TEXMATH_*, TEXVEC_*); z: image extension (TEXEXT_*) / Separate
                          Color's channel; w: coordinates (TEXCOORD_*) */
    int4 in;           /* x, y, z: node feeding a, b, the factor (-1: the constant); w: image index */
    int4 blk;          /* x: first node of the program ending here; y: 1 = clamp the Mix factor / Math's result; z: 1 =
                          the image's texels are sRGB-encoded: decode after filtering (8-bit sRGB images, as Cycles) /
                          clamp the Mix result; w: 1 = the node gives a number (tex_number reads it as it is) */
} TexNode;             /* 144 bytes */

/* One image and its mip chain in the texel buffer: level 0 (width x height texels, bottom row first as Blender
 * stores them) at offset, each further level (halved, rounded up) right after the previous one. */
typedef struct {
    int offset;
    int width;
    int height;
    int levels;
} TexImage;            /* 16 bytes */

#ifndef MAX_TEX_PROGRAM
#endif

/* One packed 64-byte record per light: a candidate costs one cache line, even with 1e6 lights. Every type keeps
 * its code in p.w, its radiance (intensity for points) in L.xyz and its flags in L.w (lights/record.h); what the
 * other lanes hold is the type's: see its decode step in lights/<type>.h. */
typedef struct {
    float4 p;    /* xyz: per type;  w: type (int bits) */
    float4 a;    /* per type */
    float4 b;    /* per type */
    float4 L;    /* rgb: radiance or intensity; w: flags (int bits) */
} Light;         /* 64 bytes */

/* A node of the light tree (lights/tree.h, built by lights/tree.py): the bounds of the lights below it. */
typedef struct {
    float4 lo;   /* xyz: box min;  w: summed power */
    float4 hi;   /* xyz: box max;  w: cos theta_o, the half angle of the cone of emission normals */
    float4 axis; /* xyz: unit axis of that cone;  w: cos theta_e, how far beyond the normals they emit */
    int4 meta;   /* x: the light of a leaf (-1: inner node);  y: flags (LIGHT_TREE_TWO_SIDED);  z: sin theta_o
                    (float bits);  w: the number of leaves below it (1 for a leaf) */
} LightTreeNode; /* 64 bytes */

/* ---- camera ----------------------------------------------------------------------------------- */

/* A pinhole (kind CAMERA_PERSP) or orthographic (CAMERA_ORTHO) camera. With a = nx * lens.x + lens.z and
 * b = ny * lens.y + lens.w at normalised device coordinates (nx, ny) in [-1, 1]^2, the perspective ray leaves the
 * origin along forward + a right + b up; the orthographic one leaves origin + a right + b up along forward. */
typedef struct {
    float4 origin;    /* xyz: position */
    float4 right;     /* xyz: unit right */
    float4 up;        /* xyz: unit up */
    float4 forward;   /* xyz: unit view direction */
    float4 lens;      /* x, y: half the view plane (tan of the half field of view, or world units when orthographic);
                       * z, w: shift in the same units */
    float4 jitter;    /* xy: sub-pixel jitter in pixels applied to this frame's rays (unless the pixel's own:
                         camera/jitter.h); z: this frame's point of a stratified sequence in [0, 1)
                         (camera/coverage_number.h); w: unused */
    int width;
    int height;
    int kind;         /* CAMERA_PERSP or CAMERA_ORTHO */
    int texture_full; /* 1: camera rays read images at full resolution; 0: at their ray cone's mip level */
    float4 aperture;  /* thin lens (camera/lens.h): x: radius (world units; 0: a pinhole), y: height over width,
                       * z: blades (a polygon of that many corners; below 3 a disc), w: the polygon's rotation */
    float4 focus;     /* x: distance from the origin to the plane in focus, along forward; yzw: unused */
} Camera;             /* 144 bytes */

/* ---- per-pixel buffers ------------------------------------------------------------------------ */

/* The G-buffer of one pixel: what the primary ray hit. prim < 0 marks a miss. */
typedef struct {
    float4 pos;        /* xyz: world position of the hit; w: view depth (along camera forward) */
    float4 normal;     /* xyz: shading normal, facing the camera; w: primitive id (int bits), -1: miss */
    float4 gnormal;    /* xyz: geometric normal, facing the camera; w: material id (int bits) */
    float4 albedo;     /* rgb: diffuse albedo; w: object id (int bits) */
    float4 emission;   /* rgb: radiance emitted towards the camera (lights seen directly) */
    float4 motion;     /* xy: motion in pixels, previous minus current position (jitter removed); zw: 0 */
    float4 layer;      /* x: the transparent surfaces the camera ray passed to reach this one (int bits; 0 without
                          HAS_TRANSPARENCY), whose count a shadow ray's allowance takes off (bvh/transparent.h);
                          y: the layer's weight in a still's weighted layers (camera/layers.h; 0 outside them);
                          zw: 0 */
} GSample;             /* 112 bytes */

/* One lobe of a pixel's BSDF beyond its Lambert part (HAS_GLOSSY), as the primary pass resolved it from the
 * material's closures for this pixel's view (bsdf/resolve.h). Every lobe kind keeps its roughness squared (alpha)
 * in a.w, its sampling weight (its estimated albedo at this view) in d.w and its kind code in e.w
 * (bsdf/lobe_record.h); what the other lanes hold is the kind's: see its decode step in bsdf/<kind>.h. */
typedef struct {
    float4 a;          /* xyz: per kind; w: alpha (roughness^2) */
    float4 b;          /* per kind */
    float4 c;          /* per kind */
    float4 d;          /* xyz: per kind; w: sampling weight */
    float4 e;          /* xyz: per kind; w: kind (int bits, LOBE_*) */
} Lobe;                /* 80 bytes */

/* The G-buffer extension of glossy scenes (HAS_GLOSSY): what the BSDF needs beyond GSample, whose albedo holds the
 * diffuse part (already layered under the specular). */
typedef struct {
    float4 wo;         /* xyz: unit direction towards the viewer; w: lobe count (int bits) */
    Lobe lobe0;
    Lobe lobe1;
} GlossySample;        /* 176 bytes */

/* A weighted reservoir holding one light sample y = (light, u, v). */
typedef struct {
    int light;        /* light index, -1: empty */
    float u;          /* sample coordinates on the light, in [0, 1)^2 */
    float v;
    float w_sum;      /* sum of resampling weights */
    float M;          /* number of candidates seen (float: merges add confidence) */
    float W;          /* unbiased contribution weight */
    float target;     /* p-hat(y) at the pixel that owns the reservoir */
    int vis_age;      /* with visibility reuse: reuse passes that took the sample's visibility at this pixel from a
                         stored result rather than a ray since its last shadow ray (restir/reuse.h) */
} Reservoir;          /* 32 bytes */

/* A ReSTIR GI reservoir (opencl/restir_gi/): its sample is a secondary surface point x_s that a BSDF ray from the
 * pixel's visible point met, with the radiance L_o leaving it towards that point (restir_gi/sample.h). */
typedef struct {
    float4 pos;       /* xyz: x_s; w: unused */
    float4 normal;    /* xyz: geometric normal at x_s on the side its visible point saw; w: unused */
    float4 radiance;  /* rgb: L_o, what the path gathered from x_s on; w: unused */
    float w_sum;      /* sum of resampling weights */
    float M;          /* candidates seen (float: merges add confidence) */
    float W;          /* unbiased contribution weight, in solid angle at the reservoir's own visible point */
    float target;     /* p-hat of the sample at the reservoir's own pixel; 0: no sample */
} GIReservoir;        /* 64 bytes */

/* ---- parameters of the passes ---------------------------------------------------------------
 * One struct per stage, passed by value and read by field name; the host packs them (python/restircl/render/stages.py).
 * Every pass reads its random stream key (sample, seed) from FrameParams. */

/* The image a frame renders, and the key of its random numbers. */
typedef struct {
    int width;
    int height;
    int pixels;            /* width * height */
    uint sample;           /* frames rendered so far by this renderer */
    uint seed;             /* Settings.seed */
    int qmc;               /* QMC_ON (1): RIS draws from the pixel's scrambled Sobol sequence (sampling/qmc.h, setting
                            * sampler); QMC_PIXEL_JITTER (2): so does the camera ray's place in its pixel (camera/jitter.h) */
    uint qmc_index;        /* the sample's index in that sequence */
    uint qmc_key;          /* its scramble key (one per half buffer of a still render) */
} FrameParams;             /* 32 bytes */

/* What the light samplers draw candidates from (lights/array.h, lights/tiles.h). */
typedef struct {
    int light_count;       /* lights the samplers draw from; 0 when no light emits */
    int slot_count;        /* light array slots */
    int tile_count;        /* presampled light tiles; 0: candidates come straight from the light array */
    int tile_size;         /* entries per tile */
    int bsdf_candidates;   /* BSDF-sampled candidates per pixel (direct/bsdf_candidates.h); 0: none */
    int bsdf_analytic;     /* how many of the first lights (the analytic ones) BSDF rays are tested against */
    int bsdf_triangles;    /* 1: BSDF rays look for emissive triangles (tri_light) */
    int bsdf_glossy_only;  /* 1: BSDF candidates only where the material has a specular lobe */
    int light_tree;        /* 1: light candidates come from the light tree (lights/tree.h), not the array */
    int tree_leaves;       /* lights in the tree */
    int tree_distant;      /* lights outside it (no position: suns, the world; lights/distant_pick.h) */
    float tree_p_local;    /* the tree's share of the light array: the floor of a point's local share */
    int pick_table;        /* 1: RIS picks lights by the pixel's row of the per-pixel table (lights/pick_table.h) */
    int pad0;
    int pad1;
    int pad2;
} SamplerParams;           /* 64 bytes */

/* When a history or neighbour surface counts as the pixel's own (temporal and spatial reuse, TAA). */
typedef struct {
    float depth_tolerance; /* relative view-depth mismatch that rejects it */
    float normal_cos;      /* cosine below which its normal is rejected */
    int pad0;
    int pad1;
} SimilarityParams;        /* 16 bytes */

/* ReSTIR pass 2 (restir/initial.cl). */
typedef struct {
    SamplerParams sampler;
    int candidates;        /* RIS candidates per pixel */
    int visibility_reuse;  /* 1: shadow-test the chosen sample */
    int pad0;
    int pad1;
} InitialParams;           /* 80 bytes */

/* ReSTIR pass 4 (restir/temporal.cl). */
typedef struct {
    SimilarityParams similar;
    float m_cap;           /* history cap, absolute M */
    int bias_correction;   /* BIAS_* */
    int visibility_reuse;
    int lights_static;     /* 1: the light records are last frame's */
    uint permutation;      /* 0: none; else 16 | a per-frame 4-bit key (permutation sampling, camera/reproject.h) */
    int vis_static;        /* 1: geometry and lights are last frame's, so last frame's shadow tests still hold */
    int vis_max_age;       /* the visibility shortcut: reuse a stored visibility at most this often in a row; 0: off */
    float vis_max_distance;/* ... where the history's point is within this many pixels of the pixel's */
} TemporalParams;          /* 48 bytes */

/* ReSTIR pass 5 (restir/spatial.cl), one launch per spatial pass. */
typedef struct {
    SimilarityParams similar;
    int spatial_neighbours;
    float spatial_radius;  /* pixels */
    int bias_correction;   /* BIAS_* */
    int visibility_reuse;
    int pass_index;        /* index of this spatial pass: its own random numbers */
    int boost_neighbours;  /* neighbours of a pixel whose reservoir has no history (M <= fresh_m); 0: no boost */
    float fresh_m;         /* the M of a reservoir of this frame's candidates alone */
    int fresh_candidates;  /* first pass: extra light candidates for a fresh pixel no neighbour is similar to; 0: off */
    SamplerParams sampler; /* ... drawn as restir/initial.cl draws its candidates */
} SpatialParams;           /* 112 bytes */

/* The path pass (path/path.cl): the bounces after the primary hit, by Blender's Light Paths. */
typedef struct {
    SamplerParams sampler; /* NEE's light pick at every vertex (the array or the tree) and what its rays look for */
    int max_bounces;       /* Max Bounces (total): light that scattered at most this often; 0: no path pass */
    int max_diffuse;       /* scatterings off the Lambert part */
    int max_glossy;        /* scatterings off a lobe */
    int min_bounces;       /* Min Light Bounces: Russian roulette from bounce min_bounces + 2 on */
    float clamp_indirect;  /* Clamp Indirect (0: off): a contribution's rgb sum at most 3x this */
    float light_threshold; /* Light Threshold (0: off): NEE samples below it go through Russian roulette */
    int max_transmission;  /* refractions through a dielectric lobe */
    int split_glass;       /* 1: ReSTIR GI runs beside it and shades the rest: only pixels that transmit here */
} PathParams;              /* 96 bytes */

/* ReSTIR GI pass 2 (restir_gi/temporal.cl). */
typedef struct {
    SimilarityParams similar;
    float m_cap;           /* history cap, absolute M (an initial GI reservoir has M = 1) */
    int bias_correction;   /* BIAS_* */
    uint permutation;      /* 0: none; else 16 | a per-frame 4-bit key (permutation sampling, camera/reproject.h) */
    int pad0;
} GITemporalParams;        /* 32 bytes */

/* ReSTIR GI pass 3 (restir_gi/spatial.cl). */
typedef struct {
    SimilarityParams similar;
    int neighbours;
    float radius;          /* pixels */
    int bias_correction;   /* BIAS_* */
    int boost_neighbours;  /* neighbours of a pixel whose reservoir has no history (M <= 1); 0: no boost */
} GISpatialParams;         /* 32 bytes */

/* ReSTIR GI pass 4 (restir_gi/shade.cl). */
typedef struct {
    int visible_known;     /* 1: the reuse kept only samples visible from their pixel (the unbiased modes) */
    int split_glass;       /* 1: the path pass shades the pixels that transmit (path/path.cl): not here */
    int pad1;
    int pad2;
} GIShadeParams;           /* 16 bytes */

/* Pass 6: restir_shade, and the samplers without reuse (direct/direct.cl). */
typedef struct {
    SamplerParams sampler;
    int method;            /* METHOD_* (shade_direct) */
    int candidates;        /* RIS candidates per pixel (shade_direct, METHOD_RIS) */
    int visible_known;     /* restir_shade: the reuse passes already zeroed occluded samples */
    int bsdf_mis_sample;   /* shade_direct, METHOD_RIS: 1 = one BSDF sample beside the reservoir's (direct/bsdf_mis.h) */
    float clamp_direct;    /* Clamp Direct (direct/clamp.h; 0: off) */
    int pad0, pad1, pad2;
} ShadeParams;             /* 96 bytes */

/* Pass 7: temporal accumulation (taa/taa.cl). */
typedef struct {
    SimilarityParams similar; /* a disocclusion: the history's surface is not the pixel's */
    float alpha_min;       /* lower bound of the blend factor a = max(1/n, alpha_min) */
    float gamma;           /* variance clipping width, in standard deviations */
    int moving;            /* 1: camera, objects or lights move: validate history by surface and clip it to the
                              neighbourhood (YCoCg variance box); 0: a still scene accumulates everything */
    int max_history;       /* cap of the per-pixel history length n */
    int reset;             /* 1: no history (first frame, camera cut): start from this frame's sample */
    int filter;            /* history fetch: TAA_BILINEAR or TAA_CATMULL_ROM */
    int dilate;            /* 1: take the motion of the nearest surface in the 3x3 neighbourhood */
    int fresh_fill;        /* 1: a moving pixel without history shows its surface's 3x3 mean (taa/fresh_fill.h) */
    float sweep_open;      /* motion blur: the shutter from this frame's time, in frames (taa/sweep.h); */
    float sweep_close;     /* open == close: a sharp frame */
    int clip_surface;      /* 1: the clipping box from the neighbours on the pixel's surface only (taa/clip_box.h) */
    int pad2;
} TaaParams;               /* 64 bytes */

/* One iteration of the real-time filter (filter/atrous.cl). */
typedef struct {
    int step;              /* tap spacing in pixels: 1, 2, 4, ... */
    float sigma_l;         /* luminance edge stop, in standard deviations of the centre */
    float sigma_z;         /* view-depth edge stop, relative to the centre's depth, per pixel of spacing */
    int pad0;
} AtrousParams;            /* 16 bytes */

/* Counters of numerical guards, accumulated by the kernels with atomic_inc. */

#endif
