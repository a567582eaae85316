"""What ReSTIR GI buys in motion, measured: along an orbit of the camera in the Cornell box (bounced light is a large
share of it), the error per frame against a converged reference of that frame (our path pass, many frames) of
    (a) ReSTIR DI + ReSTIR GI + TAA                   ("restir_gi")
    (b) ReSTIR DI + paths without reuse + TAA          ("restir_paths"), at the same wall time per frame
    (c) Cycles restarting every frame, given the same time per frame (its samples per pixel chosen so that its
        render time is what our frames of (a) took; when bpy imports)
and, at one frame each without TAA, the per-frame error of (a) against (b) (the ReSTIR GI paper's comparison at one
sample per pixel).

    python -m restircl.eval.report.gi_motion --width 160 --height 90 --frames 24 --every 4 --bounces 4

Equal time per frame follows `restircl report --moving` (eval/report/moving.py): each method renders k frames along
the same camera path for each animation frame, k its share of the budget (budget_factor x the slower method's frame
time, so that whole frames come near the ratio of the frame times). The first evaluated frame is where every method
starts without history; the summary also gives the mean after it. Cycles' error floor against our reference (the
renderers' residual difference) is measured at 64x the samples on the first evaluated frame.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

from ...scene.camera import Camera
from ...scene.scene import Scene
from ...scene.transforms import look_at
from ...scenes.builtin import cornell_box
from ...settings.table import Settings
from ..metrics import rel_mse
from .moving import run_moving
from .reference import get_reference

CENTRE = (0.0, 0.0, 1.0)


def orbit_box(width: int, height: int, frames: int, step_deg: float, radius: float = 3.9) -> Scene:
    """The Cornell box seen from a camera that orbits its centre by `step_deg` degrees per frame, centred on the
    builtin scene's view."""
    scene = cornell_box(width, height, frames)
    cam = scene.camera
    assert cam is not None
    mats = []
    for f in range(frames):
        a = math.radians(step_deg * (f - (frames - 1) / 2))
        eye = (radius * math.sin(a), -radius * math.cos(a), CENTRE[2] + 0.1)
        mats.append(look_at(eye, CENTRE))
    scene.camera = Camera(np.stack(mats), width, height, lens=cam.lens, sensor_fit=cam.sensor_fit,
                          sensor_height=cam.sensor_height)
    scene.frame_count = frames
    scene.name = "cornell_orbit"
    return scene


def cycles_samples(sc, paths: Settings, seconds: float) -> int:
    """Cycles' samples per pixel whose render time (without scene synchronisation) comes nearest `seconds`: its time
    limit ends with the sample during which the limit passes, and overshot our frame time by 1.4-1.9x, so the
    samples are chosen from its measured cost per sample (1 and 8 samples, the median of three each)."""
    from ..cycles import bridge as cycles

    def cost(n: int) -> float:
        return float(np.median([cycles.render(sc, samples=n, paths=paths).render_seconds for _ in range(3)]))

    one, eight = cost(1), cost(8)
    per = max((eight - one) / 7.0, 1e-6)
    return max(1, int(round(1 + (seconds - one) / per)))


def cycles_rows(scene: Scene, evaluated: list[int], seconds: float, paths: Settings, refs: dict[int, np.ndarray],
                floor_factor: float = 64.0) -> list[dict]:
    """Cycles restarting at every evaluated frame with the samples that take it `seconds`, and its floor
    (floor_factor x those samples) on the first."""
    from ..cycles import bridge as cycles

    if not cycles.available():
        return []
    sc = cycles.to_bpy(scene, 0)
    sc.render.use_persistent_data = True
    cam = scene.camera
    assert cam is not None
    sc.camera.matrix_world = cycles._matrix(cam.transforms[evaluated[0]])
    spp = cycles_samples(sc, paths, seconds)
    rows = []
    for f, factor in [(f, 1) for f in evaluated] + [(evaluated[0], int(floor_factor))]:
        sc.camera.matrix_world = cycles._matrix(cam.transforms[f])
        res = cycles.render(sc, samples=spp * factor, paths=paths)
        rows.append({"method": "cycles" if factor == 1 else f"cycles x{floor_factor:g} samples", "frame": f,
                     "ms": res.render_seconds * 1e3, "samples": spp * factor, "rel_mse": rel_mse(res.image, refs[f])})
    return rows


