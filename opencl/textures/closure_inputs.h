/* A closure's inputs at a surface point, as the BSDF resolve (bsdf/bsdf.h) takes them: its constants, or the value of
 * the texture node an input is linked to (texture.h, when HAS_TEXTURES). Read once per primary hit; the shading
 * passes read the resolved lobes from the G-buffer, never the textures. */
#ifndef RESTIRCL_CLOSURE_INPUTS_H
#define RESTIRCL_CLOSURE_INPUTS_H

#include "textures/bump.h"

typedef struct {
    float3 base;        /* Base Color / Color */
    float3 tint;        /* Specular Tint */
    float metallic;
    float roughness;
    float ior;
    float specular;     /* Specular IOR Level */
    float weight;       /* of this closure in the material's sum (Mix: 1 - f or f; Add: 1) */
    int kind;           /* CLOSURE_* */
    int multiscatter;   /* 1: multiscatter GGX; 0: GGX */
    float3 normal;      /* shading normal facing the camera (its Normal Map's, else the surface's); closure_constants
                           leaves it 0: the caller's surface normal */
    float transmission; /* the Principled BSDF's Transmission Weight */
    int backfacing;     /* 1: the ray met the surface's back face (a refracting closure leaves its medium there); the
                           caller sets it, closure_constants leaves it 0 */
    int thin_wall;      /* 1: the Principled BSDF's Thin Wall (Blender 5.3): its transmission is a sheet */
    float film_thickness; /* Thin Film Thickness (nm; at most THIN_FILM_CUTOFF: no film, bsdf/thin_film.h) */
    float film_ior;       /* Thin Film IOR */
} ClosureInputs;

/* The constants of closure c (texture inputs not applied). */
inline ClosureInputs closure_constants(const __global Closure* c)
{
    ClosureInputs in;
    float4 base = c->base, spec = c->spec;
    int4 kind = c->kind;
    in.base = base.xyz;
    in.metallic = base.w;
    in.roughness = spec.x;
    in.ior = spec.y;
    in.specular = spec.z;
    in.weight = kind.z ? 1.0f - spec.w : spec.w;
    in.tint = c->tint.xyz;
    in.kind = kind.x;
    in.multiscatter = kind.y;
    in.normal = (float3)(0.0f);
    in.transmission = c->glass.x;
    in.backfacing = 0;
    in.thin_wall = c->glass.w != 0.0f;
    in.film_thickness = c->glass.y;
    in.film_ior = c->glass.z;
    return in;
}

/* the number a value input reads from the program ending at node root */
inline float tex_input_number(const __global TexNode* nodes, const __global TexImage* images,
                              const __global float4* texels, int root, const TexPoint* tp)
{
    return tex_number(nodes, root, texture_eval(nodes, images, texels, root, tp));
}

/* The inputs of closure c at the surface point tp: the constants, with every input that has a texture node
 * (c->tex, c->tex2) replaced by the node's value; a colour feeding a value input is read as its luminance, as
 * Blender converts it (a node that gives a number, as it is: tex_number), and clamped to the input's range as Cycles
 * clamps it (Metallic, Roughness and the Mix factor to [0, 1], colours and Specular IOR Level to >= 0). */
inline ClosureInputs closure_inputs(const __global Closure* c, const __global TexNode* nodes,
                                    const __global TexImage* images, const __global float4* texels,
                                    const TexPoint* tp)
{
    ClosureInputs in = closure_constants(c);
    int4 tex = c->tex, tex2 = c->tex2;
    in.normal = tp->ns;
    float3 zero = (float3)(0.0f);
    if (tex.x >= 0) in.base = fmax(texture_eval(nodes, images, texels, tex.x, tp).xyz, zero);
    if (tex.y >= 0) in.metallic = clamp_f(tex_input_number(nodes, images, texels, tex.y, tp), 0.0f, 1.0f);
    if (tex.z >= 0) in.roughness = clamp_f(tex_input_number(nodes, images, texels, tex.z, tp), 0.0f, 1.0f);
    if (tex.w >= 0) in.specular = fmax_f(tex_input_number(nodes, images, texels, tex.w, tp), 0.0f);
    if (tex2.x >= 0) in.tint = fmax(texture_eval(nodes, images, texels, tex2.x, tp).xyz, zero);
    if (tex2.y >= 0) in.normal = texture_normal(nodes, images, texels, tex2.y, tp);
    if (tex2.z >= 0) {
        float f = clamp_f(tex_input_number(nodes, images, texels, tex2.z, tp), 0.0f, 1.0f);
        in.weight = c->kind.z ? 1.0f - f : f;
    }
    return in;
}

#endif
