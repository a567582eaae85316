"""Depth of field in animation: the add-on's animation frames (ReSTIR DI + TAA, one lens point per pixel per frame,
the hit point reprojected) against restarting every frame (a still render of each frame from scratch, ours and
Cycles', as Cycles renders an animation) at equal time per frame, with the lens and without it: docs/design.md,
"Depth of field and motion blur in motion".

The scene is `moving_box` (a box sliding past a panning camera, two lights) focused on the box, or `many_lights`
(a flight over 500 glowing lamps and 64 point lights) focused 14 m ahead. The error of every
`--every`-th frame is the relMSE against that frame's converged reference (eval/report/reference.py, cached). CPU
time (time.process_time), not wall time: the machine is shared; Cycles (direct light only, 2 threads) gets that
time as its time limit per frame.

    python -m tools.experiments.dof_motion --width 160 --height 120 --frames 24 --every 6 --radius 0.12
    python -m tools.experiments.dof_motion --scene many_lights --width 160 --height 90 --radius 0.3
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.render.pipeline import Renderer
from restircl.render.still_method import still_settings
from restircl.scenes.builtin import many_lights, moving_box
from restircl.settings.table import Settings

# the scene and where it is focused: moving_box on the box's depth along the camera's axis (the camera is 5 m back
# and 2.7 m above it), many_lights about where the camera looks
SCENES = {"moving_box": (moving_box, 5.6), "many_lights": (many_lights, 14.0)}


def animation(scene, evaluated: set[int], settings: Settings | None = None) -> tuple[float, dict[int, np.ndarray]]:
    """CPU ms per frame (after the first two, which compile) and the images of the evaluated frames."""
    r = Renderer(scene, settings or Settings())
    ms, images = [], {}
    for k in range(scene.frames):
        c0 = time.process_time()
        out = r.render_frame(k)
        if k >= 2:
            ms.append((time.process_time() - c0) * 1e3)
        if k in evaluated:
            images[k] = out.color[..., :3]
    return float(np.mean(ms)), images


def restarted(scene, evaluated: set[int], budget_ms: float) -> tuple[dict[int, np.ndarray], float]:
    """Each evaluated frame rendered from scratch as a still for `budget_ms` of CPU time; the mean samples."""
    r = Renderer(scene, still_settings(Settings(), scene))
    r.render_still(0, 2)  # compile
    images, samples = {}, []
    for k in sorted(evaluated):
        c0 = time.process_time()
        out = r.render_still(k, 10_000, should_stop=lambda c0=c0: (time.process_time() - c0) * 1e3 >= budget_ms)
        images[k] = out.color[..., :3]
        samples.append(out.samples)
    return images, float(np.mean(samples))


def cycles_rows(scene, evaluated: set[int], seconds: float) -> dict[int, np.ndarray]:
    """Cycles (direct light only, eval/cycles/bridge.py) rendering each evaluated frame for `seconds`."""
    from restircl.eval.cycles import bridge as cycles

    if not cycles.available():
        return {}
    return {k: cycles.render(cycles.to_bpy(scene, k), seconds=seconds, threads=2).image[..., :3]
            for k in sorted(evaluated)}


def scene_arguments(description: str) -> argparse.ArgumentParser:
    """The scene, its size, frames and lens, and the references' time (also tools/experiments/dof_coc_reuse.py)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--scene", choices=sorted(SCENES), default="moving_box")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--every", type=int, default=6)
    ap.add_argument("--radius", type=float, default=0.12)
    ap.add_argument("--ref-seconds", type=float, default=20.0)
    return ap


def main() -> None:
    a = scene_arguments(__doc__.split("\n\n")[0]).parse_args()
    evaluated = {k for k in range(a.frames) if k % a.every == a.every - 1}
    result = {"scene": a.scene, "load_before": os.getloadavg(), "rows": []}
    make, focus = SCENES[a.scene]
    for radius in (0.0, a.radius):
        scene = make(a.width, a.height, frames=a.frames)
        assert scene.camera is not None
        scene.camera.aperture_radius, scene.camera.focus_distance = radius, focus
        refs = {k: get_reference(scene, k, a.ref_seconds).image[..., :3] for k in sorted(evaluated)}
        ms, anim = animation(scene, evaluated)
        still, samples = restarted(scene, evaluated, ms)
        cyc = cycles_rows(scene, evaluated, ms / 1e3)
        row = {"radius": radius, "cpu_ms_per_frame": ms, "restart_samples": samples,
               "animation_rel_mse": float(np.mean([rel_mse(anim[k], refs[k]) for k in evaluated])),
               "restart_rel_mse": float(np.mean([rel_mse(still[k], refs[k]) for k in evaluated])),
               "cycles_rel_mse": float(np.mean([rel_mse(cyc[k], refs[k]) for k in cyc])) if cyc else None}
        print(json.dumps(row))
        result["rows"].append(row)
    result["load_after"] = os.getloadavg()
    print(json.dumps(result))


if __name__ == "__main__":
    main()
