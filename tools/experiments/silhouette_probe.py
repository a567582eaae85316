"""Where our converged direct light on the `user` kind differs from Cycles' cached 2 x 1024-spp reference, pixel by
pixel (issue 37: the metals' silhouettes). Two renders of ours (RIS, 32 candidates, as the compare command's converged
image; seeds 101 and 102) give the mean and our per-pixel noise; Cycles' reference is the cached average (its noise
is known as a whole only). Writes an .npz (our two renders, the reference, the last frame's shading normal and
depth) and prints the excess over our noise and its largest pixels; `--against` compares with a Cycles variant's two
renders of tools/experiments/user_direct_probe.py instead. docs/measurements/error-vs-time.md, "user: the metals'
silhouettes".

    nice python -m tools.experiments.silhouette_probe --frames 512 --tag base --cache-dir out/cache
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from restircl.eval.cycles.compare import cycles_reference, scene_pair
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings

SEEDS = (101, 102)


def render(scene, frames: int) -> dict[str, np.ndarray]:
    out: dict[str, np.ndarray] = {}
    for k, seed in enumerate(SEEDS):
        s = Settings(method="ris", candidates=32, seed=seed).validate()
        f = Renderer(scene, s).render_still(0, frames)
        out[f"color{k}"] = np.asarray(f.color[..., :3], np.float64)
        if f.normal is not None:
            out["normal"] = np.asarray(f.normal, np.float64)
        if f.depth is not None:
            out["depth"] = np.asarray(f.depth, np.float64)
    return out


def report(d: dict[str, np.ndarray], top: int) -> None:
    ref = d["ref"]
    mo = (d["color0"] + d["color1"]) / 2
    w = 1.0 / (ref * ref + 0.01)
    n = ref.size
    raw = (mo - ref) ** 2 * w
    ours_noise = (d["color0"] - d["color1"]) ** 2 / 4 * w
    print(
        f"relMSE {raw.sum() / n:.3e}, our noise {ours_noise.sum() / n:.3e}, raw less our noise "
        f"{(raw - ours_noise).sum() / n:.3e} (Cycles' noise 3.9e-4 is in it); sum ratio {mo.sum() / ref.sum():.4f}"
    )
    px = (raw - ours_noise).sum(-1) / n
    order = np.argsort(px.ravel())[::-1][:top]
    for i in order:
        y, x = divmod(int(i), ref.shape[1])
        o0, o1 = d["color0"][y, x].mean(), d["color1"][y, x].mean()
        print(f"  ({y:3d},{x:3d}) excess {px[y, x]:.2e}  ours {mo[y, x].mean():7.3f} (halves {o0:.3f} {o1:.3f})")
        print(f"            Cycles {ref[y, x].mean():7.3f}")


def against(d: dict[str, np.ndarray], cyc: dict[str, np.ndarray], top: int) -> None:
    """Our two renders against two Cycles renders (user_direct_probe's .npz of a variant, color0 and color1): the
    converged relMSE with both sides' noise taken out per pixel by their halves, and where it lies."""
    c0, c1 = cyc["color0"].astype(np.float64), cyc["color1"].astype(np.float64)
    mc, mo = (c0 + c1) / 2, (d["color0"] + d["color1"]) / 2
    w = 1.0 / (mc * mc + 0.01)
    n = mc.size
    ex = ((mo - mc) ** 2 - (d["color0"] - d["color1"]) ** 2 / 4 - (c0 - c1) ** 2 / 4) * w
    raw = ((mo - mc) ** 2 * w).sum() / n
    print(f"converged relMSE {ex.sum() / n:.3e} (raw {raw:.3e}), sums {mo.sum() / mc.sum():.4f}")
    px = ex.sum(-1) / n
    for i in np.argsort(px.ravel())[::-1][:top]:
        y, x = divmod(int(i), mc.shape[1])
        print(
            f"  ({y:3d},{x:3d}) excess {px[y, x]:.2e}  ours {mo[y, x].mean():7.3f}  Cycles {mc[y, x].mean():7.3f}"
            f" (halves {c0[y, x].mean():.3f} {c1[y, x].mean():.3f})  cached reference {d['ref'][y, x].mean():7.3f}"
        )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--frames", type=int, default=512)
    p.add_argument("--tag", default="base")
    p.add_argument("--top", type=int, default=12)
    p.add_argument("--cache-dir", default="out/cache")
    p.add_argument("--out", default="out/silhouette")
    p.add_argument("--report", action="store_true", help="only report the saved .npz of --tag")
    p.add_argument("--against", default=None, help="a user_direct_probe Cycles .npz to compare with instead")
    a = p.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"ours_{a.tag}_{a.frames}.npz"
    if not a.report:
        scene, sc = scene_pair("user", 192, 108)
        ref = cycles_reference("user", scene, sc, 1024, 2, Path(a.cache_dir))
        d = render(scene, a.frames)
        d["ref"] = np.asarray(ref.image[..., :3], np.float64)
        np.savez_compressed(path, **d)
        print(f"wrote {path}")
    if a.against:
        against(dict(np.load(path)), dict(np.load(a.against)), a.top)
        return
    report(dict(np.load(path)), a.top)


if __name__ == "__main__":
    main()
