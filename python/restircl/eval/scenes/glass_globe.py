"""A light behind glass (issue 39): a small point light inside a glass globe hanging in a closed room with a
table. Shadow rays stop at glass in both renderers, so the room is lit only by paths that reach the globe and then
the light: with a frosted globe, next-event estimation at the globe's rough surface finds the light; with a clear
one only BSDF-sampled paths through two smooth interfaces do (caustics). `restircl compare` renders both kinds
against Cycles (eval/scenes/kinds.py), and the frosted one with the globe
excluded from the bulb's shadows by shadow linking; eval/blender_scenes.py builds the twins from the same Scene."""

from __future__ import annotations

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.linking import Linking
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import box, icosphere
from .glass import ROUGH, glass_material

ROOM = (4.0, 4.0, 2.6)
GLOBE_R = 0.3
GLOBE_AT = (0.0, 0.0, 1.8)
BULB_R = 0.03
BULB_POWER = 150.0
KINDS = ("globe_frosted", "globe_clear", "globe_frosted_unshadowed")


def glass_globe(kind: str, width: int = 64, height: int = 48) -> Scene:
    """The room lit by a bulb in a frosted (roughness ROUGH) or clear (smooth) globe; globe_frosted_unshadowed: the
    frosted globe excluded from the bulb's blockers by shadow linking (docs/blender.md, what users can do)."""
    roughness = {"globe_frosted": ROUGH, "globe_clear": 0.0, "globe_frosted_unshadowed": ROUGH}[kind]
    links = Linking(blockers={"globe": "EXCLUDE"}) if kind == "globe_frosted_unshadowed" else Linking()
    rv, rt = box(ROOM)
    tv, tt = box((1.0, 0.6, 0.7))
    gv, gt = icosphere(3, GLOBE_R)
    mats = [Material("walls", (0.7, 0.7, 0.65)), Material("table", (0.3, 0.45, 0.6)),
            glass_material("globe", roughness)]
    meshes = [Mesh("room", rv, rt[:, ::-1].copy(), 0, translation(0.0, 0.0, ROOM[2] / 2)),
              Mesh("table", tv, tt, 1, translation(0.6, 0.5, 0.35)),
              Mesh("globe", gv, gt, 2, translation(*GLOBE_AT))]
    lights = [Light("bulb", "point", (1.0, 0.9, 0.75), BULB_POWER, translation(*GLOBE_AT), radius=BULB_R,
                    linking=links)]
    eye = look_at((-1.7, -1.8, 1.5), (0.4, 0.5, 0.9))
    cam = Camera(np.asarray(eye)[None], width, height, lens=24.0)
    return Scene(meshes, mats, lights, cam, name=f"glass_{kind}")
