"""Probe for docs/measurements/benchmarks.md ("Frame time"): does explicit SIMD across pixels pay on PoCL? A stand-alone
4-candidate triangle-light RIS loop, one pixel per work-item (float3 math, as the kernels are written), against 8
pixels per work-item in float8 lanes (light records gathered by scalar loads, branch-free selects). The random
numbers are keyed by the pixel, so both must give the same results.

    python -m tools.experiments.simd_probe
"""

import time

import numpy as np
import pyopencl as cl
from restircl import get_device
from restircl.core.program import BASE_OPTIONS

d = get_device()
ctx, q = d.context, d.queue
SRC = r'''
inline uint hash(uint x) { x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16; return x; }
inline float u01(uint* s) { *s = hash(*s + 0x9e3779b9U); return (float)(*s >> 8) * (1.0f / 16777216.0f); }
inline uint8 hash8(uint8 x) { x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16; return x; }
inline float8 u01_8(uint8* s) { *s = hash8(*s + 0x9e3779b9U); return convert_float8(*s >> 8) * (1.0f / 16777216.0f); }

__kernel void cand1(__global const float4* pos, __global const float4* nrm, __global const float4* lights,
                    int nlights, __global float4* out)
{
    int i = get_global_id(0);
    float3 x = pos[i].xyz, n = nrm[i].xyz;
    uint s = (uint)i * 747796405u;
    float wsum = 0.0f, best = 0.0f; int pick = -1;
    for (int k = 0; k < NCAND; ++k) {
        int l = (int)(u01(&s) * (float)nlights);
        float3 p = lights[3 * l].xyz, a = lights[3 * l + 1].xyz, b = lights[3 * l + 2].xyz;
        float area = lights[3 * l + 2].w;
        float su = sqrt(u01(&s)), v = u01(&s);
        float3 y = p + a * (su * (1.0f - v)) + b * (su * v);
        float3 c = (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
        float3 ny = c * (1.0f / sqrt(c.x * c.x + c.y * c.y + c.z * c.z));
        float3 dd = y - x;
        float d2 = dd.x * dd.x + dd.y * dd.y + dd.z * dd.z;
        float dist = sqrt(d2);
        float3 wi = dd / dist;
        float cx = n.x * wi.x + n.y * wi.y + n.z * wi.z;
        float cl = -(ny.x * wi.x + ny.y * wi.y + ny.z * wi.z);
        cl = cl < 0.0f ? -cl : cl;
        float t = (cx > 0.0f && cl > 0.0f && d2 > 1e-30f) ? cx * cl / d2 * area : 0.0f;
        wsum += t;
        float r = u01(&s);
        if (r * wsum < t) { pick = l; best = t; }
    }
    out[i] = (float4)(wsum, best, (float)pick, 0.0f);
}

#define G8(buf, idx, comp) (float8)(buf[idx.s0].comp, buf[idx.s1].comp, buf[idx.s2].comp, buf[idx.s3].comp, \
                                    buf[idx.s4].comp, buf[idx.s5].comp, buf[idx.s6].comp, buf[idx.s7].comp)
__kernel void cand8(__global const float4* pos, __global const float4* nrm, __global const float4* lights,
                    int nlights, __global float4* out)
{
    int i0 = get_global_id(0) * 8;
    int8 pi = (int8)(i0) + (int8)(0, 1, 2, 3, 4, 5, 6, 7);
    float8 xx = G8(pos, pi, x), xy = G8(pos, pi, y), xz = G8(pos, pi, z);
    float8 nx = G8(nrm, pi, x), ny_ = G8(nrm, pi, y), nz = G8(nrm, pi, z);
    uint8 s = convert_uint8(pi) * 747796405u;
    float8 wsum = 0.0f, best = 0.0f, pick = -1.0f;
    for (int k = 0; k < NCAND; ++k) {
        int8 l = convert_int8(u01_8(&s) * (float)nlights);
        int8 l0 = 3 * l, l1 = 3 * l + 1, l2 = 3 * l + 2;
        float8 px = G8(lights, l0, x), py = G8(lights, l0, y), pz = G8(lights, l0, z);
        float8 ax = G8(lights, l1, x), ay = G8(lights, l1, y), az = G8(lights, l1, z);
        float8 bx = G8(lights, l2, x), by = G8(lights, l2, y), bz = G8(lights, l2, z), area = G8(lights, l2, w);
        float8 su = sqrt(u01_8(&s)), v = u01_8(&s);
        float8 wa = su * (1.0f - v), wb = su * v;
        float8 yx = px + ax * wa + bx * wb, yy = py + ay * wa + by * wb, yz = pz + az * wa + bz * wb;
        float8 cx_ = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
        float8 inv = 1.0f / sqrt(cx_ * cx_ + cy * cy + cz * cz);
        float8 dx = yx - xx, dy = yy - xy, dz = yz - xz;
        float8 d2 = dx * dx + dy * dy + dz * dz;
        float8 dist = sqrt(d2);
        float8 wx = dx / dist, wy = dy / dist, wz = dz / dist;
        float8 cosx = nx * wx + ny_ * wy + nz * wz;
        float8 cosl = -(cx_ * inv * wx + cy * inv * wy + cz * inv * wz);
        cosl = fabs(cosl);
        float8 t = select((float8)(0.0f), cosx * cosl / d2 * area, (cosx > 0.0f) & (cosl > 0.0f) & (d2 > 1e-30f));
        wsum += t;
        float8 r = u01_8(&s);
        int8 take = r * wsum < t;
        pick = select(pick, convert_float8(l), take);
        best = select(best, t, take);
    }
    float tmp[3][8];
    vstore8(wsum, 0, tmp[0]);
    vstore8(best, 0, tmp[1]);
    vstore8(pick, 0, tmp[2]);
    for (int j = 0; j < 8; ++j) out[i0 + j] = (float4)(tmp[0][j], tmp[1][j], tmp[2][j], 0.0f);
}
'''


