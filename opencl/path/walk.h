/* The walk of a path from a vertex it has reached: at every vertex Russian roulette, a BSDF sample, the ray, the
 * emitters that ray meets (path/emitters.h) and, at the vertex it reaches, NEE (path/nee.h), until a bound of
 * Cycles' Light Paths, roulette, or the ray's escape ends it. The path pass (path/path.cl) walks from the primary hit;
 * ReSTIR GI's initial pass (restir_gi/initial.cl) from the secondary vertex x1, to find the radiance L_o leaving it.
 *
 * A path that has scattered n times carries light of n bounces; Max Bounces B keeps n <= B (total), and Diffuse /
 * Glossy / Transmission bound the scatterings of each kind (the BSDF's part drawn: Lambert or a lobe; a lobe's
 * scatter through the surface, a refraction, is a transmission bounce, as in Cycles). A scatter past a bound still
 * counts the emitters its ray meets (they are light of the bounces before it) and ends the path. Russian roulette
 * from bounce min_bounces + 2 on survives with q = min(1, sqrt(max throughput)) and divides by q (Cycles'
 * continuation probability); Clamp Indirect scales a contribution whose rgb sum, as it reaches the pixel, exceeds 3x
 * the clamp down to it (Cycles' per-contribution clamp). The ray from the primary hit meets only light that the
 * direct estimators already have, so its emitters are left out. */
#ifndef RESTIRCL_PATH_WALK_H
#define RESTIRCL_PATH_WALK_H

/* Where a path stands: the vertex it reached, its throughput T since the walk's start, and the scatterings so far
 * (all, diffuse, glossy). prefix: the throughput before the walk's start, which only the clamp reads (the
 * contribution as it reaches the pixel is prefix * T * c); 1 for a walk from the primary hit. */
typedef struct {
    Surface s;
    float3 T;
    float3 prefix;
    int bounces;
    int diffuse;
    int gloss;
#ifdef HAS_TRANSMISSION
    int transmission;     /* refractions (a scatter off a lobe to the other side of the surface) */
#endif
#ifdef HAS_LIGHT_PASSES
    float3 pass_diffuse;  /* the diffuse share of the first scatter's BSDF (film/light_passes.h), which all its light
                             takes; 0 until it scatters (a zero initialiser leaves it 0) */
    int pass_through;     /* whether the first scatter went through the surface: all its light is transmission's */
#endif
#ifdef HAS_LIGHT_GROUPS
    GroupLight groups;    /* the light it gathered by light group (film/light_groups.h); 0 from a zero initialiser */
#endif
} PathState;

/* The factor that scales c down where its rgb sum as it reaches the pixel (prefix * c) exceeds 3x the clamp (0: off). */
inline float path_clamp_scale(float3 c, float3 prefix, float clamp)
{
    float3 seen = prefix * c;
    float sum = seen.x + seen.y + seen.z;
    return (clamp > 0.0f && sum > 3.0f * clamp) ? 3.0f * clamp / sum : 1.0f;
}

/* c clamped by path_clamp_scale */
inline float3 path_clamp(float3 c, float3 prefix, float clamp)
{
    float3 seen = prefix * c;
    float sum = seen.x + seen.y + seen.z;
    return (clamp > 0.0f && sum > 3.0f * clamp) ? c * (3.0f * clamp / sum) : c;
}

/* The path's estimators at a scene's buffers: what its vertices, NEE and emitter tests read. */
typedef struct {
    const SceneSurfaces* sc;
    const __global BVHNode* nodes;
    const __global Light* lights;
    const __global int* tri_light;
    const LightPick* lp;
    BsdfSource hits;
    const PathParams* params;
} PathScene;

/* NEE at the vertex the path stands on, times T (the light of this vertex), clamped; also to the light's group. */
inline float3 path_vertex_light(const PathScene* ps, PathState* st, uint* rng, const Qmc* q)
{
    const PathParams* p = ps->params;
    if (!(p->sampler.light_count > 0)) return (float3)(0.0f);
#ifdef HAS_TRANSMISSION  /* no light sample can meet smooth glass: no NEE there (Cycles' rule for singular lobes) */
    if (surface_is_singular(&st->s)) return (float3)(0.0f);
#endif
    int light;
    float3 c = path_clamp(st->T * path_nee(&st->s, ps->lights, ps->lp, p->sampler.slot_count, ps->hits, ps->nodes,
                                           ps->sc->tris, p->light_threshold, rng, q, QMC_PATH_LIGHT(st->bounces),
                                           &light),
                          st->prefix, p->clamp_indirect);
#ifdef HAS_LIGHT_GROUPS
    GROUP_ADD(&st->groups, ps->lights, &ps->lights[light], c);
#endif
    return c;
}

/* Walk on from st (whose vertex's own NEE is already counted) until the path ends; returns the light it gathers
 * (in st's units: times T). */
