"""Issue 23: CPU ms (all threads of the process) per frame stage of Settings variants on many_lights, interleaved
round by round in one process. CPU time is steadier than wall time on the shared machine; it counts what the
device's threads spent on a stage, not how long it waited for a core.

    python -m tools.experiments.stage_cpu \
        '{"default": {}, "ris8": {"settings": {"method": "ris"}}, "l256": {"local": 256}}' \
        [--rounds 3] [--frames 4] [--width 640 --height 360]

A variant is {"settings": Settings keywords, "local": work-items per work-group (kernels.LOCAL_ITEMS; 8x8 stays
the 2D shape for 64), "shape": [x, y], the work-group shape of the 2D kernels (e.g. [64, 1]: rows of pixels),
"opencl": a directory of kernel sources to build this variant from (another checkout's opencl/, to compare kernel
changes side by side in one process; the host code stays this checkout's), "module": {"bvh_packets.ENABLED":
false} (restircl module constants while the variant's renderer is built)}.
Prints the median over the frames of each stage and of their sum.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import statistics
import time
from pathlib import Path

import pyopencl as cl
from restircl import Renderer, Settings
from restircl.core import kernels, program
from restircl.render import pipeline, stages
from restircl.scenes.builtin import many_lights

_LAST: dict[str, dict[str, float]] = {}
_LOCAL: list[int | None] = [None]
_SHAPE: list[tuple[int, int] | None] = [None]
_local_size = kernels.local_size
_opencl_dir = program.opencl_dir


def _use_opencl(path: str | None) -> None:
    """Build and launch kernels from `path` (None: this checkout's opencl/) until the next call."""
    def where() -> Path:
        return Path(path) if path else _opencl_dir()
    program.opencl_dir = where  # type: ignore[assignment]
    kernels.opencl_dir = where  # type: ignore[assignment]


class CpuStageTimer(stages.StageTimer):
    """The stage timer, also keeping the process's CPU ms per stage (in _LAST["cpu"])."""

    def __init__(self, queue: cl.CommandQueue) -> None:
        super().__init__(queue)
        self.c = time.process_time()
        self.cpu: dict[str, float] = {}
        _LAST["cpu"] = self.cpu

    def mark(self, name: str) -> None:
        super().mark(name)
        c1 = time.process_time()
        self.cpu[name] = self.cpu.get(name, 0.0) + (c1 - self.c) * 1e3
        self.c = c1


def _variant_local_size(dims: int, max_items: int) -> tuple[int, ...]:
    shape = _SHAPE[0]
    if dims == 2 and shape is not None and shape[0] * shape[1] <= max_items:
        return shape
    if _LOCAL[0] is None:
        return _local_size(dims, max_items)
    saved = kernels.LOCAL_ITEMS
    kernels.LOCAL_ITEMS = _LOCAL[0]
    try:
        return _local_size(dims, max_items)
    finally:
        kernels.LOCAL_ITEMS = saved


def _renderer(scene, variant: dict) -> Renderer:
    """The variant's Renderer, built with its "module" constants (restircl submodule attributes, e.g.
    {"bvh_packets.ENABLED": false}) set while its program is built and its scene uploaded."""
    saved = {}
    for key, value in variant.get("module", {}).items():
        mod, attr = key.rsplit(".", 1)
        m = importlib.import_module(f"restircl.{mod}")
        saved[(m, attr)] = getattr(m, attr)
        setattr(m, attr, value)
    try:
        return Renderer(scene, Settings(**variant.get("settings", {})))
    finally:
        for (m, attr), value in saved.items():
            setattr(m, attr, value)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variants", help="JSON: name -> {settings: {...}, local: n}")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--frames", type=int, default=4, help="frames per variant and round")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    a = ap.parse_args()
    pipeline.StageTimer = CpuStageTimer  # type: ignore[misc]
    kernels.local_size = _variant_local_size
    variants: dict[str, dict] = json.loads(a.variants)
    scene = many_lights(width=a.width, height=a.height, frames=16)
    renderers = {}
    for n, v in variants.items():
        _use_opencl(v.get("opencl"))
        renderers[n] = _renderer(scene, v)
    frame = dict.fromkeys(renderers, 0)
    cpu: dict[str, dict[str, list[float]]] = {n: {} for n in renderers}
    totals: dict[str, list[float]] = {n: [] for n in renderers}  # per frame (a stage such as upload may be absent)
    print(f"many_lights {a.width}x{a.height}, load {os.getloadavg()}", flush=True)
    for rnd in range(a.rounds + 1):  # round 0: warm-up (program build, uploads, history)
        for n, r in renderers.items():
            _LOCAL[0] = variants[n].get("local")
            _use_opencl(variants[n].get("opencl"))
            shape = variants[n].get("shape")
            _SHAPE[0] = (int(shape[0]), int(shape[1])) if shape else None
            for _ in range(a.frames):
                r.render_frame(frame[n] % scene.frames, aovs=False)
                frame[n] += 1
                if rnd > 0:
                    for k, v in _LAST["cpu"].items():
                        cpu[n].setdefault(k, []).append(v)
                    totals[n].append(sum(_LAST["cpu"].values()))
        print(f"round {rnd} done, load {os.getloadavg()}", flush=True)
    for n, d in cpu.items():
        total = totals[n]
        parts = " ".join(f"{k} {statistics.median(v):6.1f}" for k, v in d.items() if k != "upload")
        print(f"{n:<16} CPU ms {statistics.median(total):7.1f} = [{parts}]")


if __name__ == "__main__":
    main()
