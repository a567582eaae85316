/* A textured material at the primary hit (HAS_TEXTURES): its emission, the diffuse albedo the G-buffer stores (the
 * weighted sum of its closures' base colours: without HAS_GLOSSY every closure is diffuse), and the shading normal
 * of its first normal-mapped closure. With HAS_GLOSSY the BSDF resolve reads each closure's closure_inputs. */
#ifndef RESTIRCL_TEXTURE_MATERIAL_H
#define RESTIRCL_TEXTURE_MATERIAL_H

inline void texture_material(const __global Material* m, const __global Closure* closures,
                             const __global TexNode* nodes, const __global TexImage* images,
                             const __global float4* texels, TexPoint* tp, float3* albedo, float3* emission)
{
    int4 info = m->info;
    if (info.z >= 0)
        *emission = fmax(texture_eval(nodes, images, texels, info.z, tp).xyz, (float3)(0.0f)) * m->emission.xyz;
    float3 sum = (float3)(0.0f), ns = tp->ns;
    bool mapped = false;
    for (int k = 0; k < info.y; ++k) {
        const __global Closure* c = closures + info.x + k;
        ClosureInputs in = closure_inputs(c, nodes, images, texels, tp);
        sum += in.weight * in.base;
        if (!mapped && c->tex2.y >= 0) {
            ns = in.normal;
            mapped = true;
        }
    }
    *albedo = sum;
    tp->nb = tp->ns;
    tp->ns = ns;
    tp->bumped = mapped;
}

#endif
