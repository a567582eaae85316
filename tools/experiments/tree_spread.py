"""Where the light tree pays: RIS stills with candidates from the light array and from the tree, at equal CPU time, on
lamp fields of 1k-10k point lights spread over squares of growing side (docs/measurements/error-vs-time.md, "Light
tree on lamp fields").

A lamp field: `n` point lights (powers log-uniform over 1-100 W) on a jittered grid over a square ground of side
`side` m at 0.5-3 m height, a few boxes, the camera at 1.7 m on the square's edge looking across it. Where the side
is large against the distance over which a lamp lights the ground, a light drawn by its power is almost never one
that lights the shading point: the array's proposal fails, the tree's bound (power over the squared distance to its
clusters) does not.

For each field and method: a still of `--frames` frames (F12's Sobol sampler), its process CPU time per frame, its
relMSE against the field's converged image (RIS with 32 tree candidates, `--ref-frames` frames, cached under
--cache-dir), then over `--seeds` seeds. Efficiency: 1 / (relMSE x CPU seconds) (a still's relMSE falls as
1/frames); the last column the tree's over the array's, above 1 where the tree pays at equal time. Each field's
`spread` (light_spread below) is printed beside it: a candidate for a rule of lights/tree.py `tree_pays`.

    python -m tools.experiments.tree_spread --fields 1000:20,1000:200,4000:100,10000:400 --seeds 2
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from pathlib import Path

import numpy as np
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, translation
from restircl.eval.metrics import rel_mse
from restircl.scenes.shapes import box, merge, quad

# ---- the spread of lights: how badly the light array's proposal (a light by its power) matches the light that
# reaches a lamp's surroundings. At a point x, light i brings about f_i = P_i / (|x - c_i|^2 + FLOOR^2) (power over
# squared distance, floored: a shading point is rarely nearer a light's centre). Drawn by power, p_i = P_i / sum P,
# one sample's estimate f_i / p_i of sum f has the relative second moment
#     m(x) = sum(f_i^2 / p_i) / (sum f_i)^2 = sum P x sum(P_i / d_i^4) / (sum P_i / d_i^2)^2,
# 1 where power alone is the right proposal (every light equally far), up to the light count where one light
# outshines the rest at x. The spread: the median of m over probe points at the lights' own centres (a lamp lights
# what is near it). Orientation (spots, area lights facing away) is left out.

#: metres: the nearest a shading point is taken to be to a light's centre
FLOOR = 1.0
#: probe points (lights' centres, evenly spaced through the list), fewer where probes x lights would pass WORK
PROBES = 256
WORK = 4_000_000


def light_spread(centres: np.ndarray, power: np.ndarray) -> float:
    """The spread (above) of lights with these centres ((N, 3), finite) and powers (N,); 1 for fewer
    than two lights or no power."""
    c = np.asarray(centres, np.float64).reshape(-1, 3)
    p = np.asarray(power, np.float64).reshape(-1)
    keep = np.all(np.isfinite(c), axis=1) & np.isfinite(p) & (p > 0)
    c, p = c[keep], p[keep]
    if len(p) < 2:
        return 1.0
    count = min(PROBES, len(c), max(16, WORK // len(c)))
    probes = c[np.unique(np.linspace(0, len(c) - 1, count).round().astype(np.int64))]
    m = np.empty(len(probes))
    for k, x in enumerate(probes):  # one row at a time: 10k lights x 256 probes stays small
        inv = 1.0 / (((c - x) ** 2).sum(axis=1) + FLOOR * FLOOR)
        m[k] = p.sum() * (p * inv * inv).sum() / (p * inv).sum() ** 2
    return float(np.median(m))


def lamp_field(n: int, side: float, width: int, height: int, seed: int = 0) -> Scene:
    """The module docstring's lamp field of `n` lights over a square of `side` m."""
    rng = np.random.default_rng(seed)
    half = side / 2
    gv, gt = quad(side, side)
    parts = []
    for _ in range(max(4, int(side / 4))):
        sx, sy, sz = rng.uniform(0.5, 2.0, 3)
        v, t = box((sx, sy, sz))
        parts.append((v + (*rng.uniform(-half * 0.9, half * 0.9, 2), sz / 2), t, np.array(1)))
    v, t, m = merge(parts)
    meshes = [Mesh("ground", gv, gt, 0), Mesh("boxes", v, t, m)]
    k = int(math.ceil(math.sqrt(n)))
    cells = rng.permutation(k * k)[:n]
    gx, gy = np.divmod(cells, k)
    xs = (gx + rng.uniform(0.2, 0.8, n)) / k * side - half
    ys = (gy + rng.uniform(0.2, 0.8, n)) / k * side - half
    zs = rng.uniform(0.5, 3.0, n)
    powers = np.exp(rng.uniform(0.0, math.log(100.0), n))
    lights = [Light(f"lamp{i}", "point", (1.0, 0.9, 0.75), float(powers[i]), translation(xs[i], ys[i], zs[i]))
              for i in range(n)]
    cam = Camera(look_at((0.0, -half, 1.7), (0.0, -half + min(side, 40.0), 0.3)), width, height, lens=24.0)
    return Scene(meshes, [Material("ground", (0.6, 0.6, 0.6)), Material("box", (0.7, 0.5, 0.4))], lights, cam,
                 name=f"lamp_field_{n}_{side:g}m")


