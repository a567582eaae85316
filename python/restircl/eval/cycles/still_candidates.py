"""Which estimator converges fastest on a still camera (the measurement behind render/still_method.py, issue 23).

Per tuning scene kind and per candidate (cycles_compare.OURS: Settings overrides), a still render of `samples`
frames, its relMSE against the cached 2 x 1024-spp Cycles reference, and its seconds per sample: wall clock and
the process's CPU time (every PoCL thread), which a loaded machine disturbs less. The figure of merit of an
unbiased estimator is the inverse efficiency relMSE x seconds (constant while relMSE falls as 1/n): the smaller,
the better. Where reuse correlates the frames relMSE falls slower than 1/n, so two sample counts are taken and the
product is compared at each.

    python -m restircl.eval.cycles.still_candidates [--kinds studio,neon,garden] [--samples 32,128]
        [--methods default,ris,...] [--cache-dir DIR]

Needs bpy (the reference's cache key) and the cached references (`restircl compare` makes them).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

from ...render.pipeline import Renderer
from ..metrics import rel_mse
from ..scenes.held_out import HEIGHT, KINDS, WIDTH, held_out
from . import bridge as cycles
from .compare import OURS, REFERENCE_SPP, cycles_reference, ours_settings


def measure(kind: str, methods, samples=(32, 128), cache_dir: Path | None = None, device=None,
            log=print) -> list[dict]:
    scene = held_out(kind, WIDTH, HEIGHT)
    ref = cycles_reference(kind, scene, cycles.to_bpy(scene), REFERENCE_SPP, cache_dir=cache_dir, log=log)
    rows = []
    for m in methods:
        r = Renderer(scene, replace(ours_settings(m, scene), seed=11), device)
        r.render_still(0, 2)  # kernels, first uploads
        for n in samples:
            c0, t0 = time.process_time(), time.perf_counter()
            img = r.render_still(0, n).color[..., :3]
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            e = rel_mse(img, ref.image)
            row = {"kind": kind, "method": m, "samples": n, "rel_mse": e, "wall_ms": wall * 1e3 / n,
                   "cpu_ms": cpu * 1e3 / n, "rel_mse_x_cpu_s": e * cpu, "rel_mse_x_wall_s": e * wall,
                   "load": os.getloadavg()[0]}
            rows.append(row)
            log(f"{kind:<7} {m:<14} {n:4d} samples: relMSE {e:.3e}, {row['wall_ms']:7.1f} ms wall, "
                f"{row['cpu_ms']:7.1f} ms CPU per sample; relMSE x CPU s {row['rel_mse_x_cpu_s']:.3e} "
                f"(load {row['load']:.1f})")
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m restircl.eval.cycles.still_candidates", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--methods", default=",".join(OURS))
    ap.add_argument("--samples", default="32,128")
    ap.add_argument("--cache-dir", default=None)
    ap.add_argument("--device", default=None)
    ap.add_argument("--json", default=None, help="write the rows here")
    a = ap.parse_args(argv)
    samples = tuple(int(s) for s in a.samples.split(","))
    cache = Path(a.cache_dir) if a.cache_dir else None
    rows = [row for k in a.kinds.split(",") for row in measure(k, a.methods.split(","), samples, cache, a.device)]
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
