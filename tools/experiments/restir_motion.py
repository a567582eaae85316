"""ReSTIR DI + TAA against RIS + TAA on an orbiting camera at equal CPU time per frame: docs/measurements/
temporal-stability.md, "ReSTIR DI in motion against RIS".

Every method renders the orbit with TAA, k frames along the same camera path per animation frame (as
`restircl report --moving` does, eval/report/moving.py), k = the budget's CPU time over the method's own CPU time per
frame, rounded (at least 1); the budget is the CPU time of one frame of `--budget-method` (default: ReSTIR with its
defaults, the add-on's animation render). CPU time (time.process_time), not wall time: the machine is shared and its
load moves the wall time of a frame by tens of percent. The error of every `--every`-th frame is the relMSE against
that frame's converged reference (cached). Methods are `restircl report` names, with settings changed written
`base+key=value` (eval/report/methods.py), and optionally kernel defines of a probe after a `|` (`;`-separated),
for that method only.

With two or more RIS rows `ris+candidates=N` rendered one frame per animation frame, every other method is also
set against RIS at its own CPU time (equal_time_ris), so that a method cheaper than the budget is compared at its
own cost too.

    python -m tools.experiments.restir_motion --scene garden_orbit --methods ris,restir,restir+m_cap=5 --seeds 3
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import time
from pathlib import Path

import numpy as np
from restircl.core import program
from restircl.eval.probe_defines import add_probe_defines, parse_defines
from restircl.eval.report.moving import MovingReport, _taa_rows, frame_time_ms
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import MOTION_SCENES, motion_scene


@contextlib.contextmanager
def method_defines(method: str):
    """A method `name|NAME=VALUE;NAME2` compiles its kernels with those defines (a probe beside the same method
    without it, in one run); yields the method's `restircl report` name."""
    name, _, defines = method.partition("|")
    base = program.kernel_defines
    extra = parse_defines([d for d in defines.split(";") if d])
    program.kernel_defines = lambda: {**base(), **extra}  # type: ignore[assignment]
    try:
        yield name
    finally:
        program.kernel_defines = base  # type: ignore[assignment]


def cpu_times(scene, methods: list[str], repeats: int) -> dict[str, float]:
    """Median CPU ms per animation frame of each method, over `repeats` interleaved measurements."""
    got: dict[str, list[float]] = {m: [] for m in methods}
    for _ in range(repeats):
        for m in methods:
            with method_defines(m) as name:
                got[m].append(frame_time_ms(scene, name, frames=6)[1])
    return {m: float(np.median(v)) for m, v in got.items()}


def ris_candidates_of(method: str) -> int | None:
    """The candidate count of a plain RIS variant `ris+candidates=N` (None for anything else)."""
    head, *parts = method.split("+")
    if head != "ris" or len(parts) != 1 or not parts[0].startswith("candidates="):
        return None
    return int(parts[0].partition("=")[2])


def equal_time_ris(rows: list[dict], key: str = "mean_rel_mse_after_0") -> dict[str, tuple[float, float]] | None:
    """RIS at each method's own CPU time, from the RIS rows of the same run rendered one frame per animation frame
    (`ris+candidates=N`, k = 1): their CPU ms fitted as a + b N (least squares), the N of a method's CPU ms, and
    RIS's relMSE (`key`: the mean or the median over the seeds) at that N interpolated linearly in log N and log
    relMSE between the two nearest counts (the end segments beyond them). Returns {method: (N, relMSE)} for the
    other methods, None with fewer than two counts."""
    ladder = sorted(
        (n, r["cpu_ms"], r[key]) for r in rows if (n := ris_candidates_of(r["method"])) is not None and r["k"] == 1
    )
    if len({n for n, _, _ in ladder}) < 2:
        return None
    ns = np.array([n for n, _, _ in ladder], float)
    b, a = np.polyfit(ns, [c for _, c, _ in ladder], 1)
    log_n, log_e = np.log(ns), np.log([e for _, _, e in ladder])
    out = {}
    for r in rows:
        if ris_candidates_of(r["method"]) is not None:
            continue
        n = max((r["cpu_ms"] - a) / b, 1.0)
        j = int(np.clip(np.searchsorted(log_n, math.log(n)), 1, len(ns) - 1))
        t = (math.log(n) - log_n[j - 1]) / (log_n[j] - log_n[j - 1])
        out[r["method"]] = (n, float(math.exp(log_e[j - 1] + t * (log_e[j] - log_e[j - 1]))))
    return out


