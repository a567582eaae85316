"""Scenes with glass (issue 39's dielectric half), built the same way here and in Blender (eval/blender_scenes.py
builds their twins for Cycles): a lit floor with a smooth glass sphere, a glass pane (a thin box) standing on it and
a rough glass sphere, under a square area light. `kind` picks how the glass is made (the Glass BSDF or a Principled
BSDF with Transmission 1), `distribution` its microfacets (GGX, or Multiscatter GGX)."""

from __future__ import annotations

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import box, icosphere, quad

IOR = 1.45
ROUGH = 0.3
SPHERE_R = 0.45
PANE = (0.9, 0.06, 0.8)  # its size: x, y (thickness), z
LIGHT_POWER = 250.0
KINDS = ("glass_table",)  # for restircl compare (eval/scenes/kinds.py)


def glass_material(name: str, roughness: float, kind: str = "glass", ior: float = IOR,
                   distribution: str = "ggx") -> Material:
    """Clear glass of this roughness, as a Glass BSDF or a Principled BSDF with Transmission 1."""
    if kind == "principled":
        return Material(name, (1.0, 1.0, 1.0), roughness=roughness, ior=ior, specular=0.5, transmission=1.0,
                        distribution=distribution)
    return Material(name, (1.0, 1.0, 1.0), kind=kind, roughness=roughness, ior=ior, distribution=distribution)


def glass_table(width: int = 64, height: int = 48, kind: str = "glass", distribution: str = "ggx") -> Scene:
    fv, ft = quad(8.0, 8.0)
    sv, st = icosphere(3, SPHERE_R)
    bv, bt = box(PANE)
    mats = [Material("floor", (0.6, 0.6, 0.6)), glass_material("clear", 0.0, kind, distribution=distribution),
            glass_material("frosted", ROUGH, kind, distribution=distribution), Material("back", (0.7, 0.3, 0.2))]
    wv, wt = quad(8.0, 3.0)
    wall = np.array([[1, 0, 0, 0], [0, 0, -1, 1.6], [0, 1, 0, 1.5], [0, 0, 0, 1]], float)
    meshes = [Mesh("floor", fv, ft, 0), Mesh("clear", sv, st, 1, translation(-0.9, 0.0, SPHERE_R)),
              Mesh("pane", bv, bt, 1, translation(0.1, -0.3, PANE[2] / 2)),
              Mesh("frosted", sv, st, 2, translation(1.0, 0.3, SPHERE_R)), Mesh("back", wv, wt, 3, wall)]
    lights = [Light("panel", "area", (1.0, 0.95, 0.9), LIGHT_POWER, translation(0.3, -0.8, 2.6), size=1.2)]
    eye = look_at((0.2, -4.2, 1.9), (0.05, 0.0, 0.45))
    cam = Camera(eye[None], width, height, lens=35.0)
    return Scene(meshes, mats, lights, cam, name=f"glass_table_{kind}")
