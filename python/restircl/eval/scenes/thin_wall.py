"""A thin-walled pane (Blender 5.3's Principled BSDF with Thin Wall, opencl/bsdf/closures/thin_wall.h), built the
same way here and, through eval/cycles/bridge.py, in Blender: one quad of tinted glass, no thickness, standing
turned to the view over a lit floor, a box and a wall behind it, under a square area light behind the camera.
`roughness` 0 is a window pane, 0.35 a frosted sheet; `thin_wall` False is the same quad as a solid's surface (what
restircl rendered before it modelled Thin Wall: the ray refracts into the quad and never leaves); `ior`,
`transmission` (the rest is the Principled's specular and diffuse) and `distribution` vary the sheet. `lamp`
"point" adds a point light in front of the sheet, close to it, whose light reaches the floor, box and wall behind
only through the sheet where the sheet stands in the way (the shadow rays that a smooth thin wall lets through,
opencl/bvh/thin_wall_shadow.h); "point only" has that lamp alone."""

from __future__ import annotations

import math

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import box, quad

IOR = 1.5
TINT = (0.9, 0.75, 0.5)  # the sheet's transmittance at normal incidence
LIGHT_POWER = 300.0
BULB_POWER = 60.0


def _standing(x: float, y: float, z: float, turn_deg: float) -> np.ndarray:
    """A quad of the xy plane stood up (its normal horizontal), turned by turn_deg about z, centred at (x, y, z)"""
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    return np.array([[c, 0, -s, x], [s, 0, c, y], [0, 1, 0, z], [0, 0, 0, 1]], float)


def thin_pane(width: int = 48, height: int = 36, roughness: float = 0.0, thin_wall: bool = True, ior: float = IOR,
              transmission: float = 1.0, distribution: str = "ggx", lamp: str = "area") -> Scene:
    fv, ft = quad(8.0, 8.0)
    pv, pt = quad(1.6, 1.1)
    wv, wt = quad(8.0, 3.0)
    bv, bt = box((0.5, 0.5, 0.7))
    sheet = Material("sheet", TINT, roughness=roughness, ior=ior, specular=0.5, transmission=transmission,
                     distribution=distribution, thin_wall=thin_wall)
    mats = [Material("floor", (0.6, 0.6, 0.6)), sheet, Material("back", (0.7, 0.3, 0.2)),
            Material("block", (0.2, 0.4, 0.7))]
    meshes = [Mesh("floor", fv, ft, 0), Mesh("sheet", pv, pt, 1, _standing(0.0, -0.6, 0.6, 30.0)),
              Mesh("back", wv, wt, 2, _standing(0.0, 1.6, 1.5, 0.0)),
              Mesh("block", bv, bt, 3, translation(0.35, 0.3, 0.35))]
    lights = [] if lamp == "point only" else [Light("panel", "area", (1.0, 0.95, 0.9), LIGHT_POWER,
                                                    translation(-0.6, -2.2, 2.8), size=1.4)]
    if lamp.startswith("point"):
        lights.append(Light("bulb", "point", (1.0, 1.0, 1.0), BULB_POWER, translation(-0.25, -1.25, 0.7)))
    eye = look_at((0.4, -4.0, 1.6), (0.0, 0.0, 0.5))
    cam = Camera(eye[None], width, height, lens=35.0)
    return Scene(meshes, mats, lights, cam, name=f"thin_pane_{roughness:g}_{ior:g}{'' if thin_wall else '_solid'}"
                 f"{'' if lamp == 'area' else '_' + lamp.replace(' ', '_')}")
