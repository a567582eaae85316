"""A rough glass pane with a light behind it (issue 39's transmission passes and lights behind rough glass), built
the same way here and in Blender (eval/cycles/bridge.py to_bpy): a single-sheet pane of rough glass (the Glass BSDF,
roughness 0.3, IOR 1.45) standing on a grey floor, an area light behind it facing the camera, so that the pane's
pixels take its light through their transmission (direct, and bounced off the floor behind), and a second area
light above the camera's side for the reflected part. `lights_behind` > 1 puts that many small area lights in a row
behind the pane instead of the one (their total power the same): a many-light scene whose light tree must rank
lights behind a transmitting surface."""

from __future__ import annotations

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import quad

ROUGH = 0.3
IOR = 1.45
BEHIND_POWER = 120.0
FRONT_POWER = 60.0
# rotations about x: +90 turns a quad's +z normal to -y (the pane faces the camera), -90 turns a light's -z to -y
RX_UP = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], float)
RX_DOWN = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, 0, 0], [0, 0, 0, 1]], float)


def glass_pane(width: int = 64, height: int = 48, lights_behind: int = 1, front: bool = True) -> Scene:
    fv, ft = quad(8.0, 8.0)
    pv, pt = quad(1.6, 1.2)
    mats = [Material("floor", (0.6, 0.6, 0.6)),
            Material("frosted", (1.0, 1.0, 1.0), kind="glass", roughness=ROUGH, ior=IOR)]
    meshes = [Mesh("floor", fv, ft, 0), Mesh("pane", pv, pt, 1, translation(0.0, 0.0, 0.8) @ RX_UP)]
    lights = []
    for k in range(lights_behind):
        x = 0.0 if lights_behind == 1 else -0.6 + 1.2 * k / (lights_behind - 1)
        size = 0.8 if lights_behind == 1 else 0.8 / lights_behind
        lights.append(Light(f"behind{k}", "area", (1.0, 0.9, 0.8), BEHIND_POWER / lights_behind,
                            translation(x, 1.0, 0.9) @ RX_DOWN, size=size))
    if front:
        lights.append(Light("front", "area", (0.8, 0.9, 1.0), FRONT_POWER, translation(0.9, -1.6, 2.4), size=0.5))
    eye = look_at((0.3, -3.2, 1.3), (0.0, 0.0, 0.75))
    cam = Camera(eye[None], width, height, lens=35.0)
    return Scene(meshes, mats, lights, cam, name=f"glass_pane_{lights_behind}")
