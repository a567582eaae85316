"""Validation scenes for global illumination against Cycles (`restircl compare --kinds interior,outdoor
--max-bounces 4`): scenes built to check that a converged render of ours with bounces agrees with Cycles', and to
measure error against time with the same Light Paths on both sides.

They are validation scenes, not tuning scenes that happen to have bounces: nothing in the renderer, its settings
or the still path's rule (render/still_method.py) is tuned on them, and they were written after the path pass was
done, so an agreement measured on them is not one that was fitted. A lever measured on them to choose a setting
would make them tuning scenes; such a lever belongs on other scenes, and these stay as they are.

    interior  a room closed but for a window (black outside: the paths that leave end there), walls of three
              colours, a glossy floor (Principled, roughness 0.3, specular 0.5), a copper sphere (metallic 1,
              roughness 0.25), a diffuse sofa of boxes and a glossy plastic vase; lit by 24 ceiling spots
              (radius 4 cm, so BSDF-sampled rays meet them as they meet Cycles' spot spheres) and one emissive
              mesh, the open shade of a floor lamp (a tube of 576 triangles)
    outdoor   a ground under a generated HDRI with a sun in it (environment only, no light objects: the sky
              generator of the built-in `sky`, its sun disk 1.6 degrees wide and ~1e3 above the sky, towards
              another direction than the tuning sky's), a chrome sphere (metallic 1, roughness 0.2), a glossy red
              box (roughness 0.3, specular 0.5), a diffuse lumpy mesh, a diffuse wall that casts a shadow, and an
              emissive torus lying in that shadow

Materials are constant (no textures): the Cycles bridge (eval/cycles/bridge.py, materials.py) writes the same
Principled BSDFs, and the lights are those of docs/units.md.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ...environment.world import Environment
from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.hdri_sky import sky_map
from ...scenes.shapes import box, icosphere, merge, quad
from .held_out import HEIGHT, WIDTH, blob, placed, rot_x, rot_z, torus, tube

KINDS = ("interior", "outdoor")
ROOM = (6.0, 5.0, 2.8)  # interior: x, y, height (m)
SPOTS = (6, 4)  # interior: ceiling spots along x and y
OUTDOOR_SUN = (0.55, 0.62, 0.56)  # towards the sun: about 34 degrees up, behind the objects to the right


def rect(x0: float, x1: float, y0: float, y1: float) -> tuple[np.ndarray, np.ndarray]:
    """A quad over [x0, x1] x [y0, y1] in the XY plane, facing +Z."""
    v, t = quad(x1 - x0, y1 - y0)
    return v + ((x0 + x1) / 2, (y0 + y1) / 2, 0.0), t


def wall_with_window(width: float, height: float, window: tuple[float, float, float, float]
                     ) -> list[tuple[np.ndarray, np.ndarray]]:
    """A wall in the XY plane (centred, facing +Z) with a rectangular hole window = (x0, x1, y0, y1): four quads."""
    x0, x1, y0, y1 = window
    w, h = width / 2, height / 2
    return [rect(-w, w, -h, y0), rect(-w, w, y1, h), rect(-w, x0, y0, y1), rect(x1, w, y0, y1)]


def _room(mats: dict[str, int]) -> list:
    """Floor, ceiling and four walls facing inwards; the right wall (+x) has the window."""
    sx, sy, sz = ROOM
    right = wall_with_window(sy, sz, (-0.9, 0.6, -0.6, 0.5))
    return [placed(quad(sx, sy), np.eye(4), mats["floor"]),
            placed(quad(sx, sy), translation(0, 0, sz) @ rot_x(180), mats["ceiling"]),
            placed(quad(sx, sz), translation(0, sy / 2, sz / 2) @ rot_x(90), mats["back"]),
            placed(quad(sx, sz), translation(0, -sy / 2, sz / 2) @ rot_x(-90), mats["back"]),
            placed(quad(sy, sz), translation(-sx / 2, 0, sz / 2) @ rot_z(-90) @ rot_x(-90), mats["left"]),
            *(placed(p, translation(sx / 2, 0, sz / 2) @ rot_z(90) @ rot_x(-90), mats["right"]) for p in right)]


def _furniture(mats: dict[str, int]) -> list:
    """A sofa of four boxes against the back wall, a copper sphere and a vase on the floor, a floor lamp (pole and
    an open emissive shade) in the back right corner."""
    sofa = translation(-1.2, 1.85, 0.0)
    parts = [placed(box((2.2, 0.9, 0.45)), sofa @ translation(0, 0, 0.225), mats["sofa"]),
             placed(box((2.2, 0.25, 0.55)), sofa @ translation(0, 0.33, 0.72), mats["sofa"]),
             placed(box((0.25, 0.9, 0.3)), sofa @ translation(-0.98, 0, 0.6), mats["sofa"]),
             placed(box((0.25, 0.9, 0.3)), sofa @ translation(0.98, 0, 0.6), mats["sofa"]),
             placed(icosphere(3, 0.42), translation(0.7, 0.2, 0.42), mats["copper"]),
             placed(box((0.3, 0.3, 0.7)), translation(1.7, -0.6, 0.35) @ rot_z(25), mats["vase"]),
             placed(box((0.05, 0.05, 1.5)), translation(2.3, 1.9, 0.75), mats["pole"]),
             placed(tube(0.35, 0.22, 8, 36), translation(2.3, 1.9, 1.55) @ _up(), mats["shade"])]
    return parts


def _up() -> np.ndarray:
    """The rotation that turns a tube along X upright (along Z)."""
    m = np.eye(4)
    m[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]
    return m


def ceiling_spots(room: tuple[float, float, float], grid: tuple[int, int], drop: float, aim: tuple[float, float],
                  radius: float, size_deg: float, blend: float, colour: Callable[[int, int], tuple],
                  power: Callable[[int, int], float]) -> list[Light]:
    """A grid of spots `drop` below the ceiling of a room centred on the origin, the spot of cell (i, j) at (x, y)
    aiming at (aim_x x, aim_y y) on the floor (1: straight down, more: outwards), of colour(i, j) and power(i, j)."""
    sx, sy, sz = room
    nx, ny = grid
    out = []
    for i in range(nx):
        for j in range(ny):
            x, y = (i + 0.5) / nx * sx - sx / 2, (j + 0.5) / ny * sy - sy / 2
            out.append(Light(f"spot{i}_{j}", "spot", colour(i, j), power(i, j),
                             look_at((x, y, sz - drop), (aim[0] * x, aim[1] * y, 0.0)), radius=radius,
                             spot_size=math.radians(size_deg), spot_blend=blend))
    return out


def _spots() -> list[Light]:
    """SPOTS ceiling spots 5 cm below the ceiling, pointing down and a little outwards, warm and cool in turn."""
    return ceiling_spots(ROOM, SPOTS, 0.05, (1.15, 1.15), 0.04, 75, 0.35,
                         lambda i, j: (1.0, 0.85, 0.7) if (i + j) % 2 else (0.85, 0.9, 1.0),
                         lambda i, j: 25.0 + 5.0 * ((3 * i + j) % 4))


def interior(width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """A room lit by 24 ceiling spots and a lamp's emissive shade: diffuse, glossy and metal surfaces."""
    materials = [Material("floor", (0.45, 0.33, 0.22), roughness=0.3, specular=0.5),
                 Material("ceiling", (0.8, 0.8, 0.78)), Material("back", (0.7, 0.68, 0.62)),
                 Material("left", (0.65, 0.22, 0.15)), Material("right", (0.2, 0.45, 0.3)),
                 Material("sofa", (0.2, 0.28, 0.55)),
                 Material("copper", (0.95, 0.64, 0.54), metallic=1.0, roughness=0.25),
                 Material("vase", (0.85, 0.8, 0.3), roughness=0.2, specular=0.5),
                 Material("pole", (0.1, 0.1, 0.1)),
                 Material("shade", (0.0, 0.0, 0.0), (1.0, 0.8, 0.55), 12.0)]
    mats = {m.name: i for i, m in enumerate(materials)}
    v, t, m = merge(_room(mats) + _furniture(mats))
    sx, sy, _ = ROOM
    cam = Camera(look_at((-0.4, -sy / 2 + 0.35, 1.55), (0.2, 1.2, 0.8)), width, height, lens=17.0)
    return Scene([Mesh("interior", v, t, m)], materials, _spots(), cam, name="interior")


