"""Why permutation sampling (Settings.temporal_permutation) costs CPU time: CPU ms per frame stage (stage_cpu's
timer) and the share of pixels the temporal pass found no history for ("fresh") and of those the spatial pass found
no similar neighbour for either ("lonely": restir/lonely_fresh.h draws fresh_candidates more candidates for them), on
an orbit: docs/measurements/temporal-stability.md, "Why permutation sampling cost CPU time".

    python -m tools.experiments.permutation_cost --scene garden_orbit --rounds 3 [--define NAME]

The variants render the orbit frame by frame, interleaved. Lonely pixels are counted on the fresh_candidates = 0
variants, where the spatial pass leaves a lonely pixel's reservoir as it is (its M unchanged); whether a pixel is
lonely depends on the G-buffers alone, so the count holds for the default too.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics

import numpy as np
import pyopencl as cl
from restircl import Renderer
from restircl.core import layouts as L
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.methods import method_settings
from restircl.eval.scenes.motion_validation import MOTION_SCENES, motion_scene
from restircl.render import pipeline

from tools.experiments.stage_cpu import _LAST, CpuStageTimer

VARIANTS = {
    "restir": {},
    "permutation": {"temporal_permutation": True},
    "restir fc0": {"fresh_candidates": 0},
    "permutation fc0": {"temporal_permutation": True, "fresh_candidates": 0},
}


def reservoirs(r: Renderer, buf: cl.Buffer) -> np.ndarray:
    a = np.empty(r.pixels, L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, a, buf)
    r.device.queue.finish()
    return a


def counts(r: Renderer) -> tuple[int, int, int]:
    """Valid, fresh and (on a fresh_candidates = 0 variant) lonely pixels of the frame just rendered: the temporal
    pass's output is still in res_temp (one spatial pass), the spatial pass's in last frame's history slot."""
    temp = reservoirs(r, r.buffers.res_temp)
    final = reservoirs(r, r.history.reservoirs(r.history.prev))
    valid = final["M"] > 0
    fresh = valid & (temp["M"] <= r.settings.candidates + r.settings.bsdf_candidates)
    lonely = fresh & (final["M"] == temp["M"])
    return int(valid.sum()), int(fresh.sum()), int(lonely.sum())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="garden_orbit", choices=sorted(MOTION_SCENES))
    ap.add_argument("--rounds", type=int, default=3, help="passes over the orbit's 24 frames")
    ap.add_argument("--define", action="append", default=[], help="a kernel -D of a probe, for every variant")
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    pipeline.StageTimer = CpuStageTimer  # type: ignore[misc]
    scene = motion_scene(a.scene, 192, 108, 24)
    rs = {n: Renderer(scene, dataclasses.replace(method_settings("restir", None, 1), **v)) for n, v in VARIANTS.items()}
    cpu: dict[str, dict[str, list[float]]] = {n: {} for n in rs}
    total: dict[str, list[float]] = {n: [] for n in rs}
    got: dict[str, list[tuple[int, int, int]]] = {n: [] for n in rs}
    print(f"{a.scene} 192x108, load {os.getloadavg()[0]:.1f}", flush=True)
    for rnd in range(a.rounds):
        for f in range(scene.frames):
            for n, r in rs.items():
                r.render_frame(f, aovs=False)
                if f >= 2:  # frames 0 and 1 of each pass: no history, then a cold one
                    stage_ms = {k: v for k, v in _LAST["cpu"].items() if k != "upload"}
                    for k, v in stage_ms.items():
                        cpu[n].setdefault(k, []).append(v)
                    total[n].append(sum(stage_ms.values()))
                if rnd == 0 and f >= 1:
                    got[n].append(counts(r))
    print(f"load at the end {os.getloadavg()[0]:.1f}; CPU ms: medians over frames 2-23 of every pass")
    for n in rs:
        valid, fresh, lonely = np.mean(got[n], axis=0)
        parts = " ".join(f"{k} {statistics.median(v):5.2f}" for k, v in cpu[n].items())
        lonely_part = f", lonely {lonely / valid:6.2%}" if "fc0" in n else ""
        print(f"{n:<16} CPU ms {statistics.median(total[n]):6.2f} [{parts}]  fresh {fresh / valid:6.2%}{lonely_part}")


if __name__ == "__main__":
    main()
