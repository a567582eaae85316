"""The denoiser's worth (Settings.denoise): error with and without Open Image Denoise at equal wall time.

    python -m restircl.eval.report.denoise [--size 320x180] [--budgets 1,4] [--frames 24]

Stills (many_lights at its first frame, held still; material_balls, glossy): F12's settings render for the budget
(noisy), and for the budget less the denoiser's own time, then denoise (so both images cost the same wall time).
Moving camera (many_lights' flythrough, ReSTIR + TAA): the noisy path, each denoiser (OIDN, the real-time filter),
and the noisy path at each denoiser's time per frame: the paths are timed side by side first, then the noisy path
renders the flythrough at (that denoiser's ms per frame / its own, rounded) times the frame rate, the same camera
path sampled more densely, and shows every so many frames: what a viewer of a real-time renderer gets from a
faster path. The error of every 4th shown frame against that frame's reference. relMSE and FLIP (when flip-evaluator is
installed) against the cached references of eval/report_reference.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from ... import scenes
from ...render.denoise import denoise_image
from ...render.pipeline import Renderer
from ...settings.table import Settings
from ..metrics import FLIP_MISSING, flip, flip_available, rel_mse
from .reference import get_reference


def _timed_still(scene, settings: Settings, seconds: float):
    r = Renderer(scene, settings)
    r.render_still(0, 2)  # kernels compiled and the scene uploaded before the clock starts
    t0 = time.perf_counter()
    f = r.render_still(0, 1 << 20, should_stop=lambda: time.perf_counter() - t0 >= seconds)
    return f, time.perf_counter() - t0


def _row(label: str, img: np.ndarray, ref: np.ndarray, seconds: float, samples: int) -> str:
    fl = flip(img, ref)
    return (f"| {label} | {rel_mse(img, ref):.3e} | {'n/a' if fl is None else f'{fl:.4f}'} | {seconds:.2f} | "
            f"{samples} |")


def stills(width: int, height: int, budgets: list[float], cache: Path) -> list[str]:
    out = ["| scene, budget, image | relMSE | FLIP | s | samples |", "|---|---|---|---|---|"]
    for name, scene in (("many_lights", scenes.many_lights(width, height, frames=1)),
                        ("material_balls", scenes.material_balls(width, height))):
        ref = get_reference(scene, 0, 60.0, cache_dir=cache, log=lambda s: None).image
        probe, _ = _timed_still(scene, Settings(), 0.5)
        t0 = time.perf_counter()
        denoise_image(probe.color, probe.albedo, probe.normal)
        t_oidn = time.perf_counter() - t0
        for b in budgets:
            noisy, s_noisy = _timed_still(scene, Settings(), b)
            out.append(_row(f"{name}, {b:g} s, noisy", noisy.color, ref, s_noisy, noisy.samples))
            den, s_den = _timed_still(scene, Settings(denoise=True), max(b - t_oidn, 0.05))
            out.append(_row(f"{name}, {b:g} s, denoised", den.color, ref, s_den, den.samples))
        out.append(f"| {name}: denoiser alone | | | {t_oidn:.3f} | |")
    return out


MOVING_VARIANTS = {"noisy": Settings(), "OIDN": Settings(denoise=True),
                   "real-time filter": Settings(realtime_filter=True)}


def _time_paths(scene, frames: int) -> dict[str, float]:
    """Median ms per frame of every MOVING_VARIANTS path over the flythrough, the paths taking turns frame by frame
    so that a change of the machine's load falls on all of them alike."""
    rs = {k: Renderer(scene, s) for k, s in MOVING_VARIANTS.items()}
    for r in rs.values():
        r.render_frame(0)  # kernels built, scene uploaded, OIDN's first call
        r.reset()
    ms: dict[str, list[float]] = {k: [] for k in rs}
    for f in range(frames):
        for k, r in rs.items():
            t0 = time.perf_counter()
            r.render_frame(f, aovs=False)
            ms[k].append((time.perf_counter() - t0) * 1e3)
    return {k: float(np.median(v)) for k, v in ms.items()}


def _run_path(scene, settings: Settings, frames: int, refs: dict[int, np.ndarray], rate: int = 1
              ) -> tuple[float, float | None, float]:
    """Mean relMSE and FLIP of the scored frames, and the ms per shown frame. `rate` > 1 renders the flythrough at
    that many times the frame rate (the same camera path sampled `rate` times as densely, many_lights(frames=)) and
    shows every rate-th frame: the time a denoiser would take, spent on frames in between, so TAA and ReSTIR reuse
    more history, each step shorter."""
    if rate > 1:
        scene = scenes.many_lights(scene.camera.width, scene.camera.height, frames=(frames - 1) * rate + 1)
    r = Renderer(scene, settings)
    r.render_frame(0)
    r.reset()
    errs, flips = [], []
    t0 = time.perf_counter()
    for g in range((frames - 1) * rate + 1):
        fr = r.render_frame(g, aovs=False)
        f, shown = divmod(g, rate)
        if shown == 0 and f in refs:
            t_score = time.perf_counter()
            errs.append(rel_mse(fr.color, refs[f]))
            fl = flip(fr.color, refs[f])
            if fl is not None:
                flips.append(fl)
            t0 += time.perf_counter() - t_score  # scoring is not the path's time
    ms = (time.perf_counter() - t0) * 1e3 / frames
    return float(np.mean(errs)), (float(np.mean(flips)) if flips else None), ms


def moving(width: int, height: int, frames: int, cache: Path, every: int = 4) -> list[str]:
    """The flythrough with and without each denoiser, and the noisy path at each denoiser's time per frame."""
    scene = scenes.many_lights(width, height, frames=frames)
    scored = sorted({*range(0, frames, every), frames - 1})
    refs = {f: get_reference(scene, f, 20.0, cache_dir=cache, log=lambda s: None).image for f in scored}
    cost = _time_paths(scene, frames)
    out = [f"many_lights {width}x{height} moving (its {frames}-frame flythrough), ReSTIR + TAA; median ms per frame "
           f"of the paths in turn: " + ", ".join(f"{k} {v:.0f}" for k, v in cost.items()),
           "| path | frame rate | mean relMSE | mean FLIP | ms per shown frame |", "|---|---|---|---|---|"]
    runs = [("noisy", MOVING_VARIANTS["noisy"], 1)]
    for k in ("OIDN", "real-time filter"):
        runs.append((k, MOVING_VARIANTS[k], 1))
        rate = max(1, round(cost[k] / cost["noisy"]))
        runs.append((f"noisy at {k}'s time ({cost[k] / cost['noisy']:.2f}x)", MOVING_VARIANTS["noisy"], rate))
    for label, settings, rate in runs:
        err, fl, ms = _run_path(scene, settings, frames, refs, rate)
        fl_text = "n/a" if fl is None else f"{fl:.4f}"
        out.append(f"| {label} | {rate}x | {err:.3e} | {fl_text} | {ms:.0f} |")
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", default="320x180")
    p.add_argument("--budgets", default="1,4")
    p.add_argument("--frames", type=int, default=24)
    p.add_argument("--cache-dir", type=Path, default=Path("out/denoise_refs"))
    p.add_argument("--moving-only", action="store_true", help="leave out the stills")
    a = p.parse_args(argv)
    w, h = (int(v) for v in a.size.split("x"))
    budgets = [float(v) for v in a.budgets.split(",")]
    if not flip_available():
        print(FLIP_MISSING, flush=True)
    still_lines = [] if a.moving_only else [*stills(w, h, budgets, a.cache_dir), ""]
    for line in [*still_lines, *moving(w, h, a.frames, a.cache_dir)]:
        print(line, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
