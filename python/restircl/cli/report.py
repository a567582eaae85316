"""`restircl report`: error against run time for every method (restircl/eval/report, imported when the command
runs): a still camera at a series of budgets, a moving camera at equal time per frame (--moving), or temporal
stability (--flicker)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from .arguments import COUNT, POSITIVE, SECONDS, load_scene


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    rp = sub.add_parser("report", help="error against run time for every method (CSV, JSON, log-log plot)",
                        description="Render a still camera with each method (and Cycles, direct light only, when "
                                    "bpy imports) for a series of wall-clock budgets and record relMSE and RMSE "
                                    "(FLIP with flip-evaluator) against a converged, cached reference. With "
                                    "--moving: every frame of the animation with the same time per frame (a faster "
                                    "method renders more frames along the same camera path with TAA, more samples "
                                    "of each frame without it), and the error of every --every-th frame against that "
                                    "frame's reference.")
    rp.add_argument("scene", nargs="?", help="built-in scene, scene file (.npz) or .blend (needs bpy)")
    rp.add_argument("--width", type=COUNT, default=None)
    rp.add_argument("--height", type=COUNT, default=None)
    rp.add_argument("--methods", default=None, help="comma-separated subset (default: all); a method with settings "
                    "changed is written base+key=value, e.g. restir+m_cap=5+candidates=16")
    rp.add_argument("--budgets", type=POSITIVE.parse_list, default="0.25,0.5,1,2,4",
                    help="seconds, comma-separated (%(default)s)")
    rp.add_argument("--modes", default=None,
                    help="still: accumulate (running mean) and/or taa (TAA output), default accumulate,taa; "
                         "--moving: taa and/or frame (mean of the frame's own samples, no TAA), default taa")
    rp.add_argument("--no-cycles", action="store_true", help="leave Cycles out even when bpy imports")
    rp.add_argument("--moving", action="store_true", help="moving camera: error per frame at equal time per frame")
    rp.add_argument("--frames", type=COUNT, default=None, help="--moving: animation length of many_lights")
    rp.add_argument("--ms-per-frame", type=SECONDS, default=None,
                    help="--moving: wall time per frame (default: the slowest method's frame time)")
    rp.add_argument("--every", type=COUNT, default=4, help="--moving: evaluate every N-th frame (%(default)s)")
    rp.add_argument("--flicker", action="store_true",
                    help="instead: temporal stability of the animation path (TAA output) per method: flicker, "
                         "error, their ratio and boiling pixels, on the still camera or (--moving) a slowed one")
    rp.add_argument("--flicker-frames", type=COUNT, default=16, help="--flicker: frames kept (%(default)s)")
    rp.add_argument("--reference-seconds", type=SECONDS, default=120.0,
                    help="time for a reference, per frame (%(default)s); references are cached")
    rp.add_argument("--cache-dir", default=None, help="reference cache (default: ~/.cache/restircl)")
    rp.add_argument("--replot", default=None, metavar="JSON", help="redraw the plot of a written report and exit")
    rp.add_argument("--out", default="out")
    rp.add_argument("--device", default=None)
    rp.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    from ..eval.cycles import bridge as cycles
    from ..eval.report import main as report
    from ..eval.report.methods import METHODS as REPORT_METHODS
    from ..eval.report.methods import method_overrides

    if a.replot:
        for path in report.replot(Path(a.replot)):
            print(f"wrote {path}")
        return 0
    if not a.scene:
        raise ValueError("report: give a SCENE (or --replot JSON)")
    methods = a.methods.split(",") if a.methods else list(REPORT_METHODS)
    for m in methods:
        method_overrides(m)  # an unknown method or setting fails here, before any rendering
    cache = Path(a.cache_dir) if a.cache_dir else None
    if a.flicker:
        return _flicker(a, methods, cache)
    blend = a.scene.endswith(".blend")
    if blend and not cycles.available():
        raise ValueError("report: a .blend scene needs the bpy module (run under a Python with bpy installed)")
    if a.moving:
        return _moving(a, methods, cache, blend)
    return _still(a, methods, cache, blend)


def _flicker(a: argparse.Namespace, methods: list[str], cache: Path | None) -> int:
    from ..eval.report import flicker

    scene = load_scene(a.scene, a.width, a.height, a.frames)
    if a.moving and scene.frames < 2:
        raise ValueError(f"report --flicker --moving: {scene.name} has one frame (no camera motion)")
    results = flicker.run_flicker(scene, methods, frames=a.flicker_frames, moving=a.moving, device=a.device,
                                  cache_dir=cache, reference_seconds=a.reference_seconds, log=lambda s: None)
    print(flicker.HEADER)
    for res in results:
        print(res.row())
    out = Path(a.out) / f"flicker_{scene.name}_{'moving' if a.moving else 'still'}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(flicker.as_json(results), indent=1))
    print(f"wrote {out}")
    return 0


def _moving(a: argparse.Namespace, methods: list[str], cache: Path | None, blend: bool) -> int:
    from ..eval.cycles import bridge as cycles
    from ..eval.report import moving as report_moving

    if blend:
        scene, _, warnings = cycles.load_blend(a.scene, a.width, a.height, all_frames=True)
        for w in warnings:
            print(f"export warning: {w}")
    else:
        scene = load_scene(a.scene, a.width, a.height, a.frames)
    if scene.frames < 2:
        raise ValueError(f"report --moving: {scene.name} has one frame (no camera motion)")
    modes = tuple((a.modes or "taa").split(","))
    mv = report_moving.run_moving(scene, methods, a.ms_per_frame, a.every, modes, device=a.device,
                                  reference_seconds=a.reference_seconds, cache_dir=cache)
    print(f"device: {mv.device}, {mv.width}x{mv.height}, {scene.frames} frames, {mv.budget_ms:.0f} ms per frame")
    print(mv.table())
    for path in mv.write(Path(a.out)):
        print(f"wrote {path}")
    return 0


def _still(a: argparse.Namespace, methods: list[str], cache: Path | None, blend: bool) -> int:
    from ..eval.cycles import bridge as cycles
    from ..eval.report import main as report
    from ..eval.report import reference as report_reference

    target: bool | object = not a.no_cycles
    if blend:
        scene, bpy_scene, warnings = cycles.load_blend(a.scene, a.width, a.height)
        for w in warnings:
            print(f"export warning: {w}")
        if target:
            target = bpy_scene
    else:
        scene = load_scene(a.scene, a.width, a.height, 1)
    budgets = tuple(a.budgets)
    ref = report_reference.get_reference(scene, 0, a.reference_seconds, device=a.device, cache_dir=cache)
    rep = report.run_report(scene, methods, budgets, tuple((a.modes or "accumulate,taa").split(",")),
                            device=a.device, reference=ref, cycles=target)
    print(f"device: {rep.device}, {rep.width}x{rep.height}")
    print(rep.table())
    for note in rep.notes:
        print(f"note: {note}")
    for path in rep.write(Path(a.out)):
        print(f"wrote {path}")
    return 0
