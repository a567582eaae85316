"""Time to the first image of a still (`restircl bench first-image`): what lies between a fresh process and the
first finished frame of F12, per phase, each configuration in a process of its own (nothing warm but what the
configuration says): importing restircl, building the scene, the renderer's parts (the scene's upload with its BVH,
the GGX tables of glossy scenes, the kernel build) and the first still frame; once with an empty kernel cache (PoCL
and pyopencl compile everything: a first F12 after installing) and once with the cache that run left (every later
F12 of the same features). `--computed-tables` times the GGX tables computed in the process instead of read from
the package (the cost before they shipped)."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

SCENES = ("material_balls", "textured_room")


def _child(scene_name: str, width: int, height: int, computed_tables: bool, start: float) -> dict[str, float]:
    """The phases of one first image, in this process (run by run_child), from `start`: the process's clock
    before it imported anything of restircl."""
    t = {"start": start}
    import restircl
    from restircl.upload import device_scene, ggx_tables

    t["import"] = time.perf_counter()
    scene = restircl.scenes.builtin(scene_name, width=width, height=height)
    settings = restircl.still_settings(restircl.Settings(), scene)
    t["scene"] = time.perf_counter()
    if computed_tables:  # the path before the tables shipped: the quadrature in every new process
        device_scene.ggx_tables = ggx_tables.compute_ggx_tables
    tables = {"s": 0.0}
    upload = device_scene.DeviceScene.upload_ggx_tables

    def timed_upload(self) -> None:
        t0 = time.perf_counter()
        upload(self)
        tables["s"] += time.perf_counter() - t0

    device_scene.DeviceScene.upload_ggx_tables = timed_upload
    r = restircl.Renderer(scene, settings)
    t["renderer"] = time.perf_counter()
    r.render_still(0, samples=1)
    t["first frame"] = time.perf_counter()
    return {"import": t["import"] - t["start"], "scene": t["scene"] - t["import"],
            "renderer": t["renderer"] - t["scene"], "  of which the kernel build": r.build_seconds,
            "  of which the GGX tables": tables["s"], "  of which the BVH": r.bvh_seconds,
            "first frame": t["first frame"] - t["renderer"], "total": t["first frame"] - t["start"]}


def run_child(scene_name: str, width: int, height: int, cache_dir: str, computed_tables: bool) -> dict[str, float]:
    env = {**os.environ, "POCL_CACHE_DIR": os.path.join(cache_dir, "pocl"),
           "PYOPENCL_CACHE_DIR": os.path.join(cache_dir, "pyopencl")}
    code = (f"import json, time; t0 = time.perf_counter(); from restircl.eval.bench.first_image import _child; "
            f"print(json.dumps(_child({scene_name!r}, {width}, {height}, {computed_tables}, t0)))")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def bench_first_image(width: int = 320, height: int = 180, scenes: tuple[str, ...] = SCENES,
                      computed_tables: bool = False, print_fn=print) -> dict[str, dict[str, dict[str, float]]]:
    """{scene: {"cold": phases, "warm": phases}} in seconds."""
    out: dict[str, dict[str, dict[str, float]]] = {}
    for name in scenes:
        with tempfile.TemporaryDirectory(prefix="restircl-first-image-") as cache:
            runs = {k: run_child(name, width, height, cache, computed_tables) for k in ("cold", "warm")}
        out[name] = runs
        tables = "computed in the process" if computed_tables else "shipped"
        print_fn(f"{name} {width}x{height}, F12's settings, GGX tables {tables}: seconds to the first still frame")
        for phase in runs["cold"]:
            print_fn(f"  {phase:<30} cold cache {runs['cold'][phase]:6.2f}   warm cache {runs['warm'][phase]:6.2f}")
    return out


def main(a: argparse.Namespace) -> int:
    bench_first_image(a.width, a.height, computed_tables=getattr(a, "computed_tables", False))
    return 0
