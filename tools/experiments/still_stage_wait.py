"""Frames per second of a still render with a wait for the device after every stage (the stage timer's rule before)
against none (the stage timer of a still frame now), alternated: docs/measurements/benchmarks.md, "Still frames
without a wait per stage". The wait is patched in and out of render/stages.py StageTimer.mark.

    python -m tools.experiments.still_stage_wait outdoor 4
"""

from __future__ import annotations

import sys
import time

from restircl import Renderer, Settings
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render import stages
from restircl.render.still_method import still_settings

UNPATCHED = stages.StageTimer.mark


def with_wait(self: stages.StageTimer, name: str) -> None:
    self.queue.finish()
    UNPATCHED(self, name)


def without_wait(self: stages.StageTimer, name: str) -> None:
    self.wait = False
    UNPATCHED(self, name)


def main() -> None:
    kind, bounces, n = sys.argv[1], int(sys.argv[2]), 96
    scene = scene_of_kind(kind, 192, 108)
    s = still_settings(Settings(**LightPaths.of(bounces).overrides()).validate(), scene)
    Renderer(scene, s).render_still(0, 2)  # the kernels' build, outside the timed renders
    try:
        for _ in range(3):
            for mode, mark in (("wait per stage", with_wait), ("no wait", without_wait)):
                stages.StageTimer.mark = mark  # type: ignore[method-assign]
                r = Renderer(scene, s)
                c0, t0 = time.process_time(), time.perf_counter()
                r.render_still(0, n)
                wall, cpu = (time.perf_counter() - t0) * 1e3 / n, (time.process_time() - c0) * 1e3 / n
                print(f"{kind} b{bounces} {mode:14s}: {wall:.1f} ms/frame wall, {cpu:.1f} CPU ms/frame", flush=True)
    finally:
        stages.StageTimer.mark = UNPATCHED  # type: ignore[method-assign]


if __name__ == "__main__":
    main()
