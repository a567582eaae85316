"""`restircl bench`: benchmark figures, printed (run by hand; never timed tests).

    traversal  BVH build and Mrays/s for camera and shadow rays, ours vs Embree (eval/bench/traversal.py)
    frame      ms per frame and per stage for every method on many_lights at 640x360, then the default frame
               and the lightest ReSTIR frame against the floor (camera ray, shadow ray, TAA), then the default
               frame with 0-8 bounces (eval/bench/paths.py)
    lights     ReSTIR frame time against the number of lights, 1e2 .. 1e6 emissive triangles
    taa        relMSE against frame number with TAA on and off (still and moving camera), TAA pass ms
    filter     the real-time filter's ms per frame at 1..5 iterations against the frame without it
    (eval/bench/filter.py, which the command line calls after this module's main); every frame timed by
               time_frames (eval/bench/timing.py)
"""

from __future__ import annotations

import argparse
import gc
import math
import time

import numpy as np

from ...lights.array import build_light_array
from ...lights.device_lights import scene_lights
from ...render.pipeline import Renderer
from ...scenes.builtin import many_lights
from ...settings.table import Settings
from ..metrics import rel_mse
from . import traversal as bench_traversal
from .frame_profile import floor_of
from .paths import bench_paths
from .scenes import light_scaling_scene
from .timing import time_frames

FRAME_METHODS: dict[str, dict] = {
    "uniform": dict(method="uniform"),
    "light_array": dict(method="light_array"),
    "ris (8)": dict(method="ris", candidates=8),
    "restir unbiased (4)": dict(method="restir", candidates=4),
    "restir unbiased (8)": dict(method="restir", candidates=8),
    "restir unbiased, no vis. reuse (4)": dict(method="restir", candidates=4, visibility_reuse=False),
    "restir biased (4)": dict(method="restir", candidates=4, bias_correction="none"),
    "restir biased, no vis. reuse (4)": dict(method="restir", candidates=4, bias_correction="none",
                                             visibility_reuse=False),
}


def bench_frame(width: int, height: int, device=None, print_fn=print) -> dict:
    scene = many_lights(width=width, height=height, frames=16)
    out = {}
    print_fn(f"many_lights {width}x{height}, animated camera, TAA on; ms per frame (median of 6 after 3 warm-up)")
    for name, kw in FRAME_METHODS.items():
        ms, st = time_frames(scene, Settings(**kw), device=device)
        out[name] = (ms, st)
        stages = ", ".join(f"{k} {v:.1f}" for k, v in st.items() if k not in ("upload", "cpu"))
        print_fn(f"  {name:<36} {ms:8.1f} ms  (CPU {st['cpu']:7.1f} ms)   [{stages}]")
    return out


#: the cheapest frame that still runs every ReSTIR pass: one light candidate, no BSDF candidate, no visibility
#: reuse (one shadow ray, in the shading). What is left above the floor is the reuse passes' own work, which no
#: cheaper candidate or fewer shadow rays can remove.
LIGHTEST_RESTIR: dict = dict(method="restir", candidates=1, bsdf_sampling="off", visibility_reuse=False)


def bench_floor(width: int, height: int, device=None, frames: int = 12, print_fn=print) -> dict:
    """The default ReSTIR + TAA frame (Settings()) of many_lights against the floor of one camera ray and one
    shadow ray per pixel plus TAA (frame_profile.floor_of), measured in one run: per stage ms and the ratio; and
    the lightest ReSTIR frame (LIGHTEST_RESTIR) against the same floor, the ratio below which the default cannot go
    while it keeps temporal and spatial reuse."""
    scene = many_lights(width=width, height=height, frames=16)
    ms, st = time_frames(scene, Settings(), frames=frames, device=device)
    la_ms, la = time_frames(scene, Settings(method="light_array"), frames=frames, device=device)
    lite_ms, lite = time_frames(scene, Settings(**LIGHTEST_RESTIR), frames=frames, device=device)
    floor = floor_of(la, st.get("taa", 0.0))
    stages = ", ".join(f"{k} {v:.1f}" for k, v in st.items() if k != "cpu")
    print_fn(f"many_lights {width}x{height}, default ReSTIR + TAA (median of {frames} frames): {ms:.1f} ms = "
             f"[{stages}] + read-back")
    print_fn(f"  floor: camera rays {floor['camera_ms']:.1f} + one shadow ray {floor['shadow_ms']:.1f} (light_array "
             f"frame, {la_ms:.1f} ms in all) + TAA {floor['taa_ms']:.1f} = {floor['ms']:.1f} ms")
    ratio = ms / floor["ms"] if floor["ms"] > 0 else math.nan
    print_fn(f"  default frame / floor: {ratio:.2f} (goal 1.5)")
    lite_ratio = lite_ms / floor["ms"] if floor["ms"] > 0 else math.nan
    lite_stages = ", ".join(f"{k} {v:.1f}" for k, v in lite.items() if k not in ("upload", "cpu"))
    print_fn(f"  lightest ReSTIR frame (1 candidate, no BSDF candidate, no visibility reuse): {lite_ms:.1f} ms = "
             f"[{lite_stages}], / floor: {lite_ratio:.2f}")
    return {"ms": ms, "stages_ms": st, "floor": floor, "ratio": ratio,
            "lightest_ms": lite_ms, "lightest_stages_ms": lite, "lightest_ratio": lite_ratio}


