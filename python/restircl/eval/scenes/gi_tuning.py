"""A tuning scene for global illumination against Cycles (`restircl compare --kinds gi_tuning_room --max-bounces 4`):
a room of the same kind as the validation scene `interior` (validation.py) but not the same, on which the path
pass's levers are measured and chosen, so that the validation scenes stay untouched by tuning.

    gi_tuning_room  a taller, narrower room than `interior`, its window in the left wall, walls of other colours,
                    a bluish glossy floor (Principled, roughness 0.35, specular 0.5), a gold sphere (metallic 1,
                    roughness 0.22), a glossy box and a diffuse table; lit by 20 ceiling spots in a 4 x 5 grid
                    (radius 3 cm, wider cones aimed further out, other powers) and an emissive mesh, a strip of
                    light (an open tube) along the back wall
    gi_tuning_yard  a scene of the validation scene `outdoor`'s kind: a ground under a generated HDRI with its sun
                    elsewhere (higher, to the left), a brushed metal sphere (roughness 0.3), a glossy blue box, two
                    diffuse blocks, a wall and, in its shadow, an emissive box (a glowing bench)

Materials are constant, as in the validation scenes, so the Cycles bridge writes the same Principled BSDFs.
"""

from __future__ import annotations

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
from .held_out import HEIGHT, WIDTH, placed, rot_x, rot_z, tube
from .validation import ceiling_spots, wall_with_window

KINDS = ("gi_tuning_room", "gi_tuning_yard")
YARD_SUN = (-0.45, 0.35, 0.82)  # gi_tuning_yard: towards the sun, about 55 degrees up, to the left
ROOM = (4.5, 6.5, 3.0)  # x, y, height (m)
SPOTS = (4, 5)  # ceiling spots along x and y


def _room(mats: dict[str, int]) -> list:
    """Floor, ceiling and four walls facing inwards; the left wall (-x) has the window."""
    sx, sy, sz = ROOM
    left = wall_with_window(sy, sz, (-1.5, 0.2, -0.5, 0.7))
    return [placed(quad(sx, sy), np.eye(4), mats["floor"]),
            placed(quad(sx, sy), translation(0, 0, sz) @ rot_x(180), mats["ceiling"]),
            placed(quad(sx, sz), translation(0, sy / 2, sz / 2) @ rot_x(90), mats["back"]),
            placed(quad(sx, sz), translation(0, -sy / 2, sz / 2) @ rot_x(-90), mats["front"]),
            *(placed(p, translation(-sx / 2, 0, sz / 2) @ rot_z(-90) @ rot_x(-90), mats["left"]) for p in left),
            placed(quad(sy, sz), translation(sx / 2, 0, sz / 2) @ rot_z(90) @ rot_x(-90), mats["right"])]


def _furniture(mats: dict[str, int]) -> list:
    """A table (top and four legs), a gold sphere and a glossy box on the floor, a light strip on the back wall."""
    sx, sy, _ = ROOM
    table = translation(-0.6, 1.2, 0.0)
    legs = [placed(box((0.06, 0.06, 0.72)), table @ translation(x, y, 0.36), mats["table"])
            for x in (-0.65, 0.65) for y in (-0.4, 0.4)]
    return [placed(box((1.5, 1.0, 0.05)), table @ translation(0, 0, 0.745), mats["table"]), *legs,
            placed(icosphere(3, 0.35), translation(1.1, 0.3, 0.35), mats["gold"]),
            placed(box((0.5, 0.4, 0.5)), translation(-1.3, -0.6, 0.25) @ rot_z(-20), mats["glossy_box"]),
            placed(tube(2.4, 0.03, 24, 8), translation(0.3, sy / 2 - 0.08, 2.2), mats["strip"])]


def _spots() -> list[Light]:
    """SPOTS ceiling spots 6 cm below the ceiling, pointing down and outwards (the outer ones light the walls),
    five powers in turn, warm and neutral."""
    return ceiling_spots(ROOM, SPOTS, 0.06, (1.3, 1.25), 0.03, 80, 0.3,
                         lambda i, j: (1.0, 0.9, 0.75) if (i + 2 * j) % 3 else (0.95, 0.95, 1.0),
                         lambda i, j: 20.0 + 6.0 * ((2 * i + j) % 5))