def orbit_arguments(ap: argparse.ArgumentParser) -> None:
    """The orbit and its evaluated frames, as the tools of these measurements take them."""
    ap.add_argument("--scene", default="garden_orbit", choices=sorted(MOTION_SCENES))
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--height", type=int, default=108)
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--every", type=int, default=4)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--methods", default="ris,restir")
    ap.add_argument("--budget-method", default="restir")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--first-seed", type=int, default=1, help="seeds first-seed .. first-seed + seeds - 1")
    ap.add_argument("--equal-frames", action="store_true", help="k = 1 for every method (error per frame)")
    ap.add_argument("--ceil", action="store_true", help="k rounded up (every method gets at least the budget)")
    ap.add_argument("--repeats", type=int, default=2, help="interleaved CPU-time measurements per method")
    ap.add_argument("--ref-seconds", type=float, default=10.0)
    ap.add_argument("--cache-dir", default="out/refs")
    ap.add_argument("--out", default=None, help="JSON file for the figures")
    ap.add_argument(
        "--define",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a kernel -D of a probe, for every method of the run (e.g. TAA_CLIP_RADIUS=2)",
    )
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    methods = a.methods.split(",")
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    evaluated = sorted({*range(0, scene.frames, a.every), scene.frames - 1})
    refs = {
        f: get_reference(scene, f, a.ref_seconds, cache_dir=Path(a.cache_dir), log=lambda s: None).image
        for f in evaluated
    }
    t_start = time.time()
    load0 = os.getloadavg()[0]
    timed = list(dict.fromkeys([a.budget_method, *methods]))
    cpu = cpu_times(scene, timed, a.repeats)
    budget = cpu[a.budget_method]

    def k_of(m: str) -> int:
        if a.equal_frames:
            return 1
        share = budget / cpu[m]
        return max(1, math.ceil(share - 0.02) if a.ceil else int(share + 0.5))

    ks = {m: k_of(m) for m in methods}
    errs: dict[str, list[float]] = {m: [] for m in methods}
    per_frame: dict[str, list[list[float]]] = {m: [] for m in methods}
    for seed in range(a.first_seed, a.first_seed + a.seeds):
        for m in methods:
            rep = MovingReport(scene.name, "", a.width, a.height, budget)
            with method_defines(m) as name:
                _taa_rows(rep, scene, name, ks[m], refs, None, None, seed)
            errs[m].append(float(np.mean([r.rel_mse for r in rep.rows if r.frame > 0])))
            per_frame[m].append([r.rel_mse for r in rep.rows])
    load1 = os.getloadavg()[0]
    base = methods[0]
    print(
        f"{scene.name} {a.width}x{a.height}, {scene.frames} frames, budget {budget:.1f} CPU ms per frame "
        f"({a.budget_method}), load {load0:.1f} -> {load1:.1f}, {time.time() - t_start:.0f} s"
    )
    print(
        "relMSE: the mean over the evaluated frames after frame 0 (the cold start, one sample for every method); "
        "per frame: the mean over the seeds"
    )
    print(
        f"{'method':<56} {'cpu ms':>7} {'k':>3} {'cpu ms x k':>10} {'relMSE per seed':>30} {'mean':>8} {'/ ' + base:>8}"
    )
    rows = []
    for m in methods:
        mean = float(np.mean(errs[m]))
        ratio = mean / float(np.mean(errs[base]))
        per_seed = " ".join(f"{e:.4f}" for e in errs[m])
        frames = np.mean(per_frame[m], axis=0)
        print(
            f"{m:<56} {cpu[m]:>7.1f} {ks[m]:>3} {cpu[m] * ks[m]:>10.1f} {per_seed:>30} {mean:>8.4f} {ratio:>8.3f}"
            f"   per frame {' '.join(f'{e:.3f}' for e in frames)}",
            flush=True,
        )
        rows.append(
            {
                "method": m,
                "cpu_ms": cpu[m],
                "k": ks[m],
                "rel_mse_per_seed": errs[m],
                "mean_rel_mse_after_0": mean,
                "median_rel_mse_after_0": float(np.median(errs[m])),
                "rel_mse_per_frame": np.mean(per_frame[m], axis=0).tolist(),
                "ratio_to_first": ratio,
            }
        )
    matched = equal_time_ris(rows)
    by_median = equal_time_ris(rows, "median_rel_mse_after_0")
    if matched and by_median:
        print(
            "RIS at each method's own CPU time (candidates N from the RIS rows' CPU ms, relMSE interpolated "
            "between their counts), by the mean and by the median over the seeds:"
        )
        for r in rows:
            if r["method"] in matched:
                n, e = matched[r["method"]]
                em = by_median[r["method"]][1]
                r["equal_time_ris"] = {"candidates": n, "rel_mse": e, "median_rel_mse": em}
                print(
                    f"{r['method']:<56} N {n:5.1f}  mean {r['mean_rel_mse_after_0']:.4f} / RIS {e:.4f} = "
                    f"{r['mean_rel_mse_after_0'] / e:.3f}  median {r['median_rel_mse_after_0']:.4f} / RIS "
                    f"{em:.4f} = {r['median_rel_mse_after_0'] / em:.3f}"
                )
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(
            json.dumps(
                {
                    "scene": scene.name,
                    "width": a.width,
                    "height": a.height,
                    "frames": scene.frames,
                    "evaluated": evaluated,
                    "budget_method": a.budget_method,
                    "budget_cpu_ms": budget,
                    "load": [load0, load1],
                    "seeds": a.seeds,
                    "first_seed": a.first_seed,
                    "defines": a.define,
                    "rows": rows,
                },
                indent=1,
            )
        )


if __name__ == "__main__":
    main()
