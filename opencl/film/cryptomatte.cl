/* Cryptomatte's samples (render/cryptomatte.py): per pixel and kind (0: object, 1: material) `levels` slots of
 * (id + 1, samples), slot s of kind k of pixel i at slots[(k * pixels + i) * levels + s]; each still frame counts the
 * object and the material its camera ray hit in the slot of that id, or the first empty one (an id that finds
 * every slot taken by others is not counted). Misses and lights seen count in no slot. */

__kernel void accumulate_cryptomatte(const __global GSample* gbuf, __global uint2* slots, FrameParams frame_params,
                                     int levels)
{
    int i = get_global_id(0);
    if (i >= frame_params.pixels) return;
    const __global GSample* g = gbuf + i;
    if (as_int(g->normal.w) < 0) return;
    uint ids[2] = {((uint)as_int(g->albedo.w) & LINK_OBJECT_MASK) + 1u, (uint)as_int(g->gnormal.w) + 1u};
    for (int k = 0; k < 2; ++k) {
        __global uint2* s = slots + ((size_t)k * (size_t)frame_params.pixels + (size_t)i) * (size_t)levels;
        for (int n = 0; n < levels; ++n) {
            uint2 v = s[n];
            if (v.x == ids[k] || v.x == 0u) {
                s[n] = (uint2)(ids[k], v.y + 1u);
                break;
            }
        }
    }
}