def outdoor(width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """Objects on a ground under a sunny HDRI, and an emissive torus in a wall's shadow."""
    materials = [Material("ground", (0.42, 0.4, 0.34)),
                 Material("chrome", (0.92, 0.92, 0.94), metallic=1.0, roughness=0.2),
                 Material("red_gloss", (0.7, 0.12, 0.08), roughness=0.3, specular=0.5),
                 Material("lump", (0.6, 0.55, 0.45)), Material("wall", (0.75, 0.75, 0.72)),
                 Material("ring", (0.0, 0.0, 0.0), (0.3, 0.8, 1.0), 8.0)]
    parts = [placed(quad(40, 40), np.eye(4), 0),
             placed(icosphere(3, 0.55), translation(0.9, 0.2, 0.55), 1),
             placed(box((0.9, 0.9, 0.9)), translation(-0.2, 0.9, 0.45) @ rot_z(35), 2),
             placed(blob(4, 0.55, seed=11), translation(-2.0, -0.4, 0.55), 3),
             placed(box((3.5, 0.25, 1.8)), translation(0.2, 2.6, 0.9) @ rot_z(-8), 4),
             placed(torus(0.45, 0.05, 72, 10), translation(-1.4, 1.6, 0.05), 5)]
    v, t, m = merge(parts)
    world = Environment("validation_sky", color=(1.0, 1.0, 1.0), strength=1.0,
                        image=sky_map(256, 512, sun=np.array(OUTDOOR_SUN)))
    cam = Camera(look_at((0.6, -5.8, 1.9), (-0.1, 0.8, 0.5)), width, height, lens=30.0)
    return Scene([Mesh("outdoor", v, t, m)], materials, [], cam, name="outdoor", environment=world)


BUILDERS = {"interior": interior, "outdoor": outdoor}


def validation(kind: str, width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """The validation scene of `kind` (interior, outdoor) at width x height."""
    if kind not in BUILDERS:
        raise ValueError(f"no validation scene {kind!r}; kinds: {', '.join(KINDS)}")
    return BUILDERS[kind](width, height).validate()
