"""Per-sample efficiency on few lights, one factor at a time (issue 37): relMSE against the cached 2 x N-spp Cycles
reference at equal samples (Cycles spp, our frames) and the CPU seconds per sample, for Cycles with and without
its light tree (which splits a light sample where the tree's bound is loose) and for F12's still path with one of
Cycles' factors added (eval/cycles/compare.py's OURS and CYCLES: auto_tree, auto_mis, auto_solid, ...). CPU time
(time.process_time: Cycles' and PoCL's threads run in this process) rather than wall time, since the machine is
shared; relMSE x CPU seconds is the figure that compares at equal time (lower is better). Needs bpy and the cached
reference (`restircl compare` makes it). docs/measurements/error-vs-time.md, "Few lights, one factor at a time".

    python -m tools.experiments.few_lights_factors --kinds studio,user --samples 64,256 --seeds 2
    python -m tools.experiments.few_lights_factors --kinds user --methods cycles,auto --samples 1,4,16 --seeds 8 \\
        --max-bounces 4 --reference-spp 256 --cache-dir out/cache
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.compare import (
    CYCLES,
    REFERENCE_SPP,
    cycles_reference,
    cycles_variant,
    ours_settings,
    scene_pair,
)
from restircl.eval.cycles.paths import DIRECT, LightPaths
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH
from restircl.render.pipeline import Renderer

METHODS = "cycles,cycles_no_tree,auto,auto_tree,auto_mis,auto_solid,auto_array"


def measure(kind: str, methods: list[str], samples: list[int], seeds: int, cache_dir: Path | None,
            paths: LightPaths = DIRECT, reference_spp: int = REFERENCE_SPP, first_seed: int = 7) -> dict:
    """{method: {samples: {"rel_mse": [per seed], "cpu_s": [per seed]}}} for one kind, every render with the Light
    Paths `paths` (the reference of reference_spp samples per half with them, as `restircl compare` caches it)."""
    scene, sc = scene_pair(kind, WIDTH, HEIGHT)
    ref = cycles_reference(kind, scene, sc, reference_spp, 2, cache_dir, lambda *a: None, paths).image
    out: dict = {m: {n: {"rel_mse": [], "cpu_s": []} for n in samples} for m in methods}
    settings = {m: ours_settings(m, scene, paths) for m in methods if m not in CYCLES}
    for s in settings.values():
        Renderer(scene, s).render_still(0, 2)  # program build
    for m in (m for m in methods if m in CYCLES):
        with cycles_variant(sc, m):
            cycles.render(sc, samples=1, threads=2, paths=paths.cycles())  # Cycles' kernels loaded
    for seed in range(first_seed, first_seed + seeds):
        for n in samples:
            for m in methods:
                r = None if m in CYCLES else Renderer(scene, replace(settings[m], seed=seed))  # upload
                c0 = time.process_time()
                if r is None:
                    with cycles_variant(sc, m):
                        img = cycles.render(sc, samples=n, seed=seed, threads=2, paths=paths.cycles()).image
                else:
                    img = r.render_still(0, n).color[..., :3]
                cpu = time.process_time() - c0
                cell = out[m][n]
                cell["rel_mse"].append(rel_mse(img, ref))
                cell["cpu_s"].append(cpu)
                print(f"{kind:7} {m:15} n {n:4} seed {seed}: relMSE {cell['rel_mse'][-1]:.3e}, "
                      f"{cpu * 1e3 / n:7.2f} CPU ms per sample", flush=True)
    return out


def table(kind: str, got: dict) -> str:
    lines = [f"| {kind} | method | samples | relMSE (mean of seeds) | CPU ms / sample | relMSE x CPU s |",
             "|---|---|---|---|---|---|"]
    for m, cells in got.items():
        for n, c in cells.items():
            e, cpu = float(np.mean(c["rel_mse"])), float(np.mean(c["cpu_s"]))
            lines.append(f"| | {m} | {n} | {e:.3e} | {cpu * 1e3 / n:.2f} | {e * cpu:.3e} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--kinds", default="studio")
    ap.add_argument("--methods", default=METHODS)
    ap.add_argument("--samples", default="64,256")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--first-seed", type=int, default=7)
    ap.add_argument("--max-bounces", type=int, default=0, help="Light Paths' Max Bounces (0: direct light only)")
    ap.add_argument("--reference-spp", type=int, default=REFERENCE_SPP, help="the cached reference's spp per half")
    ap.add_argument("--cache-dir", default=None)
    ap.add_argument("--out", default=None, help="JSON file for the figures")
    a = ap.parse_args()
    load = os.getloadavg()
    record = {"load_before": load, "kinds": {}}
    for kind in a.kinds.split(","):
        got = measure(kind, a.methods.split(","), [int(n) for n in a.samples.split(",")], a.seeds,
                      Path(a.cache_dir) if a.cache_dir else None, LightPaths.of(a.max_bounces), a.reference_spp,
                      a.first_seed)
        record["kinds"][kind] = got
        print(table(kind, got), flush=True)
    record["load_after"] = os.getloadavg()
    print(f"load average before {load[0]:.2f}, after {record['load_after'][0]:.2f}")
    if a.out:
        Path(a.out).write_text(json.dumps(record, indent=1))


if __name__ == "__main__":
    main()
