/* Light groups (HAS_LIGHT_GROUPS = the number of groups; python/restircl/lights/light_groups.py): one plane per
 * group after the light passes' planes (film/light_passes.h), plane LPASS_COUNT + g of pixel i at
 * lp[(LPASS_COUNT + g) * pixels + i], holding the light of the emitters of group g: what the camera sees of them
 * (the primary pass starts the planes with it), their direct light (the direct estimators add it, each contribution
 * to the group of its light) and their bounced light (the path pass adds it). Every contribution to the pixel's
 * sample goes to the group of the light it came from, clamped as it is clamped there, so where every emitter is in
 * a group the planes add up to the sample. An emitter's group is in its link record (lights/linking.h), -1: none. */
#ifndef RESTIRCL_FILM_LIGHT_GROUPS_H
#define RESTIRCL_FILM_LIGHT_GROUPS_H

#ifdef HAS_LIGHT_GROUPS
#define LIGHT_GROUP_COUNT HAS_LIGHT_GROUPS
#define LPASS_PLANES (LPASS_COUNT + LIGHT_GROUP_COUNT)  /* the planes of the light passes' buffer */

/* A work-item's sums of light per group, before they go to the planes */
typedef struct {
    float3 c[LIGHT_GROUP_COUNT];
} GroupLight;

inline void group_light_clear(GroupLight* g)
{
    for (int k = 0; k < LIGHT_GROUP_COUNT; ++k) g->c[k] = (float3)(0.0f);
}

/* The group of light record rec (a record of `lights` or a copy): -1 for none */
inline int light_group(const __global Light* lights, const __global Light* rec)
{
    uint k = (uint)light_flags(rec) >> LINK_SHIFT;
    return k ? as_int(lights[k].a.x) : -1;
}

/* c to group `group` (-1: none); NaN or Inf as 0, as the sample's guard makes them */
inline void group_light_add(GroupLight* g, int group, float3 c)
{
    if (group >= 0 && group < LIGHT_GROUP_COUNT && finite3_f(c)) g->c[group] += c;
}

/* every group of h, times k, to g */
inline void group_light_merge(GroupLight* g, const GroupLight* h, float3 k)
{
    for (int n = 0; n < LIGHT_GROUP_COUNT; ++n) g->c[n] += h->c[n] * k;
}

/* The planes of pixel i start with what the camera sees: emission e of group `group` */
inline void light_groups_seen(__global float4* lp, int pixels, int i, int group, float3 e)
{
    for (int k = 0; k < LIGHT_GROUP_COUNT; ++k)
        lp[(LPASS_COUNT + k) * pixels + i] = (float4)(k == group && finite3_f(e) ? e : (float3)(0.0f), 0.0f);
}

/* The planes of pixel i, times k (Clamp Direct's scale of what the camera sees; 1: unchanged), plus g */
inline void light_groups_add(__global float4* lp, int pixels, int i, const GroupLight* g, float k)
{
    for (int n = 0; n < LIGHT_GROUP_COUNT; ++n) {
        __global float4* p = lp + (LPASS_COUNT + n) * pixels + i;
        *p = (float4)(p->xyz * k + g->c[n], 0.0f);
    }
}

/* contribution c of light record rec to g */
#define GROUP_ADD(g, lights, rec, c) group_light_add((g), light_group((lights), (rec)), (c))
#else  /* no groups: nothing to sum, nothing written */
#define LPASS_PLANES LPASS_COUNT
typedef struct {
    int unused;
} GroupLight;
#define GROUP_ADD(g, lights, rec, c) ((void)(g))
inline void group_light_clear(GroupLight* g) { (void)g; }
inline void group_light_merge(GroupLight* g, const GroupLight* h, float3 k)
{
    (void)g;
    (void)h;
    (void)k;
}
inline void light_groups_add(__global float4* lp, int pixels, int i, const GroupLight* g, float k)
{
    (void)lp;
    (void)pixels;
    (void)i;
    (void)g;
    (void)k;
}
#endif

#endif