def gi_tuning_room(width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """A room lit by 20 ceiling spots and a light strip: diffuse, glossy and metal surfaces, for tuning."""
    materials = [Material("floor", (0.3, 0.3, 0.35), roughness=0.35, specular=0.5),
                 Material("ceiling", (0.85, 0.85, 0.85)), Material("back", (0.75, 0.7, 0.45)),
                 Material("front", (0.7, 0.7, 0.7)), Material("left", (0.25, 0.35, 0.6)),
                 Material("right", (0.6, 0.3, 0.45)), Material("table", (0.5, 0.32, 0.18)),
                 Material("gold", (1.0, 0.78, 0.34), metallic=1.0, roughness=0.22),
                 Material("glossy_box", (0.15, 0.5, 0.2), roughness=0.25, specular=0.5),
                 Material("strip", (0.0, 0.0, 0.0), (0.9, 0.95, 1.0), 20.0)]
    mats = {m.name: i for i, m in enumerate(materials)}
    v, t, m = merge(_room(mats) + _furniture(mats))
    sx, sy, _ = ROOM
    cam = Camera(look_at((sx / 2 - 0.3, -sy / 2 + 0.4, 1.7), (-0.4, 1.0, 0.7)), width, height, lens=18.0)
    return Scene([Mesh("gi_tuning_room", v, t, m)], materials, _spots(), cam, name="gi_tuning_room")


def gi_tuning_yard(width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """Objects on a ground under a sunny HDRI, and a glowing box in a wall's shadow, for tuning."""
    materials = [Material("ground", (0.35, 0.38, 0.3)),
                 Material("metal", (0.85, 0.85, 0.88), metallic=1.0, roughness=0.3),
                 Material("blue_gloss", (0.1, 0.2, 0.6), roughness=0.25, specular=0.5),
                 Material("block", (0.55, 0.5, 0.48)), Material("wall", (0.7, 0.68, 0.66)),
                 Material("glow", (0.0, 0.0, 0.0), (1.0, 0.6, 0.3), 6.0)]
    parts = [placed(quad(40, 40), np.eye(4), 0),
             placed(icosphere(3, 0.45), translation(-0.8, 0.0, 0.45), 1),
             placed(box((0.8, 0.6, 0.7)), translation(0.9, 0.7, 0.35) @ rot_z(-25), 2),
             placed(box((0.5, 0.5, 1.1)), translation(2.0, -0.6, 0.55) @ rot_z(10), 3),
             placed(box((0.6, 0.6, 0.4)), translation(-2.1, 1.2, 0.2) @ rot_z(40), 3),
             placed(box((4.0, 0.3, 2.2)), translation(-0.3, 2.8, 1.1) @ rot_z(6), 4),
             placed(box((1.2, 0.3, 0.35)), translation(0.6, 2.2, 0.175) @ rot_z(6), 5)]
    v, t, m = merge(parts)
    world = Environment("tuning_sky", color=(1.0, 1.0, 1.0), strength=1.0,
                        image=sky_map(256, 512, sun=np.array(YARD_SUN)))
    cam = Camera(look_at((-0.8, -5.5, 2.2), (0.2, 1.0, 0.4)), width, height, lens=28.0)
    return Scene([Mesh("gi_tuning_yard", v, t, m)], materials, [], cam, name="gi_tuning_yard", environment=world)


BUILDERS = {"gi_tuning_room": gi_tuning_room, "gi_tuning_yard": gi_tuning_yard}


def gi_tuning(kind: str, width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """The tuning scene of `kind` (gi_tuning_room, gi_tuning_yard) at width x height."""
    if kind not in BUILDERS:
        raise ValueError(f"no tuning scene {kind!r}; kinds: {', '.join(KINDS)}")
    return BUILDERS[kind](width, height).validate()
