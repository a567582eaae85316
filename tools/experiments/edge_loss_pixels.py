"""Which pixels of a kind's edges lose between two trees, and whether the loss is more than a few samples: F12's still
path (still_settings, direct light) at N samples per seed, compared per pixel between the renders of two trees.

    PYTHONPATH=<tree>/python python tools/experiments/edge_loss_pixels.py render KIND N S0 S1 OUT.npz
    PYTHONPATH=python python tools/experiments/edge_loss_pixels.py compare BEFORE[,..] AFTER[,..] [GBUF]
    PYTHONPATH=python python tools/experiments/edge_loss_pixels.py gbuffer KIND N GBUF.npz

`render` renders seeds S0 .. S1 - 1 of 192x108 and saves each seed's mean image (m1) and its samples' mean square
(m2, read from the frame's sample buffer before it is summed); `gbuffer` saves one seed's depth, albedo and light
passes (what the pixels see and how they are lit). `compare` weighs both trees by their joint mean image and its
edge mask (sobol_net_error.edges) and prints relMSE (var / (mean^2 + 0.01)) per class of edge pixel, the same
without each pixel's largest seed, the median of the pixels' ratio after / before, the figure per group of 8
seeds, the tail (departures from each pixel's median over the seeds), the top losing pixels, and how much of the
variance of the mean is the samples' own variance / N (1: as independent samples; below: the samples stratify).
"""

from __future__ import annotations

import sys

import numpy as np

from tools.experiments.sobol_net_error import edges

LUM = np.array([0.2126, 0.7152, 0.0722])
SIZE = (192, 108)


def render(kind: str, n: int, s0: int, s1: int, out: str) -> None:
    import pyopencl as cl
    from restircl import Renderer, Settings, still_settings
    from restircl.eval.cycles.paths import LightPaths
    from restircl.eval.scenes.kinds import scene_of_kind

    scene = scene_of_kind(kind, *SIZE)
    w, h = SIZE
    m1, m2 = [], []
    for seed in range(s0, s1):
        r = Renderer(scene, still_settings(Settings(seed=seed, **LightPaths.of(0).overrides()), scene))
        sq = np.zeros((h, w, 3))
        add = r.still.add

        def add_sample(buf: cl.Buffer, fp: np.void, half: int, r: Renderer = r, sq: np.ndarray = sq,
                       add: object = add) -> None:
            host = np.empty(w * h * 4, np.float32)
            cl.enqueue_copy(r.kernels.device.queue, host, buf).wait()
            sq += host.reshape(h, w, 4)[..., :3].astype(np.float64) ** 2
            add(buf, fp, half)  # type: ignore[operator]

        r.still.add = add_sample  # type: ignore[method-assign]
        m1.append(r.render_still(0, samples=n).color[..., :3].astype(np.float64))
        m2.append(sq / n)
    np.savez(out, m1=np.array(m1), m2=np.array(m2), n=n)


def gbuffer(kind: str, n: int, out: str) -> None:
    from restircl import Renderer, Settings, still_settings
    from restircl.eval.cycles.paths import LightPaths
    from restircl.eval.scenes.kinds import scene_of_kind

    scene = scene_of_kind(kind, *SIZE)
    f = Renderer(scene, still_settings(Settings(seed=1, light_passes=True, **LightPaths.of(0).overrides()), scene)
                 ).render_still(0, samples=n)
    np.savez(out, depth=f.depth, albedo=f.albedo, diffuse=f.diffuse_direct, glossy=f.glossy_direct,
             environment=f.environment, emission=f.emission)


def load(paths: str) -> tuple[np.ndarray, np.ndarray | None, int]:
    """The runs' mean images, their samples' mean squares (None where a file lacks them) and samples per run."""
    parts = [np.load(p) for p in paths.split(",")]
    squares = np.concatenate([p["m2"] for p in parts]) if all("m2" in p for p in parts) else None
    return np.concatenate([p["m1"] for p in parts]), squares, int(parts[0]["n"])


