"""Which environment sampling table is faster on this device: the alias tables or the cumulative distributions
(environment/table.py). Two measurements, each with the kinds interleaved (A B A B ...) so that a loaded machine
slows both alike, medians reported:

- `draws`: a kernel drawing one environment sample per work-item (light_sample, 2^20 work-items) from a
  `map_height` x 2 map_height sky, i.e. the table's cost alone;
- `frames`: RIS and ReSTIR frames of the built-in `sky` scene (its 256 x 512 HDRI), the cost in a frame.

Run: python -m restircl.eval.bench.environment [--map-height 1024] [--repeats 5] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

DRAW_SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
__kernel void draw_env(const __global Light* lights, uint seed, __global float* out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, seed, 0u);
    float pdf;
    float2 uv = light_sample(&lights[0], (float3)(0.0f), rng_next(&rng), rng_next(&rng), &pdf);
    out[i] = uv.x + uv.y + pdf;
}
"""


def _with_kind(kind: str):
    from ...lights import environment

    environment.TABLE_KIND = kind


def bench_draws(map_height: int, repeats: int, count: int = 1 << 20) -> dict[str, float]:
    import pyopencl as cl

    from ...core.device import get_device
    from ...core.program import build_program
    from ...environment.world import Environment
    from ...lights.device_lights import scene_lights
    from ...render.features import general_flags
    from ...scene.scene import Scene
    from ...scenes.hdri_sky import sky_map

    device = get_device()
    prog = build_program(device, general_flags(), source=DRAW_SRC)
    img = sky_map(map_height, 2 * map_height)
    bufs = {}
    for kind in ("alias", "cdf"):
        _with_kind(kind)
        data = scene_lights(Scene(environment=Environment(color=(1, 1, 1), image=img)), 0).device_array()
        bufs[kind] = cl.Buffer(device.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=data)
    out = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, 4 * count)
    kernel = cl.Kernel(prog, "draw_env")
    times: dict[str, list[float]] = {"alias": [], "cdf": []}
    for r in range(repeats + 1):
        for kind in ("alias", "cdf"):
            t0 = time.perf_counter()
            kernel(device.queue, (count,), None, bufs[kind], np.uint32(r), out)
            device.queue.finish()
            if r > 0:  # the first launch of each warms caches
                times[kind].append(time.perf_counter() - t0)
    return {f"{k}_ms_per_M_draws": 1e3 * float(np.median(v)) * (1 << 20) / count for k, v in times.items()}


def bench_frames(repeats: int, frames: int = 8, width: int = 320, height: int = 180) -> dict[str, float]:
    from ...render.pipeline import Renderer
    from ...scenes.hdri_sky import sky
    from ...settings.table import Settings

    out: dict[str, float] = {}
    for method in ("ris", "restir"):
        renderers = {}
        for kind in ("alias", "cdf"):
            _with_kind(kind)
            renderers[kind] = Renderer(sky(width, height), Settings(method=method, seed=1))
            renderers[kind].render_frame(0, still=True)  # build and upload
        for kind, ms in interleaved_still_ms(renderers, repeats, frames).items():
            out[f"{method}_{kind}_ms_per_frame"] = ms
    return out


def interleaved_still_ms(renderers: dict, repeats: int, frames: int) -> dict[str, float]:
    """Median ms per still frame of each renderer, the renderers taking turns (`frames` frames each, `repeats`
    rounds) so that a change of the machine's load falls on all of them alike."""
    times: dict[str, list[float]] = {k: [] for k in renderers}
    for _ in range(repeats):
        for k, r in renderers.items():
            t0 = time.perf_counter()
            for _ in range(frames):
                r.render_frame(0, still=True)
            times[k].append((time.perf_counter() - t0) / frames)
    return {k: 1e3 * float(np.median(v)) for k, v in times.items()}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--map-height", type=int, default=1024)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    import os

    result = {"load_before": os.getloadavg()[0], **bench_draws(args.map_height, args.repeats),
              **bench_frames(args.repeats), "load_after": os.getloadavg()[0], "map_height": args.map_height}
    print(json.dumps(result, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
