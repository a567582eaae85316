"""`restircl render SCENE`: a still accumulated into one image, or an animation written frame by frame (chunked and
on many processes through cli/farm.py)."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import scenes
from ..farm.chunks import parse_frames
from ..render.frame import Frame
from ..render.pipeline import Renderer
from ..render.still_method import describe_still, still_settings
from ..scene.scene import Scene
from ..settings.table import Settings
from .arguments import COUNT, POSITIVE, add_settings_args, load_scene
from .farm import add_farm_arguments, render_job, wants_farm
from .progress import Progress


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    r = sub.add_parser("render", help="render a built-in scene or a scene file",
                       description="Render SCENE (a built-in name or a .npz scene file). A still scene "
                                   "accumulates --frames samples into one image; an animated one writes one "
                                   "image per frame.")
    r.add_argument("scene", help=f"built-in scene ({', '.join(scenes.BUILTIN)}) or a scene file")
    r.add_argument("--width", type=COUNT, default=None)
    r.add_argument("--height", type=COUNT, default=None)
    r.add_argument("--frames", type=parse_frames, default=16,
                   help="samples (still) or frames (animation: N for 0..N-1, or a range A-B)")
    r.add_argument("--mode", choices=("auto", "still", "animation"), default="auto",
                   help="auto: still if the scene has one frame (default)")
    r.add_argument("--out", default="out")
    r.add_argument("--target-error", type=POSITIVE.parse, default=None,
                   help="still: stop once the estimated relMSE (from two half buffers, no reference) reaches this")
    add_settings_args(r)
    add_farm_arguments(r)
    r.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    if wants_farm(a):
        return render_job(a)
    scene = load_scene(a.scene, a.width, a.height, a.frames)
    return render_scene(scene, a.settings, a.frames, Path(a.out), a.mode, a.device, a.target_error)


def render_scene(scene: Scene, settings: Settings, frames: int, out: Path, mode: str, device: str | None,
                 target_error: float | None = None) -> int:
    """Render `scene` in this process into `out` (EXR with AOVs and PNG), describing the set-up on stdout."""
    if mode == "auto":
        mode = "still" if scene.frames == 1 else "animation"
    # a still camera gets the still estimator (render/still_method.py); the files keep the name of the Method asked for
    used = still_settings(settings, scene) if mode == "still" else settings
    renderer = Renderer(scene, used, device)
    cam = scene.camera
    assert cam is not None
    print(f"device: {renderer.device.label}")
    print(f"scene: {scene.name}, {renderer.triangle_count} triangles, {len(renderer.lights)} lights, "
          f"resolution {cam.width}x{cam.height}, method {settings.method}")
    if mode == "still":
        print(describe_still(settings, used))
    print(f"features compiled: {', '.join(renderer.features) or 'none'} (build {renderer.build_seconds:.2f} s, "
          f"BVH {renderer.bvh_seconds:.2f} s)")
    if renderer.will_use_light_tiles():
        print(f"light tiles: {settings.light_tile_count} x {settings.light_tile_size} presampled lights per frame")
    out.mkdir(parents=True, exist_ok=True)
    if mode == "still":
        return _still(renderer, scene, settings, frames, out, target_error)
    return _animation(renderer, scene, frames, out)


def _still(renderer: Renderer, scene: Scene, settings: Settings, frames: int, out: Path,
           target_error: float | None) -> int:
    from ..io.images import write_exr, write_png

    bar = Progress(frames, "render")
    state = {"err": None}

    def progress(done: int, total: int) -> None:
        if done % 8 == 0 and done >= 8:
            state["err"] = renderer.error_estimate(*renderer.still_counts)
        extra = f"est. relMSE {state['err']:.2e}" if state["err"] is not None else ""
        bar.update(done, extra)

    f = renderer.render_still(0, frames, progress=progress, target_error=target_error)
    if f.samples < frames:
        bar.update(frames, f"est. relMSE {f.error_estimate:.2e}" if f.error_estimate is not None else "")
        print(f"stopped after {f.samples} of {frames} samples: the estimated relMSE reached the target "
              f"{target_error:g}")
    write_exr(out / f"{scene.name}_{settings.method}.exr", f)
    write_png(out / f"{scene.name}_{settings.method}.png", f)
    est = f"{f.error_estimate:.3e}" if f.error_estimate is not None else "n/a"
    print(f"{f.samples} samples, {f.ms:.1f} ms per sample, estimated relMSE {est}")
    _print_guards(f.guards)
    print(f"wrote {out / (scene.name + '_' + settings.method)}.exr/.png")
    return 0


def _animation(renderer: Renderer, scene: Scene, frames: int, out: Path) -> int:
    from ..io.images import write_exr, write_png

    bar = Progress(frames, "render")
    times = []
    last: Frame | None = None
    for i in range(frames):
        f = renderer.render_frame(i % scene.frames)
        times.append(f.ms)
        write_exr(out / f"{scene.name}_{i:04d}.exr", f)
        write_png(out / f"{scene.name}_{i:04d}.png", f)
        bar.update(i + 1, f"{f.ms:.0f} ms")
        last = f
    assert last is not None
    warm = times[1:] if len(times) > 1 else times
    print(f"{frames} frames, {sum(warm) / len(warm):.1f} ms per frame (after the first; first {times[0]:.1f} ms)")
    print("stages of the last frame (ms): " + ", ".join(f"{k} {v:.1f}" for k, v in last.stage_ms.items()))
    _print_guards(last.guards)
    print(f"wrote {frames} frames to {out}/ (EXR with AOVs, PNG previews)")
    return 0


def _print_guards(guards: dict[str, int]) -> None:
    bad = {k: v for k, v in guards.items() if v}
    print("NaN/Inf guards: " + (", ".join(f"{k} {v}" for k, v in bad.items()) if bad else "none triggered"))
