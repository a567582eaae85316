/* A closure's inputs at a surface point, as the BSDF resolve (bsdf.h) takes them: its constants, or the value of
 * the texture node an input is linked to (texture.h, when HAS_TEXTURES). Read once per primary hit; the shading
 * passes read the resolved lobes from the G-buffer, never the textures. */
#ifndef RESTIRCL_CLOSURE_INPUTS_H
#define RESTIRCL_CLOSURE_INPUTS_H

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
    return in;
}

#endif