def summarise(rows: list[dict], first: int) -> dict[str, dict]:
    """Per method: the mean relMSE over the evaluated frames, and over those after `first` (where every method
    starts without history, the same for all), the mean time per frame and frames along the path per frame."""
    out = {}
    for name in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == name]
        warm = [r["rel_mse"] for r in sel if r["frame"] > first] or [r["rel_mse"] for r in sel]
        out[name] = {"mean_rel_mse": float(np.mean([r["rel_mse"] for r in sel])),
                     "mean_rel_mse_after_first": float(np.mean(warm)),
                     "mean_ms": float(np.mean([r["ms"] for r in sel])), "rows": len(sel),
                     "mean_k": float(np.mean([r.get("samples", 1) for r in sel]))}
    return out


def ours(scene: Scene, paths: Settings, every: int, ref_seconds: float, seeds: list[int],
         budget_factor: float) -> tuple[list[dict], dict, float, str]:
    """(rows, references, budget ms, device) of our two methods with TAA at equal time and at one frame each
    without TAA, for every seed."""
    rows: list[dict] = []
    refs: dict[int, np.ndarray] = {}
    budget, device, meta = 0.0, "", {}
    for seed in seeds:
        taa = run_moving(scene, ["restir_gi", "restir_paths"], None, every, ("taa",), base=paths,
                         reference_seconds=ref_seconds, seed=seed, references=refs or None,
                         budget_factor=budget_factor)
        if not refs:
            refs = {int(f): get_reference(scene, int(f), ref_seconds, paths=paths, log=lambda s: None).image
                    for f in taa.references}
            meta = taa.references
        # one frame each without TAA (a budget below either frame time gives k = 1)
        single = run_moving(scene, ["restir_gi", "restir_paths"], 1e-3, every, ("taa",),
                            base=replace(paths, taa=False), references=refs, seed=seed)
        rows += [asdict(r) | {"method": r.method + " +TAA", "seed": seed} for r in taa.rows]
        rows += [asdict(r) | {"method": r.method + " 1 frame, no TAA", "seed": seed} for r in single.rows]
        budget, device = max(budget, taa.budget_ms), taa.device
    return rows, {"references": meta, "images": refs}, budget, device


def run(width: int, height: int, frames: int, step_deg: float, every: int, bounces: int, ref_seconds: float,
        with_cycles: bool, seeds: list[int], budget_factor: float, out: Path) -> dict:
    scene = orbit_box(width, height, frames, step_deg)
    paths = Settings(max_bounces=bounces, diffuse_bounces=bounces, glossy_bounces=bounces)
    load_before, t0 = os.getloadavg(), time.time()
    rows, refs, budget_ms, device = ours(scene, paths, every, ref_seconds, seeds, budget_factor)
    evaluated = sorted(refs["images"])
    if with_cycles:  # at the time our ReSTIR GI frames took (mean over the evaluated frames)
        gi_ms = float(np.mean([r["ms"] for r in rows if r["method"] == "restir_gi +TAA"]))
        rows += cycles_rows(scene, evaluated, gi_ms / 1e3, paths, refs["images"])
    result = {"scene": scene.name, "width": width, "height": height, "frames": frames, "step_deg": step_deg,
              "bounces": bounces, "evaluated": evaluated, "budget_ms": budget_ms, "budget_factor": budget_factor,
              "seeds": seeds, "device": device, "references": refs["references"], "load_before": load_before,
              "load_after": os.getloadavg(), "utc_start": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime(t0)),
              "utc_end": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()),
              "summary": summarise(rows, evaluated[0]), "rows": rows}
    out.mkdir(parents=True, exist_ok=True)
    (out / f"gi_motion_{scene.name}_{width}x{height}.json").write_text(json.dumps(result, indent=1))
    return result


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=90)
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--step", type=float, default=1.0, help="degrees of orbit per frame")
    ap.add_argument("--every", type=int, default=4, help="evaluate every n-th frame")
    ap.add_argument("--bounces", type=int, default=4)
    ap.add_argument("--ref-seconds", type=float, default=60.0)
    ap.add_argument("--seeds", type=int, default=3, help="independent runs of our methods")
    ap.add_argument("--budget-factor", type=float, default=2.0,
                    help="time per frame as a multiple of the slower method's frame time (whole frames each)")
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--out", type=Path, default=Path("out"))
    a = ap.parse_args(argv)
    res = run(a.width, a.height, a.frames, a.step, a.every, a.bounces, a.ref_seconds, not a.no_cycles,
              [4242 + k for k in range(a.seeds)], a.budget_factor, a.out)
    print(json.dumps({k: res[k] for k in ("device", "budget_ms", "summary", "load_before", "load_after",
                                          "utc_start", "utc_end")}, indent=1))


if __name__ == "__main__":
    main()
