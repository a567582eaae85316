"""The path pass's cost (Settings.max_bounces, opencl/path/): the default ReSTIR + TAA frame of many_lights with
Max Bounces 0, 1, 2, 4 and 8 side by side in one run, the path stage's milliseconds, and its nanoseconds per pixel
and bounce of the budget (Russian roulette and the bounce limits end most paths earlier, so the longer budgets cost
less per bounce). Printed by `restircl bench frame` after the floor."""

from __future__ import annotations

from ...render.pipeline import Renderer
from ...scenes.builtin import many_lights
from ...settings.table import Settings
from .timing import time_frames

BUDGETS = (0, 1, 2, 4, 8)


def bench_paths(width: int, height: int, device=None, frames: int = 6, budgets: tuple[int, ...] = BUDGETS,
                print_fn=print) -> dict[int, tuple[float, float]]:
    """{max_bounces: (frame ms, path stage ms)} of the default frame of many_lights."""
    scene = many_lights(width=width, height=height, frames=16)
    out: dict[int, tuple[float, float]] = {}
    print_fn(f"many_lights {width}x{height}, default ReSTIR + TAA with bounces (diffuse and glossy limits as the "
             f"total; median of {frames} frames):")
    for b in budgets:
        s = Settings(max_bounces=b, diffuse_bounces=b, glossy_bounces=b)
        ms, st = time_frames(scene, s, frames=frames, device=device, renderer=Renderer(scene, s, device))
        path_ms = st.get("paths", 0.0)
        out[b] = (ms, path_ms)
        per = f", {path_ms * 1e6 / (width * height * b):.0f} ns per pixel and bounce" if b else ""
        print_fn(f"  max bounces {b:>2}: {ms:7.1f} ms per frame, path stage {path_ms:6.1f} ms{per}")
    return out
