"""Motion blur in animation: the add-on's animation frames (ReSTIR DI + TAA, each frame at one time of its
shutter, taa/sweep.h) against restarting every frame (a motion-blurred still of each frame from scratch, ours and
Cycles', as Cycles renders an animation) at equal CPU time per frame: docs/design.md, "Depth of field and motion
blur in motion".

The scene is `moving_box` (a box sliding by --speed a frame past a camera panning 0.08 m a frame, two lights) or
`many_lights` (a camera flying over 500 glowing lamps and 64 point lights), with a shutter of --shutter frames
around each frame. The error of every `--every`-th frame is the relMSE against that
frame's converged motion-blurred reference (eval/report/reference.py: a still, each sample at its own time). CPU
time (time.process_time), not wall time: the machine is shared; Cycles (direct light only, 2 threads, motion blur
with the same shutter, linear motion between whole frames as ours) gets that time as its time limit per frame.
The same run renders the animation sharp (no shutter) for the cost of the blur per frame.

    python -m tools.experiments.motion_blur_animation --width 96 --height 54 --frames 24 --every 6
    python -m tools.experiments.motion_blur_animation --scene many_lights
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import numpy as np
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.render.pipeline import Renderer
from restircl.scene.scene import Scene
from restircl.scenes.builtin import many_lights, moving_box
from restircl.settings.table import Settings

from .dof_motion import animation, restarted


def cycles_blurred(scene: Scene, frame: int, seconds: float) -> np.ndarray:
    """Cycles rendering `frame` of `scene` with its shutter: the scene at `frame` (eval/cycles/bridge.py), its
    moving meshes and camera keyed at the frames before and after it (linear keys, as ours interpolates)."""
    import bpy
    from restircl.eval.cycles import bridge as cycles

    sc = cycles.to_bpy(scene, frame)
    cam = scene.camera
    assert cam is not None
    keyed = [(bpy.data.objects[m.name], m.transforms, np.linalg.inv(Scene.at(m.transforms, frame)))
             for m in scene.meshes if m.transforms.shape[0] > 1] + [(sc.camera, cam.transforms, np.eye(4))]
    for ob, transforms, baked in keyed:  # a mesh's vertices are written at `frame`: its matrix is relative
        for f in (frame - 1, frame, frame + 1):
            ob.matrix_world = cycles._matrix(Scene.at(transforms, f) @ baked)
            ob.keyframe_insert("location", frame=f)
            ob.keyframe_insert("rotation_euler", frame=f)
        for fc in _fcurves(ob.animation_data.action):
            for kp in fc.keyframe_points:
                kp.interpolation = "LINEAR"
    sc.frame_set(frame)
    sc.render.use_motion_blur = True
    sc.render.motion_blur_shutter = cam.shutter[1] - cam.shutter[0]
    sc.render.motion_blur_position = "CENTER"
    return cycles.render(sc, seconds=seconds, threads=2).image[..., :3]


def taa_ms(scene: Scene, frames: int = 12) -> float:
    """Milliseconds of TAA's stage per frame (the sweep's search with motion blur), after the first two frames."""
    r = Renderer(scene, Settings())
    return float(np.mean([r.render_frame(k).stage_ms["taa"] for k in range(frames)][2:]))


def _fcurves(action) -> list:
    if hasattr(action, "layers") and len(action.layers):
        return [fc for layer in action.layers for strip in layer.strips for bag in strip.channelbags
                for fc in bag.fcurves]
    return list(action.fcurves)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=("moving_box", "many_lights"), default="moving_box")
    for name, default in (("width", 96), ("height", 54), ("frames", 24), ("every", 6)):
        ap.add_argument(f"--{name}", type=int, default=default)
    for name, value in (("speed", 0.2), ("shutter", 1.0), ("ref-seconds", 20.0)):
        ap.add_argument(f"--{name}", type=float, default=value)
    a = ap.parse_args()
    evaluated = {k for k in range(a.frames) if k % a.every == a.every - 1}
    result: dict = {"scene": a.scene, "load_before": os.getloadavg()}
    cache = Path(tempfile.gettempdir()) / "restircl_motion_blur_refs"
    def make():
        if a.scene == "many_lights":
            return many_lights(a.width, a.height, frames=a.frames)
        return moving_box(a.width, a.height, frames=a.frames, speed=a.speed)

    scene = make()
    assert scene.camera is not None
    scene.camera.shutter = (-0.5 * a.shutter, 0.5 * a.shutter)
    refs = {k: get_reference(scene, k, a.ref_seconds, cache_dir=cache).image[..., :3] for k in sorted(evaluated)}
    sharp_ms, sharp_anim = animation(make(), evaluated)
    ms, anim = animation(scene, evaluated)
    still, samples = restarted(scene, evaluated, ms)
    cyc = {k: cycles_blurred(scene, k, ms / 1e3) for k in sorted(evaluated)}
    errors = {name: float(np.mean([rel_mse(images[k], refs[k]) for k in evaluated]))
              for name, images in (("animation", anim), ("sharp_animation", sharp_anim), ("restart", still),
                                   ("cycles_restart", cyc))}
    result.update(shutter=a.shutter, cpu_ms_per_frame=ms, sharp_cpu_ms_per_frame=sharp_ms, restart_samples=samples,
                  rel_mse=errors, taa_ms=taa_ms(scene), sharp_taa_ms=taa_ms(make()), load_after=os.getloadavg())
    print(json.dumps(result))

if __name__ == "__main__":
    main()
