"""The viewport claim, measured: along a scripted orbit, the error per frame of our viewport policy (ReSTIR and
TAA history reprojected through every view change, Renderer.render_view) against restarting on every view change
(what Cycles' viewport does: each navigation step starts its accumulation over), and against Cycles itself given
the same time per frame; and the frame time at a viewport size.

    python -m restircl.eval.report.viewport_orbit --width 160 --height 90 --views 24 --every 4 --step 2 --ref-seconds 5
    python -m restircl.eval.report.viewport_orbit --frame-time 480x270     # 960x540 at pixel size 2

Our policy renders one frame per view; the restart policy (the same renderer and settings) gets the same mean
time per view and spends it on as many frames of that view as fit (a restarted frame is cheaper: no temporal
pass); each view's error is the relMSE against its converged reference (report_reference.get_reference,
cached on disk). Cycles (direct light only, eval/cycles/bridge.py) renders each evaluated view with Cycles' time limit
set to our mean frame time; its error floor against our reference (the two renderers' residual difference) is
measured at 64x that time on the first view.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from ...render.pipeline import Renderer
from ...scene.camera import Camera
from ...scene.scene import Scene
from ...scene.transforms import look_at
from ...scenes.builtin import many_lights
from ...settings.table import Settings
from ..metrics import rel_mse
from .reference import get_reference

CENTRE = np.array([0.0, 0.0, 0.5])


def orbit(width: int, height: int, views: int, step_deg: float, radius: float = 14.0, height_m: float = 5.0,
          start_deg: float = -50.0) -> np.ndarray:
    """Camera-to-world matrices of an orbit around the scene's centre, `step_deg` degrees per view."""
    mats = []
    for k in range(views):
        a = math.radians(start_deg + step_deg * k)
        eye = CENTRE + (radius * math.cos(a), radius * math.sin(a), height_m)
        mats.append(look_at(tuple(eye), tuple(CENTRE)))
    return np.stack(mats)


def orbit_scene(width: int, height: int, views: int, step_deg: float) -> Scene:
    sc = many_lights(width, height, frames=1)
    sc.camera = Camera(orbit(width, height, views, step_deg), width, height, lens=24.0)
    sc.frame_count = views
    return sc


def view_at(scene: Scene, k: int) -> Camera:
    cam = scene.camera
    assert cam is not None
    return Camera(cam.transforms[k], cam.width, cam.height, lens=cam.lens)


def policy_rows(scene: Scene, policy: str, seed: int, budget_ms: float | None = None,
                settings: Settings | None = None) -> list[dict]:
    """'reprojected': one frame per view, the history kept. 'restart': the history dropped at every view change.
    Either renders more frames of a view while they fit in `budget_ms` (at least one). `settings`: other than the
    defaults (its seed is replaced by `seed`)."""
    views = [view_at(scene, k) for k in range(scene.frames)]
    s = replace(settings or Settings(), seed=seed)
    r = Renderer(replace(scene), s, interactive=True)  # render_view sets its scene's camera
    r.render_view(views[0], cut=True)  # kernels compile at their first launch: keep that out of the times
    r.render_view(views[1])
    rows = []
    for k, view in enumerate(views):
        t0 = time.perf_counter()
        out = r.render_view(view, cut=policy == "restart" or k == 0)
        frames = 1
        per = time.perf_counter() - t0
        # another frame of the same view if it ends nearer the budget than stopping now does
        while budget_ms is not None and (time.perf_counter() - t0 + 0.5 * per) * 1e3 < budget_ms:
            out = r.render_view(view)
            frames += 1
        rows.append({"policy": policy, "view": k, "ms": (time.perf_counter() - t0) * 1e3, "frames": frames,
                     "image": out.color[..., :3]})
    return rows


def cycles_rows(scene: Scene, views: list[int], seconds: float, floor_factor: float = 64.0) -> list[dict]:
    from ..cycles import bridge as cycles

    if not cycles.available():
        return []
    sc = cycles.to_bpy(scene, 0)
    sc.render.use_persistent_data = True
    cam = scene.camera
    assert cam is not None
    rows = []
    for k in views:
        sc.camera.matrix_world = cycles._matrix(cam.transforms[k])
        res = cycles.render(sc, seconds=seconds)
        rows.append({"policy": "cycles", "view": k, "ms": res.render_seconds * 1e3, "image": res.image})
    sc.camera.matrix_world = cycles._matrix(cam.transforms[views[0]])
    res = cycles.render(sc, seconds=seconds * floor_factor)
    rows.append({"policy": f"cycles x{floor_factor:g} time", "view": views[0], "ms": res.render_seconds * 1e3,
                 "image": res.image})
    return rows


