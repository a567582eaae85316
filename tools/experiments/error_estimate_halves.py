"""The half buffers of still renders, saved so that rules for the reference-free error estimate (render/still.py
StillAccumulation.error_estimate) can be compared offline against the true relMSE (docs/measurements/
error-vs-time.md, "Error while rendering, without a reference"). Per seed, at each checkpoint (frames), the two
half buffers' means and frame counts; with --reference, one more render of many frames (its halves too).

    python -m tools.experiments.error_estimate_halves --kind garden --max-bounces 4 --seeds 8 --out G.npz
    python -m tools.experiments.error_estimate_halves --builtin many_lights --size 64x36 --method ris \\
        --first-seed 100 --seeds 3 --reference 1024 --out M.npz

Rules and their ratios: tools/experiments/error_estimate_rules.py.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from restircl import Renderer, Settings, scenes
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.report.methods import METHODS
from restircl.eval.report.reference import emissive_triangle_count
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render.still_method import still_settings
from restircl.scene.canonical import canonical_scene


def halves(r: Renderer, checks: tuple[int, ...]) -> dict[int, tuple[np.ndarray, np.ndarray, int, int]]:
    """Render a still of max(checks) frames; at each check the halves' means (H, W, 3) and their frame counts."""
    got: dict[int, tuple[np.ndarray, np.ndarray, int, int]] = {}

    def checkpoint(done: int, _secs: float) -> None:
        if done in checks:
            acc = r.still
            total, half = acc._read(acc.sum)[:, :3], acc._read(acc.sum_half)[:, :3]
            done_, n_half = acc.counts
            shape = (*acc.shape, 3)
            a = (half / n_half).reshape(shape)
            b = ((total - half) / (done_ - n_half)).reshape(shape)
            got[done] = (a.astype(np.float32), b.astype(np.float32), n_half, done_ - n_half)

    r.render_still(0, max(checks), checkpoint=checkpoint)
    return got


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", help="a scene kind (eval/scenes/kinds.py), 192x108, F12's still settings")
    ap.add_argument("--builtin", help="a built-in scene instead, with --method")
    ap.add_argument("--size", default="64x36")
    ap.add_argument("--method", default="ris", help="a METHODS name (built-in scenes)")
    ap.add_argument("--max-bounces", type=int, default=4)
    ap.add_argument("--checks", default="16,64,256")
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--first-seed", type=int, default=100)
    ap.add_argument("--reference", type=int, default=0, help="frames of a reference render (the tests' settings)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    checks = tuple(int(c) for c in a.checks.split(","))
    if a.kind:
        scene = scene_of_kind(a.kind, 192, 108)
        base = still_settings(Settings(**LightPaths.of(a.max_bounces).overrides()).validate(), scene)
    else:
        w, h = (int(x) for x in a.size.split("x"))
        scene = scenes.builtin(a.builtin, width=w, height=h)
        base = Settings(**METHODS[a.method])
    out: dict[str, np.ndarray] = {"checks": np.array(checks)}
    t0 = time.perf_counter()
    per_seed = []
    for seed in range(a.first_seed, a.first_seed + a.seeds):
        base.seed = seed
        per_seed.append(halves(Renderer(scene, base), checks))
    for n in checks:
        out[f"a{n}"] = np.stack([s[n][0] for s in per_seed])
        out[f"b{n}"] = np.stack([s[n][1] for s in per_seed])
        out[f"counts{n}"] = np.array([s[n][2:] for s in per_seed])
    if a.reference:  # the settings of eval/report/reference.py get_reference
        n_lights = len(scene.lights) + emissive_triangle_count(scene, 0)
        ref_settings = Settings(method="reference" if n_lights <= 16 else "ris", candidates=32, seed=987654)
        rr = Renderer(canonical_scene(scene), ref_settings.validate())
        ra, rb, na, nb = halves(rr, (a.reference,))[a.reference]
        out.update(ref_a=ra, ref_b=rb, ref_counts=np.array([na, nb]))
    np.savez_compressed(a.out, **out)
    print(f"{a.out}: {a.seeds} seeds, checks {checks}, {time.perf_counter() - t0:.0f} s, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
