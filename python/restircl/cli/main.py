"""The `restircl` command line: demo, render, report, devices, bench, save-scene, stress (and `python -m restircl`)."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from .. import scenes
from ..core.device import DeviceError, build_problem, get_device, list_devices
from ..core.program import KernelBuildError
from ..farm.chunks import parse_frames
from ..render.pipeline import Renderer
from ..render.still_method import describe_still, still_settings
from ..scene.errors import SceneError
from ..scene.scene import Scene
from ..settings.spec import Range, SettingError, add_arguments, flag_of, from_arguments
from ..settings.table import Settings

COUNT = Range(int, 1).parse  # sizes, frame counts: 0 or less is a mistake, not "the default"
POSITIVE = Range(float, 0, min_open=True, finite=True)  # seconds, error targets
SECONDS = POSITIVE.parse


class Progress:
    """A one-line progress bar on stderr (plain lines when stderr is not a terminal)."""

    def __init__(self, total: int, label: str) -> None:
        self.total, self.label, self.t0 = max(total, 1), label, time.perf_counter()
        self.tty = sys.stderr.isatty()

    def update(self, done: int, extra: str = "") -> None:
        frac = done / self.total
        bar = "#" * int(frac * 30)
        line = f"{self.label} [{bar:<30}] {done}/{self.total} {time.perf_counter() - self.t0:6.1f}s {extra}"
        if self.tty:
            sys.stderr.write("\r" + line)
            if done >= self.total:
                sys.stderr.write("\n")
        elif done == self.total or done % max(self.total // 10, 1) == 0:
            sys.stderr.write(line + "\n")
        sys.stderr.flush()


def load_scene(spec: str, width: int | None, height: int | None, frames: int | None = None) -> Scene:
    """A built-in scene name or a scene file (.npz), with the resolution overridden if given."""
    if spec in scenes.BUILTIN:
        kwargs = {}
        if width:
            kwargs["width"] = width
        if height:
            kwargs["height"] = height
        if frames and spec == "many_lights":
            kwargs["frames"] = frames
        return scenes.builtin(spec, **kwargs)
    path = Path(spec)
    if not path.exists():
        raise SceneError(f"{spec!r} is neither a built-in scene ({', '.join(scenes.BUILTIN)}) nor a file")
    scene = Scene.load(path)
    if scene.camera is not None:
        if width:
            scene.camera.width = width
        if height:
            scene.camera.height = height
    return scene


def add_settings_args(p: argparse.ArgumentParser) -> None:
    """One option per Settings field (the table in settings/table.py), and --device."""
    add_arguments(p.add_argument_group("rendering method and its parameters"), Settings)
    p.add_argument("--device", default=None, help="OpenCL device: 'P:D' or a name substring (default: "
                   "$RESTIRCL_DEVICE, else the first GPU, else the first CPU)")
    p.set_defaults(settings_parser=p)


def settings_from_args(a: argparse.Namespace) -> Settings:
    return from_arguments(Settings, a).validate()


def _render(scene: Scene, settings: Settings, frames: int, out: Path, mode: str, device: str | None,
            target_error: float | None = None) -> int:
    from ..io.images import write_exr, write_png

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
    bar = Progress(frames, "render")
    times = []
    last = None
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


def cmd_demo(a: argparse.Namespace) -> int:
    scene = scenes.many_lights(width=a.width, height=a.height, frames=a.frames)
    return _render(scene, a.settings, a.frames, Path(a.out), "animation", a.device)


def cmd_render(a: argparse.Namespace) -> int:
    from .farm import render_job, wants_farm

    if wants_farm(a):
        return render_job(a)
    scene = load_scene(a.scene, a.width, a.height, a.frames)
    return _render(scene, a.settings, a.frames, Path(a.out), a.mode, a.device, a.target_error)


def cmd_devices(a: argparse.Namespace) -> int:
    for info, dev in list_devices():
        problem = build_problem(dev)
        print(info.label if problem is None else f"{info.label}: {problem}")
    dev = get_device(a.device)
    print(f"chosen: {dev.label}")
    return 0


def cmd_bench(a: argparse.Namespace) -> int:
    from ..eval.bench import filter as bench_filter
    from ..eval.bench import main as bench

    rc = bench.main(a) if a.what != "filter" else 0
    if a.what in ("filter", "all"):
        rc = rc or bench_filter.main(a)
    return rc


def _report_flicker(a: argparse.Namespace, methods: list[str], cache: Path | None) -> int:
    import json

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


def cmd_report(a: argparse.Namespace) -> int:
    from ..eval.cycles import bridge as cycles
    from ..eval.report import main as report
    from ..eval.report import moving as report_moving
    from ..eval.report import reference as report_reference
    from ..eval.report.methods import METHODS as REPORT_METHODS

    if a.replot:
        for path in report.replot(Path(a.replot)):
            print(f"wrote {path}")
        return 0
    if not a.scene:
        raise ValueError("report: give a SCENE (or --replot JSON)")
    methods = a.methods.split(",") if a.methods else list(REPORT_METHODS)
    unknown = [m for m in methods if m not in REPORT_METHODS]
    if unknown:
        raise ValueError(f"unknown methods {unknown}; choose from {', '.join(REPORT_METHODS)}")
    cache = Path(a.cache_dir) if a.cache_dir else None
    if a.flicker:
        return _report_flicker(a, methods, cache)
    blend = a.scene.endswith(".blend")
    if blend and not cycles.available():
        raise ValueError("report: a .blend scene needs the bpy module (run under a Python with bpy installed)")
    if a.moving:
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


def cmd_compare(a: argparse.Namespace) -> int:
    from ..eval.cycles import compare_report as cycles_compare_report

    return cycles_compare_report.main(a)


def cmd_save_scene(a: argparse.Namespace) -> int:
    scene = load_scene(a.scene, a.width, a.height)
    scene.save(a.path)
    print(f"wrote {a.path}")
    return 0


def cmd_stress(a: argparse.Namespace) -> int:
    from ..eval.bench import specialisation as bench_specialisation
    from ..eval.stress import judging as stress_judging
    from ..eval.stress import suite as stress

    def log(line: str) -> None:
        print(line, file=sys.stderr, flush=True)

    if a.bench_specialisation:
        rows = bench_specialisation.bench_specialisation(frames=a.bench_frames, log=print)
        if a.out:
            Path(a.out).mkdir(parents=True, exist_ok=True)
            (Path(a.out) / "specialisation.json").write_text(json.dumps(rows, indent=1))
        return 0
    methods = a.methods.split(",") if a.methods else None
    names = a.cases.split(",") if a.cases else None
    device = get_device(a.device)
    print(f"device: {device.label}; {'full' if a.full else 'small'} sizes")
    results = stress.run(full=a.full, methods=methods, names=names, device=device, log=log, seed=a.seed)
    print(stress_judging.format_table(results))
    failed = [r for r in results if not r.passed]
    print(f"{len(results) - len(failed)} of {len(results)} passed")
    if a.out:
        for path in stress_judging.write(results, Path(a.out)):
            print(f"wrote {path}")
    return 1 if failed else 0


def build_parser() -> argparse.ArgumentParser:
    from .farm import add_farm_arguments

    p = argparse.ArgumentParser(prog="restircl", description=__doc__)
    sub = p.add_subparsers(dest="command", required=True)

    d = sub.add_parser("demo", help="render the built-in many_lights flythrough into out/",
                       description="Render several frames of the built-in many_lights scene (animated camera) "
                                   "with ReSTIR + TAA into --out as EXR (with AOVs) and PNG previews.")
    d.add_argument("--width", type=COUNT, default=640)
    d.add_argument("--height", type=COUNT, default=360)
    d.add_argument("--frames", type=COUNT, default=16)
    d.add_argument("--out", default="out")
    add_settings_args(d)
    d.set_defaults(func=cmd_demo)

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
    r.set_defaults(func=cmd_render)

    v = sub.add_parser("devices", help="list OpenCL devices and the one chosen")
    v.add_argument("--device", default=None)
    v.set_defaults(func=cmd_devices)

    b = sub.add_parser("bench", help="benchmarks: traversal vs Embree, frame times, light-count scaling",
                       description="Print benchmark figures (not timed tests).")
    b.add_argument("what", nargs="?", choices=("traversal", "frame", "lights", "taa", "filter", "all"),
                   default="all",
                   help="traversal: ours vs Embree; frame: ms per stage and method; lights: frame time against "
                        "the light count; taa: error against frame number; filter: the real-time filter's ms "
                        "at 1..5 iterations (default: all)")
    b.add_argument("--triangles", type=COUNT, default=1_000_000)
    b.add_argument("--width", type=COUNT, default=640)
    b.add_argument("--height", type=COUNT, default=360)
    b.add_argument("--no-embree", action="store_true")
    b.add_argument("--device", default=None)
    b.set_defaults(func=cmd_bench)

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
    rp.add_argument("--methods", default=None, help="comma-separated subset (default: all)")
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
    rp.set_defaults(func=cmd_report)

    c = sub.add_parser("compare", help="ours against Cycles at equal wall time on the held-out scenes (needs bpy)",
                       description="Render the held-out scenes (studio, neon, garden; sky, an HDRI world, with "
                                   "--kinds) with Cycles (direct light only) and our methods (default: ReSTIR as "
                                   "for an animation; auto: F12's still estimator; ris and the other still "
                                   "candidates of eval/cycles_compare.OURS) for each wall-time budget, and "
                                   "compare their relMSE against a cached 2 x N-spp Cycles image: tables, CSV/JSON, "
                                   "plot.")
    c.add_argument("--kinds", default="studio,neon,garden")
    c.add_argument("--methods", default="cycles,default,auto,ris")
    c.add_argument("--budgets", type=POSITIVE.parse_list, default="1,4,16", help="seconds (%(default)s)")
    c.add_argument("--reps", type=COUNT, default=3, help="repetitions of every budget (%(default)s)")
    c.add_argument("--width", type=COUNT, default=192)
    c.add_argument("--height", type=COUNT, default=108)
    c.add_argument("--reference-spp", type=COUNT, default=1024, help="samples of each of the two reference halves")
    c.add_argument("--agreement-seconds", type=SECONDS, default=60.0, help="time for our converged image")
    c.add_argument("--threads", type=COUNT, default=2, help="Cycles' render threads (%(default)s)")
    c.add_argument("--cycles-world-map", type=int, default=0, metavar="N",
                   help="the timed Cycles renders' world importance map: Manual at N (default 0: Blender's "
                        "Automatic, built in every render call)")
    c.add_argument("--cache-dir", default=None, help="reference cache (default: ~/.cache/restircl)")
    c.add_argument("--out", default="out", help="writes OUT/data/compare_cycles_WxH.* and OUT/img/...png")
    c.add_argument("--device", default=None)
    c.set_defaults(func=cmd_compare)

    s = sub.add_parser("save-scene", help="write a built-in scene to a scene file (.npz)")
    s.add_argument("scene")
    s.add_argument("path")
    s.add_argument("--width", type=COUNT, default=None)
    s.add_argument("--height", type=COUNT, default=None)
    s.set_defaults(func=cmd_save_scene)

    st = sub.add_parser("stress", help="stability on extreme scenes: NaN/Inf, max value, relMSE, flicker per method",
                        description="Render the built-in extreme scenes (restircl/eval/stress/suite.py) with every "
                                    "method and check them against their references; exit status 1 if any fails. "
                                    "The flicker, flk/err and boil px columns: the temporal stability of 16 "
                                    "consecutive TAA outputs of each case's frame under test.")
    st.add_argument("--full", action="store_true", help="full sizes (1e6 lights, 5000 frames, ...): minutes")
    st.add_argument("--methods", default=None, help="comma-separated subset (default: all)")
    st.add_argument("--cases", default=None, help="comma-separated subset (default: all)")
    st.add_argument("--out", default=None, help="write stress.csv and stress.json here")
    st.add_argument("--seed", type=Range(int, 0).parse, default=0, help="shift of every random seed (%(default)s)")
    st.add_argument("--device", default=None)
    st.add_argument("--bench-specialisation", action="store_true",
                    help="instead: kernel build and frame times, specialised against general builds")
    st.add_argument("--bench-frames", type=COUNT, default=24, help="frames timed per build (%(default)s)")
    st.set_defaults(func=cmd_stress)
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    sub = getattr(args, "settings_parser", None)
    if sub is not None:  # a setting out of range together with another one: an argparse error too
        try:
            args.settings = settings_from_args(args)
        except SettingError as exc:
            sub.error(f"argument {'/'.join(flag_of(Settings, n) for n in exc.names)}: {exc}")
    try:
        return int(args.func(args) or 0)
    except (DeviceError, KernelBuildError, SceneError, ValueError) as exc:
        print(f"restircl: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("restircl: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
