"""Error per sample of F12's still path (still_settings: RIS from the Sobol sampler) on scene kinds, without a
reference: per sample count N, the variance between `seeds` renders of their own seeds, relative to the square of
the pixels' mean over every render (relMSE of one render, as eval/metrics.rel_mse weighs it: var / (mean^2 + 0.01)),
on the whole image, on its body (without its TRIM worst pixels) and on its edge pixels (those whose luminance
differs from a 4-neighbour's by more than half of the larger, in the mean image); and the CPU seconds per sample
(process_time, PoCL's threads included). For comparing two trees at equal samples, run it with PYTHONPATH at each
tree; the mean image that weighs them and picks the edges is rendered by the first run from seeds of its own
(MEAN_SEED0 + 1 ..., at the largest count), written to MEAN_OUT (default
/tmp/sobol_net_mean_<kind>_<bounces>_<seeds>x<largest count>.npy)
and read back by later runs when it is there, so every tree is weighed by the same mean and edge mask. Not from the
measured renders: a tree's outliers would raise its own mean where they fall, which lowers their weight and moves
the edge mask, and the tree that made the mean would look better than it is (on `user` at 64 samples its edges by
1.3x on average over 8 groups of 8 seeds, 1.6x in one: docs/measurements/error-vs-time.md).

    PYTHONPATH=python python tools/experiments/sobol_net_error.py KIND [bounces [seeds [counts]]]

bounces: 0 (direct light, F12's default) or Max Bounces (4: the path pass too); counts: comma-separated sample
counts (default 16,64,256).
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.scenes.kinds import scene_of_kind

TRIM = 20  # pixels left out of the body figure
MEAN_SEED0 = 1000  # the mean image's renders take seeds MEAN_SEED0 + 1 ..., none of the measured ones


def edges(mean: np.ndarray) -> np.ndarray:
    """Pixels whose luminance differs from a 4-neighbour's by more than half of the larger of the two."""
    lum = mean @ np.array([0.2126, 0.7152, 0.0722])
    out = np.zeros(lum.shape, bool)
    for axis in (0, 1):
        a, b = np.moveaxis(lum, axis, 0)[:-1], np.moveaxis(lum, axis, 0)[1:]
        jump = np.abs(a - b) > 0.5 * np.maximum(np.maximum(a, b), 1e-3)
        np.moveaxis(out, axis, 0)[:-1] |= jump
        np.moveaxis(out, axis, 0)[1:] |= jump
    return out


def main() -> None:
    kind = sys.argv[1]
    bounces = int(sys.argv[2]) if len(sys.argv) > 2 else 0
    seeds = int(sys.argv[3]) if len(sys.argv) > 3 else 4
    counts = [int(c) for c in sys.argv[4].split(",")] if len(sys.argv) > 4 else [16, 64, 256]
    scene = scene_of_kind(kind, 192, 108)
    paths = LightPaths.of(bounces)
    imgs, cpu = {}, {}

    def render(seed: int, n: int) -> np.ndarray:
        settings = still_settings(Settings(seed=seed, **paths.overrides()), scene)
        return Renderer(scene, settings).render_still(0, samples=n).color[..., :3].astype(np.float64)

    for n in counts:
        t0 = time.process_time()
        imgs[n] = np.stack([render(s, n) for s in range(1, seeds + 1)])
        cpu[n] = (time.process_time() - t0) / (n * seeds)
    path = os.environ.get("MEAN_OUT", f"/tmp/sobol_net_mean_{kind}_{bounces}_{seeds}x{max(counts)}.npy")
    if not os.path.exists(path):
        np.save(path, np.mean([render(MEAN_SEED0 + s, max(counts)) for s in range(1, seeds + 1)], axis=0))
    mean = np.load(path)
    edge = edges(mean)
    weight = 1.0 / (mean**2 + 0.01)
    print(f"{kind} bounces {bounces}, {seeds} seeds, {edge.sum()} edge pixels of {edge.size}, "
          f"load {os.getloadavg()[0]:.1f}")
    for n in counts:
        rel = (imgs[n].var(axis=0, ddof=1) * weight).mean(axis=-1)
        # the same from each disjoint group of 4 seeds: how much the figure moves with the seeds (heavy tails)
        groups = [(imgs[n][g:g + 4].var(axis=0, ddof=1) * weight).mean(axis=-1) for g in range(0, seeds - 3, 4)]
        spread = ", ".join(f"{r.mean():.3e}/{r[edge].mean():.3e}" for r in groups)
        # the image's body: without its TRIM worst pixels (a firefly of one seed decides the mean otherwise)
        body = np.sort(rel.ravel())[:-TRIM].mean()
        print(f"N={n:4d}: relMSE whole {rel.mean():.4e} edges {rel[edge].mean():.4e} body {body:.4e}; x N whole "
              f"{n * rel.mean():.4f} edges {n * rel[edge].mean():.4f}; CPU {1e3 * cpu[n]:.1f} ms/sample; "
              f"groups of 4 seeds (whole/edges): {spread}", flush=True)


if __name__ == "__main__":
    main()
