"""`restircl bench filter`: the real-time filter's cost (Settings.realtime_filter, filter_iterations) at 640x360.

The default ReSTIR + TAA frame of many_lights' flythrough without the filter and with it at 1..5 a-trous iterations,
measured side by side: the variants take turns, one block of frames each per round, so that a change of the
machine's load falls on all of them alike. Printed: the median ms per frame, the filter stage's mean ms, and the
frame's ms less the unfiltered frame's."""

from __future__ import annotations

import argparse

import numpy as np

from ...render.pipeline import Renderer
from ...scenes.builtin import many_lights
from ...settings.table import Settings
from .timing import time_frames

ITERATIONS = (1, 2, 3, 4, 5)


def bench_filter(width: int, height: int, device=None, rounds: int = 3, frames: int = 6, print_fn=print,
                 iterations: tuple[int, ...] = ITERATIONS) -> dict[str, dict[str, float]]:
    scene = many_lights(width=width, height=height, frames=16)
    variants: dict[str, Settings] = {"off": Settings()}
    for k in iterations:
        variants[f"{k} iterations"] = Settings(realtime_filter=True, filter_iterations=k)
    renderers = {name: Renderer(scene, s, device) for name, s in variants.items()}
    ms: dict[str, list[float]] = {name: [] for name in variants}
    stage: dict[str, list[float]] = {name: [] for name in variants}
    for rnd in range(rounds):
        for name, r in renderers.items():
            m, st = time_frames(scene, variants[name], frames=frames, warmup=3 if rnd == 0 else 1, device=device,
                                renderer=r)
            ms[name].append(m)
            stage[name].append(st.get("filter", 0.0))
    print_fn(f"real-time filter, many_lights {width}x{height}, default ReSTIR + TAA, animated camera: median ms per "
             f"frame over {rounds} rounds of {frames} frames, variants in turn")
    print_fn(f"  {'variant':<14} {'frame ms':>9} {'filter ms':>10} {'frame - off':>12}")
    out: dict[str, dict[str, float]] = {}
    base = float(np.median(ms["off"]))
    for name in variants:
        m = float(np.median(ms[name]))
        f = float(np.mean(stage[name]))
        out[name] = {"frame_ms": m, "filter_ms": f, "extra_ms": m - base}
        print_fn(f"  {name:<14} {m:9.1f} {f:10.1f} {m - base:12.1f}")
    return out


def main(a: argparse.Namespace) -> int:
    from ...core.device import get_device

    dev = get_device(a.device)
    print(f"device: {dev.label}")
    bench_filter(a.width, a.height, dev)
    return 0