def reference(scene: Scene, frames: int, cache_dir: Path) -> np.ndarray:
    path = cache_dir / f"{scene.name}_{scene.camera.width}x{scene.camera.height}_ref{frames}.npy"
    if path.exists():
        return np.load(path)
    s = Settings(method="ris", light_proposal="tree", candidates=32, seed=999).validate()
    img = Renderer(scene, s).render_still(0, frames).color[..., :3].astype(np.float32)
    cache_dir.mkdir(parents=True, exist_ok=True)
    np.save(path, img)
    return img


def still(scene: Scene, settings: Settings, frames: int) -> tuple[np.ndarray, float]:
    """(image, CPU seconds per frame) of a still; the renderer's first frame (uploads, kernel builds) untimed."""
    r = Renderer(scene, settings)
    r.render_still(0, 1)
    t0 = time.process_time()
    img = r.render_still(0, frames).color[..., :3]
    return img, (time.process_time() - t0) / frames


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fields", default="1000:20,1000:200,4000:100,10000:400", help="lights:side_m,...")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=72)
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--ref-frames", type=int, default=512)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--methods", default="array:8,tree:8,tree:4")
    ap.add_argument("--cache-dir", default="out/tree_spread")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    rows = []
    load0 = os.getloadavg()[0]
    for field in a.fields.split(","):
        n, side = field.split(":")
        scene = lamp_field(int(n), float(side), a.width, a.height)
        ref = reference(scene, a.ref_frames, Path(a.cache_dir))
        spread = light_spread(scene_light_positions(scene), np.array([lt.power for lt in scene.lights]))
        print(f"{scene.name}: spread {spread:.3g}", flush=True)
        base = None
        for m in a.methods.split(","):
            proposal, cand = m.split(":")
            errs, secs = [], []
            for seed in range(1, a.seeds + 1):
                s = Settings(method="ris", light_proposal=proposal, candidates=int(cand), seed=seed).validate()
                img, sec = still(scene, s, a.frames)
                errs.append(rel_mse(img, ref))
                secs.append(sec)
            err, sec = float(np.mean(errs)), float(np.median(secs))
            eff = 1.0 / (err * sec * a.frames)
            base = base or eff
            print(f"  {m:<10} relMSE {' '.join(f'{e:.4g}' for e in errs)} mean {err:.4g}  CPU ms/frame "
                  f"{sec * 1e3:.1f}  efficiency {eff:.4g}  / array {eff / base:.2f}", flush=True)
            rows.append({"field": scene.name, "lights": int(n), "side_m": float(side), "spread": spread,
                         "method": m, "rel_mse": errs, "cpu_s_per_frame": secs, "efficiency_ratio": eff / base})
    load1 = os.getloadavg()[0]
    print(f"load {load0:.1f} -> {load1:.1f}")
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(json.dumps({"frames": a.frames, "width": a.width, "height": a.height,
                                           "load": [load0, load1], "rows": rows}, indent=1))


def scene_light_positions(scene: Scene) -> np.ndarray:
    return np.array([lt.transforms[0][:3, 3] for lt in scene.lights])


if __name__ == "__main__":
    main()