inline float3 path_walk(const PathScene* ps, PathState* st, uint* rng, const Qmc* q)
{
    const PathParams* p = ps->params;
    const bool nee = p->sampler.light_count > 0;
    float3 L = (float3)(0.0f);
#ifdef HAS_TRANSMISSION
    /* The emitters the first ray meets are the direct estimator's (its BSDF candidates'); where the primary hit is
     * smooth glass and the method draws no BSDF candidates there (reference, uniform, light array, bsdf_sampling
     * off), no light sample reaches them either, so the path counts them (weight 1: p_light is 0 at singular s). */
    const bool first_uncounted = st->bounces == 0 && surface_is_singular(&st->s)
                                 && bsdf_source_at(&st->s, ps->hits).count == 0;
#else
    const bool first_uncounted = false;
#endif
    while (st->s.valid) {
        float u0 = rng_next(rng), u1 = rng_next(rng), u_rr = rng_next(rng);
        if (q->on) {
            float2 u = qmc_pair(q, QMC_PATH_BSDF(st->bounces));
            u0 = u.x;
            u1 = u.y;
        }
        /* Russian roulette at this vertex, before it scatters */
        if (st->bounces > p->min_bounces + 1) {
            float keep = fmin_f(sqrt(fmax_f(st->T.x, fmax_f(st->T.y, st->T.z))), 1.0f);
            if (!(u_rr < keep)) break;
#ifndef PATH_ROULETTE_WITHOUT_DIVIDE  /* defined only by the negative control of tests/render/test_paths.py */
            st->T /= keep;
#endif
        }
        float3 wi;
        float pdf;
        int part;
        float3 f = bsdf_sample_part(&st->s, st->s.wo, u0, u1, &wi, &pdf, &part);
        float cos_n = dot3(st->s.n, wi);
#ifdef HAS_TRANSMISSION  /* a refracting lobe sends the path through the surface: the cosine's magnitude counts */
        const bool refracted = cos_n < 0.0f;
        cos_n = abs_f(cos_n);
#endif
        if (!(pdf > 0.0f) || !(cos_n > 0.0f)) break;
        const float3 T_before = st->T;
/* on through a smooth thin wall: the vertex before counted its light (path/thin_wall_emitters.h); the negative control
 * TEST_THIN_WALL_COUNTED_TWICE (tests/bias_controls.py) counts it again */
#if defined(HAS_THIN_SHADOW) && !defined(TEST_THIN_WALL_COUNTED_TWICE)
        const bool counted = st->bounces > 0 && thin_wall_passed(ps->sc->tris, &st->s, part, wi);
#else
        const bool counted = false;
#endif
#ifdef HAS_LIGHT_PASSES
#ifndef LIGHT_PASSES_BY_LAST_BOUNCE  /* defined only by the negative control of tests/render/test_light_passes.py */
        if (st->bounces == 0)
#endif
        {
            st->pass_diffuse = light_pass_share(f, bsdf_eval_diffuse(&st->s, wi));
            st->pass_through = light_pass_through(&st->s, wi);
        }
#endif
        st->T *= f * (cos_n / pdf);
        ++st->bounces;
#ifdef HAS_TRANSMISSION
        if (part >= 0 && refracted) ++st->transmission; else
#endif
        if (part < 0) ++st->diffuse; else ++st->gloss;
        bool last = st->bounces > p->max_bounces || st->diffuse > p->max_diffuse || st->gloss > p->max_glossy;
#ifdef HAS_TRANSMISSION
        last = last || st->transmission > p->max_transmission;
#endif
        Hit h = trace_closest(ps->nodes, ps->sc->tris, path_ray_origin(ps->sc->tris, &st->s, wi), wi, INFINITY);
        if ((st->bounces > 1 || first_uncounted) && nee && !counted) {
            GroupLight eg;  /* each emitter's share, scaled as the sum is clamped */
            group_light_clear(&eg);
            float3 em = T_before * path_emitters(&st->s, wi, h, ps->nodes, ps->sc->tris, ps->lights, ps->tri_light,
                                                     ps->lp, ps->hits, &eg);
            L += path_clamp(em, st->prefix, p->clamp_indirect);
#ifdef HAS_LIGHT_GROUPS
            group_light_merge(&st->groups, &eg, T_before * path_clamp_scale(em, st->prefix, p->clamp_indirect));
#endif
        }
        if (last || h.prim < 0 || !(fmax_f(st->T.x, fmax_f(st->T.y, st->T.z)) > 0.0f)) break;
#ifdef HAS_TRANSPARENCY  /* the path's count of transparent surfaces: those of the vertices before, and this ray's */
        const int passed = st->s.passed;
        st->s = path_vertex(ps->sc, h, wi);
        st->s.passed += passed;
#else
        st->s = path_vertex(ps->sc, h, wi);
#endif
        L += path_vertex_light(ps, st, rng, q);
    }
    return L;
}

#endif
