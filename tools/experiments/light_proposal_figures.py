"""Figures of the light tree against the light array (docs/measurements/benchmarks.md,
docs/measurements/error-vs-time.md), side by side in one run: for RIS and ReSTIR with candidates from either
proposal, the relMSE of one frame and of `frames` frames against a reference (the cached Cycles references of the
tuning garden and neon, never re-rendered: pass their cache dir; our own converged image for many_lights, cached
in --own-cache), the error at equal wall time, the frame time and the tree's build time, with the load average
before and after.

    python -m tools.experiments.light_proposal_figures --cache-dir /work/cache-compare23/refs \
        --kinds garden,neon,many_lights
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np
from restircl import Renderer, Settings, scenes
from restircl.eval.cycles.compare import REFERENCE_SPP, time_ours
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.held_out import held_out

METHODS = {
    "ris": dict(method="ris"),
    "ris_tree": dict(method="ris", light_proposal="tree"),
    "ris_tree_c2": dict(method="ris", light_proposal="tree", candidates=2),
    "ris_tree_c4": dict(method="ris", light_proposal="tree", candidates=4),
    "ris_c4": dict(method="ris", candidates=4),
    "restir": dict(method="restir"),
    "restir_tree": dict(method="restir", light_proposal="tree"),
}


def scene_and_reference(kind: str, cache_dir: Path, width: int, height: int, own_cache: Path):
    if kind == "many_lights":
        scene = scenes.many_lights(width=width, height=height, frames=1)
        return scene, get_reference(scene, 0, 60.0, cache_dir=own_cache).image
    scene = held_out(kind, width, height)
    # the file as cached, whatever digest of the scene model named it (never re-rendered here: 10-20 min each)
    found = sorted(cache_dir.glob(f"cycles_reference_{kind}_{width}x{height}_2x{REFERENCE_SPP}_*.npy"))
    if not found:
        raise SystemExit(f"no cached Cycles reference of {kind} at {width}x{height} in {cache_dir}")
    print(f"{kind}: Cycles reference {found[0]}")
    return scene, np.load(found[0])


def measure(kind: str, cache_dir: Path, own_cache: Path, frames: int, budgets: list[float], reps: int, width: int,
            height: int, methods: list[str]) -> dict:
    scene, ref = scene_and_reference(kind, cache_dir, width, height, own_cache)
    out: dict = {"kind": kind, "methods": {}}
    for m in methods:
        r = Renderer(scene, Settings(**METHODS[m], seed=7).validate())
        r.render_still(0, 2)  # kernels compiled, buffers uploaded
        singles = [rel_mse(r.render_frame(0, still=True).noisy[..., :3], ref) for _ in range(16)]
        r2 = Renderer(scene, Settings(**METHODS[m], seed=8).validate())
        r2.render_still(0, 2)
        t0 = time.perf_counter()
        img = r2.render_still(0, frames).color[..., :3]
        secs = time.perf_counter() - t0
        out["methods"][m] = {"frame_rel_mse": float(np.mean(singles)), "rel_mse_at_frames": rel_mse(img, ref),
                             "frames": frames, "ms_per_frame": 1e3 * secs / frames,
                             "tree_build_s": r.device_scene.tree_seconds if r.uses_light_tree else None,
                             "equal_time": {str(b): [] for b in budgets}}
        print(f"{kind:<11} {m:<12} 1 frame relMSE {np.mean(singles):.3e}  {frames} frames {rel_mse(img, ref):.3e}"
              f"  {1e3 * secs / frames:7.1f} ms/frame", flush=True)
    for rep in range(reps):  # in turn, so that a change of the machine's load spreads over all of them
        for b in budgets:
            for m in methods:
                s = Settings(**METHODS[m], seed=100 + rep).validate()
                img, secs, _, n = time_ours(scene, s, b)
                out["methods"][m]["equal_time"][str(b)].append({"rel_mse": rel_mse(img, ref), "samples": n})
                print(f"{kind:<11} {m:<12} {b:4.1f} s rep {rep}: {n:5d} frames, relMSE {rel_mse(img, ref):.3e}",
                      flush=True)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cache-dir", required=True)
    p.add_argument("--own-cache", default="out/refs", help="where our converged many_lights image is cached")
    p.add_argument("--kinds", default="garden,neon,many_lights")
    p.add_argument("--methods", default=",".join(METHODS))
    p.add_argument("--frames", type=int, default=64)
    p.add_argument("--budgets", default="1,4")
    p.add_argument("--reps", type=int, default=2)
    p.add_argument("--width", type=int, default=192)
    p.add_argument("--height", type=int, default=108)
    p.add_argument("--out", default="out/light_proposal.json")
    a = p.parse_args()
    load = os.getloadavg()
    budgets = [float(b) for b in a.budgets.split(",")]
    res = [measure(k, Path(a.cache_dir), Path(a.own_cache), a.frames, budgets, a.reps, a.width, a.height,
                   a.methods.split(",")) for k in a.kinds.split(",")]
    meta = {"load_before": load, "load_after": os.getloadavg()}
    print(f"load average before {load[0]:.2f}, after {meta['load_after'][0]:.2f}")
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps({"meta": meta, "results": res}, indent=1))
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