def frame_time(width: int, height: int, frames: int = 12, step_deg: float = 1.0) -> dict:
    """Milliseconds per viewport frame (render_view, default settings) along an orbit at width x height."""
    scene = orbit_scene(width, height, frames + 2, step_deg)
    views = [view_at(scene, k) for k in range(scene.frames)]
    r = Renderer(scene, Settings(), interactive=True)
    r.render_view(views[0], cut=True)
    r.render_view(views[1])
    ms, cpu_ms = [], []
    for k in range(2, frames + 2):
        t0, c0 = time.perf_counter(), time.process_time()
        r.render_view(views[k])
        ms.append((time.perf_counter() - t0) * 1e3)
        cpu_ms.append((time.process_time() - c0) * 1e3)
    # CPU time of this process (PoCL's worker threads included): what a frame costs whatever else runs; on an
    # idle machine the wall time is about it divided by the cores
    return {"width": width, "height": height, "median_ms": float(np.median(ms)), "min_ms": float(np.min(ms)),
            "max_ms": float(np.max(ms)), "median_cpu_ms": float(np.median(cpu_ms)), "frames": frames,
            "device": r.device.label, "cores": os.cpu_count(), "load": os.getloadavg()}


def run(width: int, height: int, views: int, step_deg: float, every: int, ref_seconds: float, seed: int,
        with_cycles: bool, out: Path, plot_dir: Path) -> dict:
    scene = orbit_scene(width, height, views, step_deg)
    evaluated = [k for k in range(views) if k % every == every - 1 or k == views - 1]
    refs = {}
    for k in evaluated:
        refs[k] = get_reference(scene, k, ref_seconds).image
    load_before = os.getloadavg()
    rows = policy_rows(scene, "reprojected", seed)
    our_ms = float(np.mean([r["ms"] for r in rows]))
    rows += policy_rows(scene, "restart", seed, budget_ms=our_ms)
    if with_cycles:
        rows += cycles_rows(scene, evaluated, our_ms / 1e3)
    table = [{k: v for k, v in r.items() if k != "image"} | {"rel_mse": rel_mse(r["image"], refs[r["view"]])}
             for r in rows if r["view"] in refs]
    summary = {}
    for policy in dict.fromkeys(r["policy"] for r in table):
        sel = [r for r in table if r["policy"] == policy]
        summary[policy] = {"mean_rel_mse": float(np.mean([r["rel_mse"] for r in sel])),
                           "mean_ms": float(np.mean([r["ms"] for r in sel])), "views": len(sel),
                           "mean_frames": float(np.mean([r.get("frames", 1) for r in sel]))}
    result = {"scene": scene.name, "width": width, "height": height, "views": views, "step_deg": step_deg,
              "evaluated": evaluated, "ref_seconds": ref_seconds, "load_before": load_before,
              "load_after": os.getloadavg(), "summary": summary, "rows": table}
    out.mkdir(parents=True, exist_ok=True)
    plot_dir.mkdir(parents=True, exist_ok=True)
    base = out / f"viewport_orbit_{scene.name}_{width}x{height}"
    base.with_suffix(".json").write_text(json.dumps(result, indent=1))
    plot(table, plot_dir / f"{base.name}.png", f"{scene.name} {width}x{height}, orbit {step_deg:g} deg/frame, "
         f"{our_ms:.0f} ms/frame")
    return result


def plot(table: list[dict], path: Path, title: str) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(7.5, 4.0), dpi=110)
    for policy in dict.fromkeys(r["policy"] for r in table):
        sel = [r for r in table if r["policy"] == policy]
        if len(sel) > 1:
            ax.plot([r["view"] for r in sel], [r["rel_mse"] for r in sel], marker="o", ms=3, label=policy)
    ax.set_yscale("log")
    ax.set_xlabel("view (frame of the orbit)")
    ax.set_ylabel("relMSE vs the view's reference")
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--views", type=int, default=24)
    ap.add_argument("--step", type=float, default=2.0, help="degrees of orbit per frame")
    ap.add_argument("--every", type=int, default=3, help="evaluate every n-th view")
    ap.add_argument("--ref-seconds", type=float, default=15.0)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--frame-time", default=None, help="WxH: only measure the frame time at this size")
    ap.add_argument("--out", type=Path, default=Path("docs/data"))
    ap.add_argument("--plot-dir", type=Path, default=Path("docs/img"))
    a = ap.parse_args(argv)
    if a.frame_time:
        w, h = (int(v) for v in a.frame_time.lower().split("x"))
        print(json.dumps(frame_time(w, h), indent=1))
        return
    res = run(a.width, a.height, a.views, a.step, a.every, a.ref_seconds, a.seed, not a.no_cycles, a.out,
              a.plot_dir)
    print(json.dumps({"summary": res["summary"], "load_before": res["load_before"],
                      "load_after": res["load_after"]}, indent=1))


if __name__ == "__main__":
    main()
