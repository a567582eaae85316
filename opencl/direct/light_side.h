/* Which side of a surface its light comes from. A light evaluation (lights/lights.h) gives a contribution only to a
 * shading point whose normal faces the light; a surface whose BSDF refracts (a dielectric lobe that transmits,
 * bsdf/microfacet_dielectric.h) also takes light from behind, through its transmission, so a light there is
 * evaluated about the flipped normal (its cosine |cos|). Builds without refracting lobes (no HAS_TRANSMISSION)
 * evaluate about the normal alone, as before. Every shading site that evaluates a light at a surface (the target
 * function, NEE, the emitters a path's rays meet) goes through surface_light_eval. */
#ifndef RESTIRCL_DIRECT_LIGHT_SIDE_H
#define RESTIRCL_DIRECT_LIGHT_SIDE_H

#ifdef HAS_TRANSMISSION
/* Whether the BSDF of s transmits light from behind it */
inline bool surface_transmits(const Surface* s)
{
    for (int k = 0; k < s->mat.lobes; ++k) {
        const Lobe* l = &s->mat.lobe[k];
        if (lobe_kind(l) == LOBE_MICROFACET_DIELECTRIC && microfacet_dielectric_transmits(l)) return true;
        if (lobe_kind(l) == LOBE_THIN_DIELECTRIC && thin_dielectric_transmits(l)) return true;  /* a thin wall */
    }
    return false;
}

/* Whether s scatters through smooth dielectric or thin dielectric lobes alone (Cycles' singular glass: Roughness^4
 * <= 2e-10, no diffuse part): no light sample can meet such a lobe, so a path does no next-event estimation there
 * (path/walk.h) and the emitters its next ray meets take all the weight (path/emitters.h). */
inline bool surface_is_singular(const Surface* s)
{
    if (s->mat.lobes == 0 || s->mat.albedo.x + s->mat.albedo.y + s->mat.albedo.z > 0.0f) return false;
    for (int k = 0; k < s->mat.lobes; ++k) {
        const Lobe* l = &s->mat.lobe[k];
        if (lobe_kind(l) == LOBE_THIN_DIELECTRIC && thin_dielectric(l).smooth != 0.0f) continue;  /* smooth thin wall */
        if (lobe_kind(l) != LOBE_MICROFACET_DIELECTRIC || microfacet_dielectric(l).smooth == 0.0f) return false;
    }
    return true;
}
#endif

/* The normal by which the light pick ranks lights at s (lights/tree.h light_tree_importance): s->n, or twice it
 * where s transmits, the mark of a surface that takes light from both sides. The pick and its pdf (light_pick_pdf,
 * for the MIS weights) take the same, so they stay consistent. */
inline float3 light_pick_normal(const Surface* s)
{
#ifdef HAS_TRANSMISSION
    if (surface_transmits(s)) return 2.0f * s->n;
#endif
    return s->n;
}

/* light_eval of sample (u, v) of light rec at surface s: about s->n, or, where s transmits and the light lies
 * behind it, about -s->n */
inline bool surface_light_eval(const Surface* s, const __global Light* rec, float u, float v, LightEval* e)
{
    if (light_eval(rec, u, v, s->x, s->n, e)) return true;
#ifdef HAS_TRANSMISSION
    return surface_transmits(s) && light_eval(rec, u, v, s->x, -s->n, e);
#else
    return false;
#endif
}

#endif