def main() -> None:
    n, n_lights = 640 * 360, 10_000
    rng = np.random.default_rng(0)
    pos = np.zeros((n, 4), np.float32)
    pos[:, :2] = rng.uniform(-20, 20, (n, 2))
    nrm = np.zeros((n, 4), np.float32)
    nrm[:, 2] = 1
    lights = np.zeros((n_lights * 3, 4), np.float32)  # per light: v0, e1, e2 (w: area)
    lights[0::3, :3] = np.column_stack([rng.uniform(-20, 20, (n_lights, 2)), rng.uniform(0.5, 5, n_lights)])
    lights[1::3, :3] = rng.normal(0, 0.3, (n_lights, 3))
    lights[2::3, :3] = rng.normal(0, 0.3, (n_lights, 3))
    lights[2::3, 3] = 0.05
    mf = cl.mem_flags
    bufs = [cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=a) for a in (pos, nrm, lights)]
    out = cl.Buffer(ctx, mf.WRITE_ONLY, n * 16)
    prg = cl.Program(ctx, SRC).build(options=[*BASE_OPTIONS, "-DNCAND=4"])
    res = {}
    print(f"device: {d.label}")
    for name, items in (("cand1", n), ("cand8", n // 8)):
        kernel = getattr(prg, name)
        args = (q, (items,), (64,), *bufs, np.int32(n_lights), out)
        for _ in range(2):
            kernel(*args)
        q.finish()
        times = []
        for _ in range(15):
            t = time.perf_counter()
            kernel(*args)
            q.finish()
            times.append(time.perf_counter() - t)
        o = np.empty((n, 4), np.float32)
        cl.enqueue_copy(q, o, out)
        res[name] = o
        print(f"{name}: {np.median(times) * 1e3:.2f} ms (median of 15)")
    a, b = res["cand1"], res["cand8"]
    print(f"identical results: {bool(np.array_equal(a, b))}")


if __name__ == "__main__":
    main()
