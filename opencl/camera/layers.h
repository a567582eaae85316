/* The weighted layers of a still (python/restircl/render/layers.py): a pixel's camera ray shades every partly
 * transparent surface it meets with weight a (its coverage) and goes on through it with weight 1 - a, as Cycles
 * mixes a surface with a white Transparent BSDF, instead of stopping there with probability a (bvh/transparent.h,
 * "stochastic"). The G-buffer holds one surface per pixel, so a frame runs its shading stages once per layer: layer
 * k's camera ray starts where layer k - 1's passed its surface, stops at the first surface of coverage above 0
 * (surfaces of coverage 0 are passed whole), and the pixel's sample gains the layer's sample times its weight
 * (GSample.layer.y; still/layers.cl). The rim of a leaf card is then its share of the leaf plus its share of what
 * lies behind in every sample, where a stochastic choice between the two leaves the variance of a coin.
 *
 * Each surface passed counts as a transparent bounce, as in Cycles: a layer that starts after T passes
 * (TRANSPARENT_MAX_BOUNCES) ends at its first surface, black and opaque, and a shadow ray from a surface reached
 * after b passes may pass T - b more (Surface.passed). The state between layers, per pixel, two float4: the ray's
 * origin and its remaining weight; the surfaces passed (int bits). */
#ifndef RESTIRCL_CAMERA_LAYERS_H
#define RESTIRCL_CAMERA_LAYERS_H

#ifdef HAS_TRANSPARENCY

typedef struct {
    float3 o;       /* where this layer's camera ray starts */
    float weight;   /* what the surfaces before let through: the share of the pixel this layer and those behind it
                       have */
    int passed;     /* surfaces passed before it */
} CameraLayer;

/* Layer `layer` of pixel i, whose camera ray starts at o (layer 0) or where the last layer left it. */
inline CameraLayer camera_layer(const __global float4* layers, int i, int layer, float3 o)
{
    CameraLayer c = {o, 1.0f, 0};
    if (layer > 0) {
        float4 a = layers[2 * i], b = layers[2 * i + 1];
        c.o = a.xyz;
        c.weight = a.w;
        c.passed = as_int(b.x);
    }
    return c;
}

/* The layer's surface along d: the first of coverage above 0, or where the bound ends the path (prim
 * TRANSPARENT_ENDED), or a miss; hit.passed counts the surfaces of the layers before too. */
inline Hit camera_layer_trace(const __global BVHNode* nodes, const __global Tri* tris, const CameraLayer* c, float3 d)
{
    bool ended;
    /* the first layer as trace_camera counts; a later one has passed c->passed >= 1 already */
    Hit h = c->passed == 0
                ? trace_through(nodes, tris, c->o, d, INFINITY, true, TRANSPARENT_MAX_BOUNCES, LAYER_STOPS, &ended)
                : trace_through(nodes, tris, c->o, d, INFINITY, false, TRANSPARENT_MAX_BOUNCES - c->passed,
                                LAYER_STOPS, &ended);
    if (ended) h.prim = TRANSPARENT_ENDED;
    h.passed += c->passed;
    return h;
}

/* The layer's weight in the pixel, with its surface's coverage a (1 for a miss, a light, the bound's end): a times
 * what reached it; where a < 1 the next layer starts past it with the rest, and *continuing counts it (one of two
 * counters, by the layer's parity: still/layers.cl clears the other for the next layer). */
inline float camera_layer_next(const __global Tri* tris, __global float4* layers, volatile __global int* continuing,
                               int i, const CameraLayer* c, Hit h, float3 d, float a)
{
#ifdef TEST_LAYER_WEIGHT_WHOLE  /* negative control of the tests only (tests/bias_controls.py): the surface whole */
    float w = c->weight;
#else
    float w = c->weight * a;
#endif
    float rest = c->weight * (1.0f - a);
    if (h.prim >= 0 && rest > 0.0f) {
        layers[2 * i] = (float4)(transparent_continue(tris, h, c->o, d), rest);
        layers[2 * i + 1] = (float4)(as_float(h.passed + 1), 0.0f, 0.0f, 0.0f);
        atomic_inc(continuing);
    } else {
        layers[2 * i] = (float4)(c->o, 0.0f);
    }
    return w;
}

/* A pixel whose layers are done: a G-sample that the shading stages pass over (a miss that sees nothing) and whose
 * weight is 0. */
inline void camera_layer_none(__global GSample* g)
{
    GSample e;
    e.pos = (float4)(0.0f, 0.0f, 0.0f, INFINITY);
    e.normal = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
    e.gnormal = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
    e.albedo = (float4)(0.0f, 0.0f, 0.0f, as_float(-1));
    e.emission = (float4)(0.0f);
    e.motion = (float4)(0.0f);
    e.layer = (float4)(0.0f);
    *g = e;
}

#endif
#endif
