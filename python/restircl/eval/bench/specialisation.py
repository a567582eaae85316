"""The benchmark of specialised against general kernel builds (`restircl stress --bench-specialisation`, DESIGN
section 6)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable

_BENCH_CHILD = r"""
import json, sys, time
import restircl.render.pipeline as P
from restircl import Renderer, Settings
from restircl.eval.bench.scenes import bench_scene
name, specialise, frames, still = sys.argv[1], sys.argv[2] == "1", int(sys.argv[3]), sys.argv[4] == "1"
build_cpu = {}
_build = P.build_program
def timed_build(*args, **kw):
    c0 = time.process_time()
    prog = _build(*args, **kw)
    build_cpu["s"] = time.process_time() - c0
    return prog
P.build_program = timed_build
scene = bench_scene(name)
r = Renderer(scene, Settings(method="restir", specialise=specialise, jitter=not still))
render = (lambda i: r.render_frame(0, still=True)) if still else (lambda i: r.render_frame(i % scene.frames))
t0, c0 = time.perf_counter(), time.process_time()
render(0)
first, first_cpu = time.perf_counter() - t0, time.process_time() - c0
walls = []
c0 = time.process_time()
for i in range(1, frames + 1):
    t0 = time.perf_counter()
    render(i)
    walls.append(time.perf_counter() - t0)
cpu = (time.process_time() - c0) / frames
walls.sort()
print(json.dumps(dict(build_s=r.build_seconds, build_cpu_s=build_cpu["s"], first_s=first, first_cpu_s=first_cpu,
                      frame_ms=1e3 * walls[len(walls) // 2], frame_cpu_ms=1e3 * cpu, features=r.features)))
"""


def bench_specialisation(frames: int = 24, log: Callable[[str], None] | None = None) -> list[dict]:
    """Kernel build time, first frame (PoCL generates each kernel's machine code when it first runs) and the
    per-frame time after it (median wall, mean CPU), ReSTIR at 320x180, specialised against general builds. Each
    measurement runs in a fresh process with empty PoCL and pyopencl caches, so that builds are real. CPU times
    sum all threads of the process: on a shared machine they are the figures to compare."""
    rows = []
    for name, still in (("points", False), ("meshes", False), ("still", True)):
        for specialise in (True, False):
            with tempfile.TemporaryDirectory(prefix="restircl-bench-") as tmp:
                env = dict(os.environ, POCL_CACHE_DIR=os.path.join(tmp, "pocl"),
                           PYOPENCL_CACHE_DIR=os.path.join(tmp, "pyopencl"))
                out = subprocess.run([sys.executable, "-c", _BENCH_CHILD, name, str(int(specialise)), str(frames),
                                      str(int(still))], env=env, capture_output=True, text=True, check=True)
            row = dict(scene=name, build="specialised" if specialise else "general", **json.loads(
                out.stdout.strip().splitlines()[-1]))
            rows.append(row)
            if log:
                log(f"{name:7s} {row['build']:11s} build {row['build_s']:5.2f} s ({row['build_cpu_s']:5.2f} cpu)  "
                    f"first frame {row['first_s']:5.2f} s ({row['first_cpu_s']:5.2f} cpu)  then "
                    f"{row['frame_ms']:6.1f} ms/frame ({row['frame_cpu_ms']:6.1f} cpu)  "
                    f"[{', '.join(row['features'])}]")
    return rows
