"""Milliseconds per frame of the viewport session (ViewportSession: ReSTIR + TAA, one frame per view) along an
orbit of many_lights, at the render size of a 3D view, for settings variants measured side by side (one frame of
each variant per view, in turn), with the load: docs/blender.md ("Frame time").

    python -m tools.experiments.viewport_frame_time --size 480x270 --size 960x540   # 960x540 at pixel size 2 and 1
    python -m tools.experiments.viewport_frame_time --size 480x270 --variant cheap=candidates=4,spatial_neighbours=1

Each variant is a ViewportSession of its own driven like view_draw drives one (set_view, then the worker renders
the frame); a frame's time is the worker's (ViewFrame.ms: render, read-back, the copy for the texture) and this
process's CPU time over it (PoCL's threads included: what a frame costs whatever else runs).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import time
from pathlib import Path

import numpy as np
from restircl import Settings
from restircl.eval.report.viewport_orbit import orbit_scene, view_at
from restircl.io.blend import addon_module


def parse_variant(text: str) -> tuple[str, dict]:
    """'name=key=value,key=value' -> (name, Settings keyword arguments typed as Settings' defaults)."""
    name, _, rest = text.partition("=")
    kw: dict = {}
    for item in filter(None, rest.split(",")):
        key, _, value = item.partition("=")
        default = getattr(Settings, key)
        kw[key] = (value.lower() in ("1", "true", "on")) if isinstance(default, bool) else type(default)(value)
    return name, kw


def session_of(scene, kw: dict):
    # the add-on package imports bpy; the session module itself does not use it
    return addon_module().viewport_session.ViewportSession(scene, Settings(**kw), samples=1).start()


def measure(width: int, height: int, variants: dict[str, dict], frames: int, step_deg: float) -> dict:
    view_camera = addon_module().viewport_session.view_camera
    scene = orbit_scene(width, height, frames + 2, step_deg)
    cams = [view_at(scene, k) for k in range(scene.frames)]
    sessions = {name: session_of(scene, kw) for name, kw in variants.items()}
    proj = None
    rows: dict[str, dict[str, list[float]]] = {name: {"ms": [], "cpu_ms": []} for name in variants}
    try:
        for k, cam in enumerate(cams):
            view = np.linalg.inv(cam.transforms[0])
            if proj is None:  # the 3D view's window matrix of the scene camera's lens (24 mm, 36 mm sensor)
                t = 18.0 / cam.lens
                proj = np.array([[1 / t, 0, 0, 0], [0, width / height / t, 0, 0], [0, 0, -1.002, -0.2],
                                 [0, 0, -1, 0]])
            for name, s in sessions.items():
                c0 = time.process_time()
                s.set_view(view_camera(view, proj, width, height))
                f = s.wait(k + 1)
                if s.error is not None or f is None:
                    raise RuntimeError(f"{name}: {s.error}")
                if k >= 2:  # the first two: kernel builds and first uploads
                    rows[name]["ms"].append(f.ms)
                    rows[name]["cpu_ms"].append((time.process_time() - c0) * 1e3)
        out = {}
        for name, r in rows.items():
            out[name] = {"median_ms": float(np.median(r["ms"])), "min_ms": float(np.min(r["ms"])),
                         "max_ms": float(np.max(r["ms"])), "median_cpu_ms": float(np.median(r["cpu_ms"])),
                         "settings": variants[name], "device": sessions[name].device_label}
        return out
    finally:
        for s in sessions.values():
            s.stop()


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", action="append", default=None, help="WxH render size (repeatable; 480x270)")
    ap.add_argument("--variant", action="append", default=[], help="name=key=value,... Settings of a variant "
                    "measured beside the defaults")
    ap.add_argument("--frames", type=int, default=12, help="frames timed per variant and size (%(default)s)")
    ap.add_argument("--step", type=float, default=1.0, help="degrees of orbit per frame (%(default)s)")
    a = ap.parse_args(argv)
    variants = {"default": {}, **dict(parse_variant(v) for v in a.variant)}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=Path(__file__).parent, capture_output=True,
                            text=True).stdout.strip()
    for size in a.size or ["480x270"]:
        w, h = (int(v) for v in size.lower().split("x"))
        load_before = os.getloadavg()
        res = measure(w, h, variants, a.frames, a.step)
        print(json.dumps({"size": size, "frames": a.frames, "cores": os.cpu_count(), "load_before": load_before,
                          "load_after": os.getloadavg(), "commit": commit,
                          "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "variants": res}, indent=1),
              flush=True)


if __name__ == "__main__":
    main()
