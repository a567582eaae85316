"""Which pixels make a seed's relMSE on an orbit, and what ReSTIR's reservoirs held there: docs/measurements/
temporal-stability.md, "ReSTIR's seed 3 on market_orbit".

Renders the orbit `--k` frames per animation frame (as restir_motion; k = 1 is its `--equal-frames`) with one method
and seed, and prints for every evaluated frame its relMSE, the `--top` pixels of its relMSE map
(eval/metrics.rel_mse_map) with their term, TAA's history length n, the frame's sample and the reference; for a ReSTIR
method also the pixel's reservoir after each pass (initial RIS, temporal, spatial: light, w_sum, M, W, target p-hat) on
that frame. Last,
the seed's relMSE with the worst pixel of all (its term set to 0): how much of the seed one pixel is.

    python -m tools.experiments.worst_pixels --scene market_orbit --method restir --seed 3 --ref-seconds 15
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl.eval.metrics import rel_mse_map
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import motion_scene
from restircl.render.frame import read_image
from restircl.scene.retime import retime

from .restir_motion import orbit_arguments
from .taa_floor import renderer

# opencl/types.h Reservoir (32 bytes)
RESERVOIR = np.dtype([("light", "i4"), ("u", "f4"), ("v", "f4"), ("w_sum", "f4"), ("M", "f4"), ("W", "f4"),
                      ("target", "f4"), ("vis_age", "i4")])
PASSES = ("initial", "temporal", "spatial")


def worst(maps: dict[int, np.ndarray], top: int) -> list[tuple[int, int, int, float]]:
    """The `top` largest terms of all the maps, as (frame, y, x, term), largest first."""
    terms = [(float(m[y, x]), f, y, x) for f, m in maps.items()
             for y, x in zip(*np.unravel_index(np.argsort(m, axis=None)[::-1][:top], m.shape), strict=True)]
    return [(f, int(y), int(x), t) for t, f, y, x in sorted(terms, reverse=True)[:top]]


def without(maps: dict[int, np.ndarray], frame: int, y: int, x: int) -> float:
    """The mean over the maps of their mean relMSE, with the term of pixel (y, x) of `frame` left at 0."""
    return float(np.mean([m.mean() - (m[y, x] / m.size if f == frame else 0.0) for f, m in maps.items()]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--method", default="restir")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--k", type=int, default=1, help="frames rendered per animation frame")
    ap.add_argument("--top", type=int, default=3)
    ap.add_argument("--ref-seconds", type=float, default=10.0)
    ap.add_argument("--cache-dir", default="out/refs")
    a = ap.parse_args()
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    evaluated = sorted({*range(a.every, scene.frames, a.every), scene.frames - 1})
    refs = {f: get_reference(scene, f, a.ref_seconds, cache_dir=Path(a.cache_dir), log=lambda s: None).image
            for f in evaluated}
    r = renderer(retime(scene, a.k), a.method, a.seed)
    q = r.device.queue
    now = {"frame": 0}
    kept: dict[tuple[int, str], np.ndarray] = {}
    for name in PASSES:  # keep every pass's reservoirs of the evaluated frames
        stage = getattr(r, name)

        def run(*args, _plain=stage.run, _name=name, **kw):
            out = _plain(*args, **kw)
            if now["frame"] in evaluated:
                res = np.empty(r.width * r.height, RESERVOIR)
                cl.enqueue_copy(q, res, out)
                q.finish()
                kept[(now["frame"], _name)] = res.reshape(r.height, r.width)
            return out

        stage.run = run
    maps, got = {}, {}
    for j in range(r.scene.frames):
        f, rest = divmod(j, a.k)
        now["frame"] = f if rest == 0 else -1
        _, color, _ = r.run_frame(j, still=False)
        if rest == 0 and f in evaluated:
            img = read_image(q, color, (r.height, r.width))[..., :3]
            got[f] = (img, r.history_length(), read_image(q, r.sample_buf, (r.height, r.width))[..., :3])
            maps[f] = rel_mse_map(img, refs[f])
    print(f"{scene.name} {a.width}x{a.height}, {a.method}, k {a.k}, seed {a.seed}: relMSE "
          f"{np.mean([m.mean() for m in maps.values()]):.4f}")
    for f, m in maps.items():
        print(f"frame {f}: relMSE {m.mean():.4f}")
        for _, y, x, t in worst({f: m}, a.top):
            img, n, sample = got[f]
            print(f"  pixel x {x} y {y}: term {t:.1f}, n {n[y, x]:.2f}, shown {np.round(img[y, x], 3)}, sample "
                  f"{np.round(sample[y, x], 3)}, reference {np.round(refs[f][y, x], 3)}")
            for name in PASSES:
                if (f, name) in kept:
                    v = kept[(f, name)][y, x]
                    print(f"    after {name:<8}: light {v['light']}, w_sum {v['w_sum']:.3f}, M {v['M']:.0f}, "
                          f"W {v['W']:.3f}, target {v['target']:.3f}")
    f, y, x, t = worst(maps, 1)[0]
    print(f"worst pixel: frame {f} x {x} y {y} (term {t:.1f}); the seed's relMSE without it "
          f"{without(maps, f, y, x):.4f}")


if __name__ == "__main__":
    main()