def bench_lights(width: int, height: int, sizes=(100, 1000, 10_000, 100_000, 1_000_000), device=None,
                 print_fn=print, kind: str = "triangles") -> list[tuple]:
    rows = []
    print_fn(f"ReSTIR (4 candidates, unbiased) + TAA frame time against the number of "
             f"{dict(points='point', triangles='emissive-triangle', panels='flat emissive-triangle')[kind]} "
             "lights, "
             f"{width}x{height}, camera still; lit: share of pixels showing a non-emissive surface")
    print_fn(f"  {'lights':>9} {'triangles':>10} {'lit %':>6} {'setup s':>7} {'array s':>8} {'ms/frame':>9}   stages"
             "   (setup: Renderer construction, which includes array s: lights converted and light array built)")
    for n in sizes:
        scene = light_scaling_scene(n, width, height, kind=kind)
        # 1e6 Light objects make every full garbage collection long, and one lands in some frame: keep the
        # scene out of the collector while timing (gc.freeze, undone below)
        gc.collect()
        gc.freeze()
        settings = Settings(method="restir", candidates=4)
        t0 = time.perf_counter()
        r = Renderer(scene, settings, device)
        setup = time.perf_counter() - t0
        albedo = r.render_frame(0).albedo
        lit = 100.0 * float(np.mean(albedo.sum(axis=-1) > 0)) if albedo is not None else math.nan
        t1 = time.perf_counter()  # the part of the set-up spent on the lights, timed again on its own
        lights = scene_lights(scene, 0)
        build_light_array(lights.power)
        t_array = time.perf_counter() - t1
        ms, st = time_frames(scene, settings, device=device, still=False, renderer=r)
        del r
        stages = ", ".join(f"{k} {v:.1f}" for k, v in st.items() if k != "upload")
        print_fn(f"  {len(lights):>9} {scene.triangle_count:>10} {lit:6.1f} {setup:7.2f} {t_array:8.3f} {ms:9.1f}   "
                 f"[{stages}]")
        rows.append((len(lights), scene.triangle_count, lit, setup, t_array, ms, st))
        gc.unfreeze()
    return rows


def bench_taa(width: int, height: int, frames: int = 32, device=None, print_fn=print,
              plot: str | None = None) -> dict:
    """relMSE against frame number, TAA on and off, for a still and for a moving camera (moving_box: camera pan and
    a moving object, per-frame references), with RIS (8 candidates); and the ms of the TAA pass."""
    from ...scenes.builtin import moving_box

    curves: dict[str, list[float]] = {}
    for motion in ("still", "moving"):
        scene = moving_box(width, height, frames=frames if motion == "moving" else 1)
        refs = []
        ref_r = Renderer(scene, Settings(method="reference", seed=99), device)
        for f in range(scene.frames):
            refs.append(ref_r.render_still(f, 256).color[..., :3])
        for label, kw in (("taa a_min=0.1", dict(taa=True)), ("taa a=1/n", dict(taa=True, alpha_min=0.0)),
                          ("off", dict(taa=False))):
            if motion == "moving" and label == "taa a=1/n":
                continue
            r = Renderer(scene, Settings(method="ris", candidates=8, seed=5, **kw), device)
            errs = []
            for f in range(frames):
                idx = f if motion == "moving" else 0
                out = r.render_frame(idx)
                errs.append(rel_mse(out.color[..., :3], refs[idx]))
            curves[f"{motion}, {label}"] = errs
    marks = [0, 1, 3, 7, 15, 31, frames - 1]
    marks = sorted({m for m in marks if m < frames})
    print_fn(f"relMSE against frame number (moving_box {width}x{height}, RIS 8 candidates, per-frame references)")
    print_fn(f"  {'':<24}" + "".join(f"{m + 1:>10}" for m in marks))
    for k, v in curves.items():
        print_fn(f"  {k:<24}" + "".join(f"{v[m]:>10.4f}" for m in marks))
    scene = many_lights(width=640, height=360, frames=16)
    _, st = time_frames(scene, Settings(method="ris", candidates=4), device=device)
    print_fn(f"TAA pass at 640x360 (many_lights): {st.get('taa', float('nan')):.1f} ms")
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.5, 4.2), dpi=110)
        for k, v in curves.items():
            ax.plot(np.arange(1, frames + 1), v, label=k, ls="-" if k.startswith("still") else "--")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("frame")
        ax.set_ylabel("relMSE vs per-frame reference")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(plot)
        plt.close(fig)
        print_fn(f"wrote {plot}")
    curves["taa_ms_640x360"] = [st.get("taa", float("nan"))]
    return curves


def main(a: argparse.Namespace) -> int:
    from ...core.device import get_device

    dev = get_device(a.device)
    print(f"device: {dev.label}")
    if a.what in ("traversal", "all"):
        bench_traversal.run(triangles=a.triangles, width=a.width, height=a.height, embree=not a.no_embree,
                            device=dev)
    if a.what in ("frame", "all"):
        bench_frame(a.width, a.height, dev)
        bench_floor(a.width, a.height, dev)
        bench_paths(a.width, a.height, dev)
    if a.what in ("lights", "all"):
        bench_lights(a.width, a.height, device=dev)
        bench_lights(a.width, a.height, device=dev, kind="panels")
        bench_lights(a.width, a.height, device=dev, kind="points")
    if a.what in ("taa", "all"):
        bench_taa(160, 120, device=dev, plot="taa_error.png")
    return 0
