"""Issue 23: variants of the traversal (opencl/bvh/traverse.h -D flags, build_bvh keywords) side by side on the rays
of the traversal benchmark, interleaved round by round in one process; Mrays per CPU-second of all threads.

    python -m tools.experiments.traversal_ab \
        '{"base": {}, "x": {"defines": {"BVH_X": 1}}, "scalar": {"packets": false}}' \
        [--scene light_cloud --triangles 10000] [--rounds 5] [--width 640 --height 360]

Every variant traces the same rays (the benchmark's camera rays and, from the first variant's hits, its shadow
rays). Prints the median over the rounds and whether each variant's hits are those of the first: the same
triangles (original indices) and bit-identical t for camera rays, the same occluded / visible for shadow rays.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import numpy as np
from restircl.bvh import packets as bvh_packets
from restircl.bvh.build import build_bvh, make_tris
from restircl.eval.bench import traversal as bt
from restircl.eval.bench.tracers import OpenCLTracer


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variants", help='JSON: name -> {"defines": {...}, "build": {build_bvh keywords}, "packets": '
                    'bool (leaf packets, bvh/packets.py; default: bvh_packets.ENABLED)}')
    ap.add_argument("--scene", choices=("mixed", "light_cloud", "light_panels"), default="light_cloud")
    ap.add_argument("--triangles", type=int, default=10_000, help="triangles (mixed) or lights (the others)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeats", type=int, default=2, help="timed launches per round (the best is kept)")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    a = ap.parse_args()
    variants: dict[str, dict] = json.loads(a.variants)
    if a.scene == "mixed":
        v0, v1, v2 = bt.make_scene(a.triangles)
        view = None
    else:
        (v0, v1, v2), view = bt.light_cloud_scene(a.triangles, "triangles" if a.scene == "light_cloud" else "panels")
    n = len(v0)
    o, d = bt.camera_rays(a.width, a.height) if view is None else bt.camera_rays(a.width, a.height, *view)
    default_packets = bvh_packets.ENABLED
    bvhs: dict[str, tuple] = {}
    first_tris = None
    tracers: dict[str, OpenCLTracer] = {}
    for name, v in variants.items():
        bvh_packets.ENABLED = bool(v.get("packets", default_packets))  # read by build_bvh, build_program, device_arrays
        try:
            key = json.dumps([v.get("build", {}), bvh_packets.ENABLED], sort_keys=True)
            if key not in bvhs:
                bvh = build_bvh(v0, v1, v2, **v.get("build", {}))
                bvhs[key] = (bvh, make_tris(v0, v1, v2, np.zeros(n, np.int32), np.arange(n), bvh.order))
                print(f"{name}: build {bvh.build_seconds:.2f} s, {bvh.node_count} nodes, SAH {bvh.sah_cost:.1f}")
            bvh, tris = bvhs[key]
            tracers[name] = OpenCLTracer(*bvh_packets.device_arrays(bvh.nodes, tris), local_size=64,
                                         flags=v.get("defines", {}))
        finally:
            bvh_packets.ENABLED = default_packets
        first_tris = first_tris if first_tris is not None else tris
        tracers[name].order = bvh.order  # type: ignore[attr-defined]
    first = next(iter(tracers))
    t0, leaf0, _ = tracers[first].closest(o, d, repeats=1)
    so, sd = bt.shadow_rays(o, d, t0.astype(np.float64), leaf0, first_tris, np.random.default_rng(1))
    print(f"scene {a.scene}, {n} triangles, {len(o)} camera rays, {len(so)} shadow rays; load {os.getloadavg()}")
    prim_cpu: dict[str, list[float]] = {k: [] for k in tracers}
    shad_cpu: dict[str, list[float]] = {k: [] for k in tracers}
    ref = None
    for rnd in range(a.rounds):
        for name, tr in tracers.items():
            t, leaf, _ = tr.closest(o, d, repeats=a.repeats)
            prim_cpu[name].append(len(o) / tr.last_cpu_seconds / 1e6)
            occ, _ = tr.any(so, sd, 1.0, repeats=a.repeats)
            shad_cpu[name].append(len(so) / tr.last_cpu_seconds / 1e6)
            if rnd == 0:
                prim = np.where(leaf >= 0, tr.order[np.maximum(leaf, 0)], -1)  # type: ignore[attr-defined]
                if ref is None:
                    ref = (t.view(np.int32).copy(), prim, occ)
                same = (np.mean((t.view(np.int32) == ref[0]) & (prim == ref[1])), np.mean(occ == ref[2]))
                print(f"{name:<12} same hits as {first}: camera {same[0] * 100:.3f}%, shadow {same[1] * 100:.3f}%")
        print(f"round {rnd} done, load {os.getloadavg()[0]:.1f}", flush=True)
        time.sleep(0)
    for name in tracers:
        p, s = prim_cpu[name], shad_cpu[name]
        print(f"{name:<12} camera {statistics.median(p):5.2f} [{min(p):.2f}-{max(p):.2f}]  "
              f"shadow {statistics.median(s):5.2f} [{min(s):.2f}-{max(s):.2f}]  Mrays per CPU-second")


if __name__ == "__main__":
    main()