def compare(before: str, after: str, gbuf: str | None) -> None:
    b, b2, n = load(before)
    a, a2, _ = load(after)
    seeds = min(len(a), len(b))
    a, b = a[:seeds], b[:seeds]
    mean = np.concatenate([a, b]).mean(axis=0)
    edge = edges(mean)
    w = 1.0 / (mean**2 + 0.01)

    def rel(x: np.ndarray) -> np.ndarray:
        return (x.var(axis=0, ddof=1) * w).mean(-1)

    def trim(x: np.ndarray) -> np.ndarray:  # without each pixel's (channel's) largest seed
        return (np.sort(x, axis=0)[:-1].var(axis=0, ddof=1) * w).mean(-1)

    vb, va, tb, ta = rel(b), rel(a), trim(b), trim(a)
    classes = {"whole": np.ones_like(edge), "edges": edge}
    if gbuf is not None:
        g = np.load(gbuf)
        d = np.where(np.isfinite(g["depth"]), g["depth"], 1e3)
        pad = np.pad(d, 1, mode="edge")
        near = np.stack([pad[1 + dy:1 + dy + d.shape[0], 1 + dx:1 + dx + d.shape[1]]
                         for dy in (-1, 0, 1) for dx in (-1, 0, 1)])
        silhouette = near.max(0) / near.min(0) > 1.1
        glossy = g["glossy"] @ LUM > g["diffuse"] @ LUM
        world = (g["environment"] @ LUM > 0) | ~np.isfinite(g["depth"]) | (g["emission"] @ LUM > 0)
        classes |= {"edge silhouettes": edge & silhouette, "edge not silhouettes": edge & ~silhouette,
                    "edge glossy-lit": edge & glossy, "edge diffuse-lit": edge & ~glossy,
                    "edge dark albedo < 0.05": edge & (g["albedo"] @ LUM < 0.05),
                    "edge world or emitter seen": edge & world}
    print(f"{seeds} seeds of {n} samples; {edge.sum()} edge pixels of {edge.size}")
    print("class | pixels | relMSE before | after | without each pixel's largest seed: before | after | median ratio")
    for name, m in classes.items():
        if m.any():
            r = va[m] / np.maximum(vb[m], 1e-30)
            print(f"{name} | {m.sum()} | {vb[m].mean():.3e} | {va[m].mean():.3e} | {tb[m].mean():.3e} | "
                  f"{ta[m].mean():.3e} | {np.median(r):.2f}")
    for g0 in range(0, seeds - 7, 8):
        gb, ga = rel(b[g0:g0 + 8]), rel(a[g0:g0 + 8])
        print(f"runs {g0 + 1}-{g0 + 8}: whole {gb.mean():.3e} / {ga.mean():.3e}, edges {gb[edge].mean():.3e} / "
              f"{ga[edge].mean():.3e}")
    wl = 1.0 / ((mean @ LUM) ** 2 + 0.01)
    for name, x, x2 in (("before", b, b2), ("after", a, a2)):
        lum = x @ LUM
        dev = np.sort(((lum - np.median(lum, axis=0)) ** 2 * wl)[:, edge].ravel())
        print(f"{name}: edge pixel-seeds departing from their pixel's median (weighted squares) by > 1 / 0.3 / 0.1: "
              f"{(dev > 1).sum()} / {(dev > 0.3).sum()} / {(dev > 0.1).sum()}; the top 30 carry "
              f"{dev[-30:].sum() / dev.sum():.2f} of the sum")
        if x2 is not None:
            # the variance of the mean against the samples' own variance / n (the diagonal term, the same for both
            # trees where each sample is uniform): a single sample's outlier enters both, so this ratio is far
            # steadier between runs than either
            own = (((x2[:seeds] - x**2) * n / (n - 1)).mean(axis=0) / n * w).mean(-1)
            between = x.var(axis=0, ddof=1) * w
            between = between.mean(-1)
            print(f"  samples' variance / n: edges {own[edge].mean():.3e}, whole {own.mean():.3e}; variance of the "
                  f"mean / that: edges {between[edge].mean() / own[edge].mean():.3f}, whole "
                  f"{between.mean() / own.mean():.3f}")
    excess = np.where(edge, va - vb, 0.0).ravel()
    order = np.argsort(-excess)
    print(f"the 10 worst edge pixels carry {excess[order[:10]].sum() / excess.sum():.2f} of the edges' excess")
    for k in order[:10]:
        y, x = divmod(int(k), mean.shape[1])
        la, lb = a[:, y, x] @ LUM, b[:, y, x] @ LUM
        print(f"  ({x}, {y}) mean {mean[y, x] @ LUM:.3f}: relMSE {vb[y, x]:.2e} -> {va[y, x]:.2e}; after's largest "
              f"seed {la.max():.2f} (run {la.argmax() + 1}), median {np.median(la):.2f}; before's {lb.max():.2f}, "
              f"{np.median(lb):.2f}")


def main() -> None:
    cmd = sys.argv[1]
    if cmd == "render":
        render(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), sys.argv[6])
    elif cmd == "gbuffer":
        gbuffer(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    else:
        compare(sys.argv[2], sys.argv[3], sys.argv[4] if len(sys.argv) > 4 else None)


if __name__ == "__main__":
    main()
