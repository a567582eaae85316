/* The per-pixel light pick of a still render (lights/pick_table.h): per pixel, each light's unshadowed
 * contribution estimated from PICK_TABLE_POINTS points sampled on it as RIS samples them, mixed with the light
 * array's pdf, written as a row of cumulative 16-bit probabilities. Pixels whose camera ray missed, or whose
 * estimate is 0 or not finite, get the light array's pdf. */

__kernel void light_pick_table(const __global GSample* gbuf, const __global GlossySample* glossy,
                               const __global Light* lights, const __global float* light_pdf,
                               __global ushort* table, FrameParams frame_params, int light_count)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    const int n = min(light_count, PICK_TABLE_MAX);
    Surface s = surface_load(gbuf, glossy, i);
    float w[PICK_TABLE_MAX];
    float sum = 0.0f;
    uint rng = rng_seed((uint)i, frame_params.sample, frame_params.seed, 7u);
    for (int l = 0; l < n; ++l) {
        float acc = 0.0f;
        const __global Light* rec = &lights[l];
        int type = light_type(rec);
        if (s.valid && light_pdf[l] > 0.0f) {
            for (int k = 0; k < PICK_TABLE_POINTS; ++k) {
                float r0 = 0.5f * ((float)(k & 1) + rng_next(&rng)), r1 = 0.5f * ((float)(k >> 1) + rng_next(&rng));
                float py;
                LightEval e;
                float2 uv = light_sample_typed(rec, type, s.x, r0, r1, &py);
                float t = py > 0.0f ? target_of_record(&s, lights, rec, uv.x, uv.y, &e) : 0.0f;
                if (t > 0.0f) acc += t / py;
            }
        }
        w[l] = acc;
        sum += acc;
    }
    /* integer counts out of 65536: one for every light that emits, the rest by its probability (rounded down, the
     * remainder to the likeliest), so no emitting light rounds to 0 */
    bool own = sum > 0.0f && finite_f(sum);
    int count[PICK_TABLE_MAX];
    int emitting = 0;
    for (int l = 0; l < n; ++l) emitting += light_pdf[l] > 0.0f;
    float budget = (float)(PICK_TABLE_ONE - (uint)emitting);
    int total = 0, top = 0;
    for (int l = 0; l < n; ++l) {
        float p = own ? (1.0f - PICK_TABLE_FLOOR) * (w[l] / sum) + PICK_TABLE_FLOOR * light_pdf[l] : light_pdf[l];
        count[l] = light_pdf[l] > 0.0f ? 1 + (int)floor(min(p, 1.0f) * budget) : 0;
        total += count[l];
        if (count[l] > count[top]) top = l;
    }
    count[top] += (int)PICK_TABLE_ONE - total;
    __global ushort* row = table + (size_t)i * (size_t)(n - 1);
    int cum = 0;
    for (int l = 0; l < n - 1; ++l) {
        cum += count[l];
        row[l] = (ushort)min(cum, 65535);  /* a row is its own pdf: a last light of 0 counts may get 1 */
    }
}
