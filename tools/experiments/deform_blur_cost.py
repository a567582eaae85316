"""The cost of deformation blur in a still: every sample's mesh is deformed to its time and its BVH built again
(Scene.world_triangles, DeviceScene.upload), so a still of a deforming mesh pays that per sample on top of its
rendering. A wavy grid of N x N quads (2 N^2 triangles) over a lit floor, rendered with the `reference` method: the
same still sharp (no shutter) and blurred (its deformation over the shutter), per sample; and the BVH build alone
(DeviceScene.bvh_seconds, of the last sample). CPU time would hide the device's share: wall time, on a shared
machine, so the figures are ratios measured side by side.

    python -m tools.experiments.deform_blur_cost --sizes 32 100 224 --samples 16
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, translation


def grid(n: int, deform: bool) -> Mesh:
    """An n x n grid 2 m wide, its height a wave whose phase moves over the shutter (two steps)."""
    u = np.linspace(-1.0, 1.0, n + 1)
    x, y = np.meshgrid(u, u)
    flat = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    i = np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]
    quads = np.stack([i, i + 1, i + n + 2, i + n + 1], axis=-1).reshape(-1, 4)
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    mesh = Mesh("grid", flat, tris, 0, translation(0, 0, 0.5))
    if deform:
        steps = np.stack([flat, flat])
        steps[0, :, 2] = 0.2 * np.sin(4 * x.ravel())
        steps[1, :, 2] = 0.2 * np.sin(4 * x.ravel() + 1.0)
        mesh.vertices = steps[0] * 0.5 + steps[1] * 0.5
        mesh.deform, mesh.deform_times = steps, np.array([-0.25, 0.25])
    return mesh


def scene(n: int, deform: bool, shutter: tuple[float, float]) -> Scene:
    floor = Mesh("floor", [[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], [[0, 1, 2], [0, 2, 3]], 0)
    return Scene([floor, grid(n, deform)], [Material("grey", (0.6, 0.6, 0.6))],
                 [Light("key", "point", (1, 1, 1), 300.0, translation(1, -1, 3))],
                 Camera(look_at((0, -4, 3), (0, 0, 0.3)), 64, 48, shutter=shutter))


def per_sample(sc: Scene, samples: int) -> tuple[float, float, int]:
    r = Renderer(sc, Settings(method="reference", seed=1))
    r.render_still(0, 2)  # kernels built and warm
    t0 = time.perf_counter()
    r.render_still(0, samples)
    return (time.perf_counter() - t0) / samples, r.device_scene.bvh_seconds, r.device_scene.uploads["geometry"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[32, 100, 224])
    ap.add_argument("--samples", type=int, default=16)
    args = ap.parse_args()
    print(f"load {os.getloadavg()[0]:.2f}")
    for n in args.sizes:
        sharp, _, _ = per_sample(scene(n, False, (0.0, 0.0)), args.samples)
        blurred, bvh, uploads = per_sample(scene(n, True, (-0.25, 0.25)), args.samples)
        print(f"{2 * n * n:7d} triangles: sharp {1e3 * sharp:7.1f} ms/sample, blurred {1e3 * blurred:7.1f} ms/sample"
              f" ({blurred / sharp:5.2f}x; BVH build {1e3 * bvh:6.1f} ms; {uploads} geometry uploads)")
    print(f"load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
