"""Validation scenes of direct light against Cycles (`restircl compare --kinds gallery`): built once, beside the
tuning scenes (held_out.py) whose kinds the still estimator's rules, the light tree's `tree_pays` and the
sunny-world threshold were chosen on. Nothing is tuned on them: a figure measured here is one the rules were not
fitted to. A lever measured on them to choose a setting would make them tuning scenes.

    gallery  a long hall of diffuse and glossy walls with plinths, 48 small spots over the walls and 120 tiny point
             lights in a ceiling grid (powers over 3 decades: a mix of the tuning kinds' few-large and many-small
             lights), three area lights (square, disk, rectangle), and an emissive sign of a few hundred triangles

Materials are constant, the light types and units those of docs/units.md, so a converged render agrees with Cycles.
"""

from __future__ import annotations

import math

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import box, merge, quad
from .held_out import HEIGHT, WIDTH, placed, rot_z, torus

KINDS = ("gallery",)
HALL = (16.0, 6.0, 4.0)  # x (length), y (width), height (m)


def _hall() -> list:
    sx, sy, sz = HALL
    parts = [placed(quad(sx, sy), np.eye(4), 0),
             placed(box((sx, 0.2, sz)), translation(0, sy / 2 + 0.1, sz / 2), 1),
             placed(box((sx, 0.2, sz)), translation(0, -sy / 2 - 0.1, sz / 2), 1),
             placed(box((0.2, sy, sz)), translation(sx / 2 + 0.1, 0, sz / 2), 2),
             placed(box((sx, sy, 0.2)), translation(0, 0, sz + 0.1), 3)]
    for k in range(6):
        x = -6.0 + 2.4 * k
        parts.append(placed(box((0.6, 0.6, 1.0 + 0.1 * k)), translation(x, 0.8 * (-1) ** k, 0.5 + 0.05 * k) @
                            rot_z(15 * k), 4 + k % 2))
    parts.append(placed(torus(0.6, 0.04, 96, 8), translation(sx / 2 - 0.05, 0, 2.2) @ _facing_x(), 6))
    return parts


def _facing_x() -> np.ndarray:
    """The rotation that stands a torus around Z up against a wall facing -X."""
    m = np.eye(4)
    m[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    return m


def _lights() -> list[Light]:
    sx, sy, sz = HALL
    rng = np.random.default_rng(2026)
    out = []
    for k in range(24):
        for side in (-1, 1):
            x = -sx / 2 + (k + 0.5) * sx / 24
            out.append(Light(f"spot{k}_{side}", "spot", (1.0, 0.9, 0.75), float(rng.uniform(5, 40)),
                             look_at((x, side * (sy / 2 - 0.6), sz - 0.1), (x, side * sy / 2, 1.5)), radius=0.03,
                             spot_size=math.radians(50), spot_blend=0.3))
    for i in range(20):
        for j in range(6):
            out.append(Light(f"point{i}_{j}", "point", tuple(rng.uniform(0.5, 1.0, 3)),
                             float(10 ** rng.uniform(-1, 2)),
                             translation(-sx / 2 + (i + 0.5) * sx / 20, -sy / 2 + (j + 0.5) * sy / 6, sz - 0.3),
                             radius=0.02))
    out += [Light("square", "area", (1.0, 1.0, 1.0), 300.0, translation(-5.0, 0.0, sz - 0.02), shape="SQUARE",
                  size=1.0),
            Light("disk", "area", (1.0, 0.85, 0.7), 200.0, translation(0.0, 0.0, sz - 0.02), shape="DISK", size=0.8),
            Light("rectangle", "area", (0.8, 0.9, 1.0), 250.0, translation(5.0, 0.0, sz - 0.02),
                  shape="RECTANGLE", size=1.6, size_y=0.4)]
    return out


def gallery(width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """The hall of the module's docstring."""
    materials = [Material("floor", (0.35, 0.3, 0.26), roughness=0.35, specular=0.5),
                 Material("side_wall", (0.75, 0.73, 0.68)), Material("end_wall", (0.3, 0.4, 0.55)),
                 Material("ceiling", (0.8, 0.8, 0.8)), Material("plinth", (0.85, 0.85, 0.85)),
                 Material("plinth_gloss", (0.15, 0.15, 0.15), roughness=0.2, specular=0.5),
                 Material("sign", (0.0, 0.0, 0.0), (1.0, 0.3, 0.5), 6.0)]
    v, t, m = merge(_hall())
    cam = Camera(look_at((-7.5, -2.2, 1.7), (2.0, 0.6, 1.4)), width, height, lens=20.0)
    return Scene([Mesh("gallery", v, t, m)], materials, _lights(), cam, name="gallery")


def validation_direct(kind: str, width: int = WIDTH, height: int = HEIGHT) -> Scene:
    """The direct-light validation scene of `kind` (gallery) at width x height."""
    if kind not in KINDS:
        raise ValueError(f"no direct-light validation scene {kind!r}; kinds: {', '.join(KINDS)}")
    return gallery(width, height).validate()
