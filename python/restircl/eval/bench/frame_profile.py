"""Where the fixed cost of a small frame goes (issue 23, "cheaper samples"): the default ReSTIR + TAA frame of a
300-light scene at 192x108 through the Python API, per stage (the stage timers, each of which waits for the
device), the read-back and the Python around it, and a cProfile of the same frames grouped into launches,
waits, copies and the rest; beside it the floor of one camera ray + one shadow ray per pixel + TAA, measured in
the same run (the camera-ray and shade stages of a light-array frame, one light pick and one shadow ray per
pixel, and the TAA stage of the ReSTIR frame).

    python -m restircl.eval.bench.frame_profile [--kind garden] [--width 192 --height 108] [--frames 64]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import statistics
import time

from ...render.pipeline import Renderer
from ...settings.table import Settings
from ..scenes.held_out import held_out

# cProfile entries, by function name, grouped by what they are
GROUPS = {
    # kernels.launch and pyopencl's calls it makes (binding the arguments, enqueueing)
    "kernel launches": ("launch", "enqueue_nd_range_kernel", "__call__", "set_args", "set_arg", "_set_args"),
    # the stage timer's mark is queue.finish() (pyopencl's C++ calls are not profiled apart from their caller)
    "waits for the device": ("mark", "finish"),
    "copies and fills": ("enqueue_copy", "_enqueue_copy_buffer", "enqueue_fill_buffer", "_enqueue_write_buffer",
                         "_enqueue_read_buffer"),
}


def _frames(r: Renderer, n: int, aovs: bool) -> tuple[list[float], dict[str, float]]:
    walls, stages = [], {}
    for _ in range(n):
        t0 = time.perf_counter()
        f = r.render_frame(0, aovs=aovs)
        walls.append((time.perf_counter() - t0) * 1e3)
        for k, v in f.stage_ms.items():
            stages[k] = stages.get(k, 0.0) + v / n
    return walls, stages


def grouped_profile(r: Renderer, n: int) -> tuple[float, dict[str, float]]:
    """Wall ms per frame under cProfile and the self time per frame of each group of GROUPS (the rest: Python)."""
    prof = cProfile.Profile()
    t0 = time.perf_counter()
    prof.enable()
    for _ in range(n):
        r.render_frame(0, aovs=False)
    prof.disable()
    wall = (time.perf_counter() - t0) * 1e3 / n
    st = pstats.Stats(prof)
    out = {g: 0.0 for g in GROUPS}
    total = 0.0
    for (_, _, name), (_, _, tt, _, _) in st.stats.items():  # type: ignore[attr-defined]
        total += tt
        for g, names in GROUPS.items():  # builtins are named "<method 'finish' of '...' objects>"
            if name in names or any(f"'{n}'" in name for n in names):
                out[g] += tt * 1e3 / n
                break
    out["Python and the rest"] = total * 1e3 / n - sum(out.values())
    return wall, out


def floor_of(light_array_stages: dict[str, float], taa_ms: float) -> dict[str, float]:
    """The floor of a frame from the stage times of a light_array frame (its camera rays; its shade stage, one
    light pick and one shadow ray per pixel) and the TAA stage of the frame it is compared with."""
    out = {"camera_ms": light_array_stages.get("primary", 0.0), "shadow_ms": light_array_stages.get("shade", 0.0),
           "taa_ms": taa_ms}
    out["ms"] = out["camera_ms"] + out["shadow_ms"] + taa_ms
    return out


def profile(kind: str = "garden", width: int = 192, height: int = 108, frames: int = 64, device=None) -> dict:
    scene = held_out(kind, width, height)
    restir = Renderer(scene, Settings(), device)
    floor_r = Renderer(scene, Settings(method="light_array"), device)
    for r in (restir, floor_r):  # compile, first uploads, history
        _frames(r, 4, False)
    out: dict = {"scene": f"{kind} {width}x{height}", "lights": len(restir.lights), "frames": frames}
    for aovs in (False, True):
        walls, stages = _frames(restir, frames, aovs)
        out[f"restir aovs={aovs}"] = {"wall_ms": statistics.median(walls), "stages_ms": stages,
                                      "outside_stages_ms": statistics.fmean(walls) - sum(stages.values())}
    walls, stages = _frames(floor_r, frames, False)
    out["floor"] = floor_of(stages, out["restir aovs=False"]["stages_ms"].get("taa", 0.0))
    out["floor"]["light_array_wall_ms"] = statistics.median(walls)
    out["ratio_to_floor"] = out["restir aovs=False"]["wall_ms"] / out["floor"]["ms"]
    wall, groups = grouped_profile(restir, frames)
    out["cprofile"] = {"wall_ms": wall, "self_ms": groups}
    return out


def format_profile(p: dict) -> str:
    lines = [f"{p['scene']}, {p['lights']} lights, default ReSTIR + TAA, median of {p['frames']} frames"]
    for key in ("restir aovs=False", "restir aovs=True"):
        d = p[key]
        st = ", ".join(f"{k} {v:.2f}" for k, v in d["stages_ms"].items())
        lines.append(f"  {key}: {d['wall_ms']:.2f} ms per frame = stages [{st}] + "
                     f"{d['outside_stages_ms']:.2f} ms outside them (read-back, Python; from the mean frame)")
    f = p["floor"]
    lines.append(f"  floor: camera rays {f['camera_ms']:.2f} + one shadow ray (light_array shade) "
                 f"{f['shadow_ms']:.2f} + TAA {f['taa_ms']:.2f} = {f['ms']:.2f} ms; ReSTIR frame / floor "
                 f"{p['ratio_to_floor']:.2f}")
    c = p["cprofile"]
    lines.append(f"  cProfile ({c['wall_ms']:.2f} ms per frame under the profiler), self time per frame: " +
                 ", ".join(f"{k} {v:.2f} ms" for k, v in c["self_ms"].items()))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m restircl.eval.bench.frame_profile", description=__doc__)
    ap.add_argument("--kind", default="garden")
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--height", type=int, default=108)
    ap.add_argument("--frames", type=int, default=64)
    ap.add_argument("--device", default=None)
    a = ap.parse_args(argv)
    print(format_profile(profile(a.kind, a.width, a.height, a.frames, a.device)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
