"""Half-float against float32 environment texels (environment/pack.py): the error half floats add on the built-in
`sky` scene, the device memory of each, and the frame time, the two formats side by side in one run.

- error: the same still render (RIS, `frames` frames, one seed) with each format; relMSE(half, float32) is what
  half's rounding adds (the draws coincide wherever the two tables agree), set beside relMSE(float32 seed 1,
  float32 seed 2), the noise two independent renders of that length differ by;
- memory: device bytes of the map and its table (lights/environment.data_bytes) for this map and a 16384 x 8192;
- time: ms per frame, the formats interleaved (A B A B ...) so that a loaded machine slows both alike, medians;
  and the texel reads alone: a kernel looking up the radiance of 16 x 2^18 random directions in a 1024 x 2048 map,
  timed by the process's CPU seconds (PoCL's threads are the process's), steadier than wall time under load.

Run: python -m restircl.eval.bench.environment_texels [--frames 64] [--width 160 --height 90] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from .environment import interleaved_still_ms

FORMATS = ("half", "float")


def _renderer(fmt: str, width: int, height: int, seed: int, method: str = "ris"):
    from ...lights import environment
    from ...render.pipeline import Renderer
    from ...scenes.hdri_sky import sky
    from ...settings.table import Settings

    old = environment.TEXEL_FORMAT
    environment.TEXEL_FORMAT = fmt
    try:
        r = Renderer(sky(width, height), Settings(method=method, seed=seed, taa=False))
        r.render_frame(0, still=True)  # build and upload with this format
    finally:
        environment.TEXEL_FORMAT = old
    assert r.device_scene.lights.environment is not None
    assert r.device_scene.lights.environment.stored.fmt == fmt
    return r


def error(frames: int, width: int, height: int) -> dict[str, float]:
    from ..metrics import rel_mse

    img = {}
    for fmt, seed in (("half", 1), ("float", 1), ("float", 2)):
        img[fmt, seed] = _renderer(fmt, width, height, seed).render_still(0, frames).color[..., :3].copy()
    added = rel_mse(img["half", 1], img["float", 1])
    noise = rel_mse(img["float", 2], img["float", 1])
    return {"frames": frames, "relmse_half_vs_float_same_seed": added, "relmse_float_seed2_vs_seed1": noise,
            "added_over_noise": added / noise if noise > 0 else float("nan")}


def memory() -> dict[str, int]:
    from ...lights import environment

    out = {}
    for h, w, kind in ((256, 512, environment.TABLE_KIND), (8192, 16384, "cdf")):
        for fmt in FORMATS:
            out[f"{w}x{h}_{kind}_{fmt}_bytes"] = environment.data_bytes(h, w, kind, fmt)
    return out


READ_SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
__kernel void read_env(const __global Light* lights, uint seed, __global float* out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, seed, 0u);
    float3 sum = (float3)(0.0f);
    for (int k = 0; k < 16; ++k) {
        float z = 2.0f * rng_next(&rng) - 1.0f, phi = 6.2831853f * rng_next(&rng);
        float r = sqrt(fmax(0.0f, 1.0f - z * z));
        sum += environment_radiance(&lights[0], (float3)(r * cos(phi), r * sin(phi), z));
    }
    out[i] = sum.x + sum.y + sum.z;
}
"""


def texel_reads(repeats: int, map_height: int = 1024, count: int = 1 << 18) -> dict[str, float]:
    import pyopencl as cl

    from ...core.device import get_device
    from ...core.program import build_program
    from ...environment.world import Environment
    from ...lights import environment
    from ...lights.device_lights import scene_lights
    from ...render.features import general_flags
    from ...scene.scene import Scene
    from ...scenes.hdri_sky import sky_map

    device = get_device()
    prog = build_program(device, general_flags(), source=READ_SRC)
    img = sky_map(map_height, 2 * map_height)
    bufs = {}
    for fmt in FORMATS:
        old = environment.TEXEL_FORMAT
        environment.TEXEL_FORMAT = fmt
        try:
            lights = scene_lights(Scene(environment=Environment(color=(1, 1, 1), image=img)), 0)
        finally:
            environment.TEXEL_FORMAT = old
        assert lights.environment is not None and lights.environment.stored.fmt == fmt
        data = lights.device_array()
        bufs[fmt] = cl.Buffer(device.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=data)
    out = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, 4 * count)
    kernel = cl.Kernel(prog, "read_env")
    cpu: dict[str, list[float]] = {fmt: [] for fmt in FORMATS}
    for r in range(repeats + 1):
        for fmt in FORMATS:
            c0 = time.process_time()
            kernel(device.queue, (count,), None, bufs[fmt], np.uint32(r), out)
            device.queue.finish()
            if r > 0:  # the first launch of each warms caches
                cpu[fmt].append(time.process_time() - c0)
    per_m = (1 << 20) / (16 * count)  # 16 lookups per work-item
    res = {f"reads_{fmt}_cpu_ms_per_M": 1e3 * float(np.median(v)) * per_m for fmt, v in cpu.items()}
    res["reads_half_over_float"] = res["reads_half_cpu_ms_per_M"] / res["reads_float_cpu_ms_per_M"]
    return res


def frame_times(repeats: int, frames: int, width: int, height: int) -> dict[str, float]:
    out = {}
    for method in ("ris", "restir"):
        rs = {fmt: _renderer(fmt, width, height, 1, method) for fmt in FORMATS}
        for fmt, ms in interleaved_still_ms(rs, repeats, frames).items():
            out[f"{method}_{fmt}_ms_per_frame"] = ms
        out[f"{method}_half_over_float"] = out[f"{method}_half_ms_per_frame"] / out[f"{method}_float_ms_per_frame"]
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=64, help="frames of each still for the error (%(default)s)")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=90)
    ap.add_argument("--repeats", type=int, default=5, help="interleaved rounds of the frame timing (%(default)s)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    result = {"load_before": os.getloadavg()[0], **error(a.frames, a.width, a.height), **memory(),
              **frame_times(a.repeats, 8, a.width, a.height), **texel_reads(a.repeats),
              "load_after": os.getloadavg()[0], "width": a.width, "height": a.height}
    print(json.dumps(result, indent=1))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
