"""Frame time of a glossy scene against its diffuse twin (material_balls with its materials, and with every one
replaced by a diffuse material of the same colour), side by side: `python -m restircl.eval.bench.glossy`.
Each pair is timed in alternation, `rounds` times, so that a change in the machine's load hits both."""

from __future__ import annotations

import argparse

import numpy as np

from ...render.pipeline import Renderer
from ...scenes.builtin import material_balls
from ...settings.table import Settings
from .timing import time_frames

METHODS = {"ris": {"method": "ris", "candidates": 8}, "restir": {"method": "restir"}}


def bench_glossy(width: int, height: int, rounds: int = 3, device=None, print_fn=print) -> dict:
    rows = {}
    for name, kw in METHODS.items():
        rs = {twin: Renderer(material_balls(width, height, frames=8, diffuse=twin == "diffuse"), Settings(**kw),
                             device) for twin in ("glossy", "diffuse")}
        ms: dict[str, list[float]] = {twin: [] for twin in rs}
        for _ in range(rounds):
            for twin, r in rs.items():
                m, _ = time_frames(r.scene, r.settings, frames=6, warmup=2, renderer=r)
                ms[twin].append(m)
        g, d = float(np.median(ms["glossy"])), float(np.median(ms["diffuse"]))
        print_fn(f"{name:7s} {width}x{height}: glossy {g:7.1f} ms  diffuse twin {d:7.1f} ms  ratio {g / d:.2f}  "
                 f"(features {', '.join(rs['glossy'].features)} / {', '.join(rs['diffuse'].features)}; "
                 f"rounds {ms})")
        rows[name] = (g, d)
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--height", type=int, default=180)
    p.add_argument("--rounds", type=int, default=3)
    a = p.parse_args()
    bench_glossy(a.width, a.height, a.rounds)


if __name__ == "__main__":
    main()
