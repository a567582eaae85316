"""The denoiser's worth (Settings.denoise): error with and without Open Image Denoise at equal wall time.

    python -m restircl.eval.denoise_report [--size 320x180] [--budgets 1,4] [--frames 24]

Stills (many_lights at its first frame, held still; material_balls, glossy): F12's settings render for the budget
(noisy), and for the budget less the denoiser's own time, then denoise (so both images cost the same wall time).
Moving camera (many_lights' flythrough, ReSTIR + TAA): every frame rendered once with and once without the
denoiser, the error of every 8th frame against that frame's reference. relMSE and FLIP (when flip-evaluator is
installed) against the cached references of eval/report_reference.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from .. import Renderer, Settings, scenes
from ..denoise import denoise_image
from .metrics import flip, rel_mse
from .report_reference import get_reference


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


def moving(width: int, height: int, frames: int, cache: Path) -> list[str]:
    scene = scenes.many_lights(width, height, frames=frames)
    every = sorted({*range(0, frames, 8), frames - 1})
    refs = {f: get_reference(scene, f, 20.0, cache_dir=cache, log=lambda s: None).image for f in every}
    out = ["| many_lights moving, ReSTIR + TAA | mean relMSE | mean FLIP | ms per frame |", "|---|---|---|---|"]
    for label, settings in (("noisy", Settings()), ("denoised", Settings(denoise=True))):
        r = Renderer(scene, settings)
        r.render_frame(0)
        r.reset()
        errs, flips, ms = [], [], []
        for f in range(frames):
            t0 = time.perf_counter()
            fr = r.render_frame(f)
            ms.append((time.perf_counter() - t0) * 1e3)
            if f in refs:
                errs.append(rel_mse(fr.color, refs[f]))
                fl = flip(fr.color, refs[f])
                if fl is not None:
                    flips.append(fl)
        fl_text = f"{np.mean(flips):.4f}" if flips else "n/a"
        out.append(f"| {label} | {np.mean(errs):.3e} | {fl_text} | {np.median(ms):.0f} |")
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", default="320x180")
    p.add_argument("--budgets", default="1,4")
    p.add_argument("--frames", type=int, default=24)
    p.add_argument("--cache-dir", type=Path, default=Path("out/denoise_refs"))
    a = p.parse_args(argv)
    w, h = (int(v) for v in a.size.split("x"))
    budgets = [float(v) for v in a.budgets.split(",")]
    for line in [*stills(w, h, budgets, a.cache_dir), "", *moving(w, h, a.frames, a.cache_dir)]:
        print(line, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
