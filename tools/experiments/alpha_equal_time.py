"""Error against wall time, ours against Cycles, on the alpha scene (eval/scenes/alpha_cards.py: alpha-masked leaf
cards and a half-transparent pane over a lit floor), direct light, Transparent Max Bounces 8 on both sides.

Reference: two Cycles renders of REFERENCE_SPP samples (their difference estimates its own error). Cycles is timed
as the wall clock of its render call with its time limit set to the budget less the fixed cost of a call (measured
with one sample); ours from the Renderer's construction to the image read back (kernels compiled before), as
eval/cycles/compare.py times them. Prints one line per budget and method, and `uptime`'s load.

    PYTHONPATH=python python tools/experiments/alpha_equal_time.py [width height [opaque]]

ALPHA_REFERENCE=path.npy: the reference is read from that file, or rendered and written there (so that runs of two
states of the code, each with PYTHONPATH at its own tree, compare with one reference).

`opaque`: the same scene with every coverage 1 (the leaves' quads and the pane opaque), for the share of the gap
that transparency makes.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.compare import time_ours
from restircl.eval.scenes.alpha_cards import alpha_cards

BUDGETS = (1.0, 4.0, 16.0)
REFERENCE_SPP = 4096
TRANSPARENT = 8


def rel_mse(a: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((a - ref) ** 2 / (ref * ref + 1e-2)))


def adjust(sc) -> None:
    sc.cycles.transparent_max_bounces = TRANSPARENT


def cycles_at(bpy_scene, budget: float, fixed: float, seed: int) -> tuple[np.ndarray, float]:
    limit = max(budget - fixed, 0.05)
    t0 = time.perf_counter()
    res = cycles.render(bpy_scene, seconds=limit, seed=seed, threads=2, adjust=adjust)
    return res.image[..., :3], time.perf_counter() - t0


def main() -> None:
    w, h = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) > 2 else (96, 72)
    scene = alpha_cards(w, h)
    if len(sys.argv) > 3 and sys.argv[3] == "opaque":
        for m in scene.materials:
            m.alpha = 1.0
    bpy_scene = cycles.to_bpy(scene)
    print(f"alpha_cards {w}x{h} {' '.join(sys.argv[3:])}, load {os.getloadavg()}")
    cached = os.environ.get("ALPHA_REFERENCE")
    if cached and os.path.exists(cached):
        refs = list(np.load(cached))
    else:
        refs = [cycles.render(bpy_scene, samples=REFERENCE_SPP, seed=100 + k, threads=2,
                              adjust=adjust).image[..., :3] for k in range(2)]
        if cached:
            np.save(cached, np.stack(refs))
    ref = 0.5 * (refs[0] + refs[1])
    print(f"reference: 2 x {REFERENCE_SPP} spp, its own relMSE ~ {rel_mse(refs[0], refs[1]) / 4:.2e}")
    cycles.render(bpy_scene, samples=1, threads=2, adjust=adjust)
    t0 = time.perf_counter()
    cycles.render(bpy_scene, samples=1, threads=2, adjust=adjust)
    fixed = time.perf_counter() - t0
    methods = {"ris": Settings(method="ris"), "auto": still_settings(Settings(), scene)}
    for s in methods.values():
        Renderer(scene, s).render_still(0, samples=1)  # compile once
    for budget in BUDGETS:
        img, secs = cycles_at(bpy_scene, budget, fixed, seed=int(budget))
        line = [f"budget {budget:5.1f} s: cycles {rel_mse(img, ref):.2e} ({secs:.1f} s)"]
        for name, s in methods.items():
            ours, secs, _setup, n = time_ours(scene, s, budget)
            line.append(f"{name} {rel_mse(ours, ref):.2e} ({secs:.1f} s, {n} samples)")
        print("; ".join(line), f"load {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
