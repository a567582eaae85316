"""Does our still's error at the floor's edge against the world (the alpha scene, eval/scenes/alpha_cards.py) fall
with the samples, and how does it compare with Cycles' at equal samples? Against the Cycles reference that
alpha_equal_time.py leaves in ALPHA_REFERENCE (2 x 4096 spp).

The edge pixels: the top 1 % of squared error of two renders of ours at 512 samples with seeds of their own (101,
102), so that the renders measured here did not choose them. Per sample count N and seed: relMSE on those pixels and
on the whole image; the spread between the seeds (our variance); the error of the seeds' mean at the largest N (our
bias plus what is left of the variance, against what the noise alone would give; and the signed error summed over
the edge pixels of each side of the image, where a sub-pixel offset of the camera rays would show as opposite signs)
and Cycles' at equal samples on the same pixels.

    ALPHA_REFERENCE=ref.npy PYTHONPATH=python python tools/experiments/edge_convergence.py [seeds [cycles]]

EDGE_MASK=path.npy: the edge pixels, picked and written there on the first run, read by later runs (so that
variants of the code, each with PYTHONPATH at its own tree, are measured on the same pixels).
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.scenes.alpha_cards import alpha_cards

COUNTS = (64, 256, 1024, 4096)
CYCLES_COUNTS = (64, 256, 1024)


def rel_err(a: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Per pixel squared error relative to the reference (relMSE's terms, averaged over the colours)."""
    return np.mean((a - ref) ** 2 / (ref * ref + 1e-2), axis=-1)


def ours(scene, seed: int, samples: int) -> np.ndarray:
    r = Renderer(scene, still_settings(Settings(seed=seed), scene))
    return r.render_still(0, samples=samples).color[..., :3]


def cycles_image(scene, seed: int, samples: int) -> np.ndarray:
    from alpha_equal_time import adjust  # type: ignore[import-not-found]
    from restircl.eval.cycles import bridge as cycles  # bpy is loaded only when asked for

    return cycles.render(cycles.to_bpy(scene), samples=samples, seed=seed, threads=2, adjust=adjust).image[..., :3]


def main() -> None:
    seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 4
    with_cycles = len(sys.argv) > 2 and sys.argv[2] == "cycles"
    refs = np.load(os.environ["ALPHA_REFERENCE"])
    ref = 0.5 * (refs[0] + refs[1])
    h, w = ref.shape[:2]
    scene = alpha_cards(w, h)
    t0 = time.process_time()
    mask_path = os.environ.get("EDGE_MASK", "/tmp/edge_mask.npy")
    if os.path.exists(mask_path):  # the pixels an earlier run picked (a variant of the code is measured on them)
        edge = np.load(mask_path)
    else:
        pick = 0.5 * (rel_err(ours(scene, 101, 512), ref) + rel_err(ours(scene, 102, 512), ref))
        edge = np.zeros(h * w, bool)
        edge[np.argsort(pick.ravel())[::-1][: max(h * w // 100, 1)]] = True
        edge = edge.reshape(h, w)
        np.save(mask_path, edge)
        print(f"share of the picking renders' relMSE on the edge pixels {pick[edge].sum() / pick.sum():.2f}")
    own = rel_err(refs[0], refs[1]) / 4
    print(f"{w}x{h}, {edge.sum()} edge pixels; reference's own error there {own[edge].mean():.2e}, "
          f"whole {own.mean():.2e}; load {os.getloadavg()[0]:.1f}", flush=True)
    imgs = {n: [ours(scene, s, n) for s in range(1, seeds + 1)] for n in COUNTS}
    for n in COUNTS:
        e = [rel_err(im, ref) for im in imgs[n]]
        mean = np.mean(imgs[n], axis=0)
        spread = np.var(imgs[n], axis=0, ddof=1).mean(-1) / (ref * ref + 1e-2).mean(-1)
        at_edge = np.mean([x[edge].mean() for x in e])
        print(f"ours N={n:5d}: edge relMSE {at_edge:.2e} (x N {n * at_edge:.2f}), "
              f"seeds' variance {spread[edge].mean():.2e}, mean of seeds vs ref {rel_err(mean, ref)[edge].mean():.2e}; "
              f"whole {np.mean([x.mean() for x in e]):.2e}, seeds' variance {spread.mean():.2e}", flush=True)
    top = imgs[COUNTS[-1]]
    mean = np.mean(top, axis=0)
    expected = np.var(top, axis=0, ddof=1) / len(top) + (refs[0] - refs[1]) ** 2 / 4  # ours' mean's and ref's noise
    half = (mean - ref).mean(-1), expected.mean(-1), ref.mean(-1)
    sides = []
    for name, side in (("left", edge & (np.arange(w) < w // 2)), ("right", edge & (np.arange(w) >= w // 2))):
        d, e, r = (x[side] for x in half)
        sides.append(f"{name} {d.sum() / r.sum():+.4f} +- {np.sqrt(e.sum()) / r.sum():.4f}")
    print(f"bias at N={COUNTS[-1]}: mean of {seeds} seeds vs ref on the edge {rel_err(mean, ref)[edge].mean():.2e}, "
          f"its noise alone {np.mean(expected / (ref * ref + 1e-2), axis=-1)[edge].mean():.2e}; "
          f"sum(ours - ref) / sum(ref) on the floor's {', '.join(sides)}", flush=True)
    if with_cycles:
        for n in CYCLES_COUNTS:
            e = [rel_err(cycles_image(scene, 10 + s, n), ref) for s in range(1, 3)]
            at_edge = np.mean([x[edge].mean() for x in e])
            print(f"cycles N={n:5d}: edge relMSE {at_edge:.2e} (x N {n * at_edge:.2f}); "
                  f"whole {np.mean([x.mean() for x in e]):.2e}", flush=True)
    print(f"CPU {time.process_time() - t0:.0f} s, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
