"""The scene of the light-linking tests: a floor in two halves (floor_a left, floor_b right), a plank floating over
floor_a, a point light `key` over the plank, an area light `fill` over floor_b and an emissive panel `glow` at the
back. With links (linked=True):
- key lights only floor_a (receivers INCLUDE floor_a) and the plank does not shadow it (blockers EXCLUDE plank);
- fill lights everything but floor_a (receivers EXCLUDE floor_a);
- glow, an emissive mesh, does not light the plank (receivers EXCLUDE plank);
- with fence=True a low wall stands before the panel, which does not shadow it (glow's blockers EXCLUDE fence):
  an emitter with linked shadows that BSDF rays could meet (BSDF candidates, the BSDF MIS sample, paths).
Every link changes the image where the test looks: without them the plank shadows key on floor_a, key lights
floor_b, fill lights floor_a and glow lights the plank."""

from __future__ import annotations

import math

import numpy as np
from restircl import Light, Material, Mesh, Scene, look_at, translation
from restircl.scene.camera import Camera
from restircl.scene.linking import Linking

W, H = 48, 36


def quad(name: str, x0: float, x1: float, y0: float, y1: float, z: float, material: int = 0) -> Mesh:
    return Mesh(name, vertices=[(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)], triangles=[(0, 1, 2), (0, 2, 3)],
                material_ids=material)


def linking_scene(linked: bool = True, width: int = W, height: int = H, fence: bool = False) -> Scene:
    floor_a = quad("floor_a", -3.0, 0.0, -2.0, 3.0, 0.0)
    floor_b = quad("floor_b", 0.0, 3.0, -2.0, 3.0, 0.0)
    plank = quad("plank", -1.8, -0.6, -0.4, 0.8, 0.9)
    glow = Mesh("glow", vertices=[(-1.0, 2.5, 0.3), (1.0, 2.5, 0.3), (1.0, 2.5, 1.3), (-1.0, 2.5, 1.3)],
                triangles=[(0, 2, 1), (0, 3, 2)], material_ids=1)
    key = Light("key", "point", power=150.0, transforms=translation(-1.2, 0.2, 2.2), radius=0.15)
    fill = Light("fill", "area", power=120.0, transforms=translation(1.4, 0.5, 2.5), size=0.6)
    if linked:
        key.linking = Linking(receivers={"floor_a": "INCLUDE"}, blockers={"plank": "EXCLUDE"})
        fill.linking = Linking(receivers={"floor_a": "EXCLUDE"})
        glow.linking = Linking(receivers={"plank": "EXCLUDE"})
    meshes = [floor_a, floor_b, plank, glow]
    if fence:
        meshes.append(Mesh("fence", vertices=[(-1.2, 2.1, 0.0), (1.2, 2.1, 0.0), (1.2, 2.1, 0.7), (-1.2, 2.1, 0.7)],
                           triangles=[(0, 2, 1), (0, 3, 2)]))
        if linked:
            glow.linking.blockers = {"fence": "EXCLUDE"}
    cam = Camera(transforms=look_at((0.0, -5.5, 4.5), (0.0, 0.4, 0.3)), width=width, height=height)
    cam.set_fov(math.radians(55))
    mats = [Material(name="grey", albedo=(0.6, 0.6, 0.6)),
            Material(name="glow", albedo=(0.0, 0.0, 0.0), emission=(1.0, 0.8, 0.5), emission_strength=3.0)]
    return Scene(meshes=meshes, materials=mats, lights=[key, fill], camera=cam)


def rel_mse(ours: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((ours - ref) ** 2 / (ref ** 2 + 0.01)))
