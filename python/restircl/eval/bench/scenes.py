"""Scenes shared by the benchmarks: the light-count scaling scenes of `restircl bench lights` (also traced by
eval/bench/traversal.py) and the scenes of the specialisation benchmark (eval/bench/specialisation.py)."""

from __future__ import annotations

import math

import numpy as np

from ... import scenes
from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import icosphere, quad


def light_scaling_scene(n_lights: int, width: int, height: int, seed: int = 0, kind: str = "triangles") -> Scene:
    """A ground with spheres and n_lights lights of strengths spanning three decades, scattered 0.3..5 m above it.
    kind "triangles": small emissive triangles (64 shared emissive materials); the total emitting area and power
    are the same at every size: the triangles' edge shrinks as 1/sqrt(n) (0.5 m at 1e2, 0.005 m at 1e6), so they
    cover about the same fraction of the view, but they are geometry: the BVH grows with them. kind "panels": the
    same triangles lying flat in one horizontal layer at 5 m (a lit ceiling seen through from above, as lights on a
    surface are): a ray crosses the layer once, where it crosses the cloud's 4.7 m slab through ever more of its
    shrinking boxes. kind "points": point lights of the same total power, which are not geometry: only the light
    count changes."""
    rng = np.random.default_rng(seed)
    gv, gt = quad(40, 40)
    parts_v, parts_t = [gv], [gt]
    mats = [0, 0]
    base = len(gv)
    sv, st = icosphere(2, 1.0)
    for _ in range(30):
        c = np.array([*rng.uniform(-15, 15, 2), 1.0])
        parts_v.append(sv + c)
        parts_t.append(st + base)
        base += len(sv)
        mats += [1] * len(st)
    centres = np.column_stack([rng.uniform(-20, 20, n_lights), rng.uniform(-20, 20, n_lights),
                               rng.uniform(0.3, 5.0, n_lights)])
    cam = Camera(look_at((0, -22, 9), (0, 0, 0)), width, height, lens=28.0)
    if kind == "points":
        mesh = Mesh("all", np.concatenate(parts_v), np.concatenate(parts_t), np.array(mats))
        strengths = np.exp(rng.uniform(math.log(1.0), math.log(1000.0), n_lights))
        power = strengths * (2.0e4 / strengths.sum())  # 20 kW in all, at every size
        lights = [Light(f"p{k}", "point", (1.0, 0.9, 0.8), float(power[k]), translation(*centres[k]))
                  for k in range(n_lights)]
        return Scene([mesh], [Material("ground", (0.6, 0.6, 0.6)), Material("spheres", (0.7, 0.5, 0.3))],
                     lights, cam, name=f"points_{n_lights}")
    if kind not in ("triangles", "panels"):
        raise ValueError(f"kind must be triangles, panels or points, got {kind!r}")
    size = 0.5 / math.sqrt(n_lights / 100.0)
    offs = rng.normal(0, size, (n_lights, 3, 3))
    if kind == "panels":
        centres[:, 2] = 5.0
        offs[:, :, 2] = 0.0
    tri_v = (centres[:, None, :] + offs).reshape(-1, 3)
    parts_v.append(tri_v)
    parts_t.append(np.arange(3 * n_lights).reshape(-1, 3) + base)
    materials = [Material("ground", (0.6, 0.6, 0.6)), Material("spheres", (0.7, 0.5, 0.3))]
    strengths = np.exp(np.linspace(math.log(1.0), math.log(1000.0), 64))
    for k in range(64):
        col = rng.uniform(0.3, 1.0, 3)
        materials.append(Material(f"glow{k}", (0, 0, 0), tuple(col), float(strengths[k] * 0.5)))
    mats += list(2 + rng.integers(0, 64, n_lights))
    mesh = Mesh("all", np.concatenate(parts_v), np.concatenate(parts_t), np.array(mats))
    return Scene([mesh], materials, [], cam, name=f"lights_{n_lights}")


def bench_scene(name: str) -> Scene:
    """Scenes of the specialisation benchmark: many_lights with point lights only, with emissive meshes only,
    and a still frame of the full scene (its camera does not move)."""
    if name == "points":  # (many_lights(lamps=0) fails in scenes.merge: drop the lamps instead)
        scene = scenes.many_lights(width=320, height=180, frames=16, lamps=1, point_lights=256)
        scene.meshes = [m for m in scene.meshes if m.name != "lamps"]
        return scene
    if name == "meshes":
        return scenes.many_lights(width=320, height=180, frames=16, lamps=500, point_lights=0)
    if name == "still":
        return scenes.many_lights(width=320, height=180, frames=1)
    raise ValueError(name)
