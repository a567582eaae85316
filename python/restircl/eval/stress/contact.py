"""The stress case of receivers touching emitters (eval/stress/suite.py): where a light sampled uniformly in area gives
samples whose weight grows as 1 / d^2 (opencl/lights/solid_angle.h SA_NEAR_RATIO), so that the error stops falling
as 1 / N. Judged, besides the suite's tests of the mean, by the fall of its relMSE with the number of frames
(eval/stress/convergence.py).

An arena seen from straight above by an orthographic camera: a floor whose four sides are emitters standing on it or
leaning off it, so that the pixel centres next to each side are at known, small distances from a contact line:

    left    an emissive quad (two triangles) standing on the floor, 2 mm from the nearest pixel centres
    right   an emissive quad leaning outwards at 8 degrees (grazing: the floor sees it edge-on), 1 cm
    bottom  a rectangle area light standing on the floor, facing in, 3 cm
    top     a second emissive quad standing on the floor, 6 cm

plus a sphere light and a soft-falloff point light resting on the floor inside. The floor ends at the sides: the
arena is convex and nothing else is in it, so no emitter shadows another anywhere on the floor, and the analytic
reference (eval/stress/references.py) is exact at the pixel centres (no jitter). An orthographic camera looking
straight down puts the pixel centres on a known grid (x, y = +-(2k + 1) / n) whatever the sign conventions, and sees
the standing emitters edge-on. The distances span the range where the weights of area sampling were rare and large:
at 2 mm a uniform pick of the left quad draws, about once in 1e6 samples, a point near its foot worth of the order
of 1e5 times the pixel's value.

The renders draw random numbers (sampler `random`): RIS stills otherwise draw from the Sobol sequence, whose error
may fall faster than 1 / N (on a lone light, much faster), and the convergence test is of the Monte Carlo rate.
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
from .cases import Case, _standing

#: the distance of each side's contact line from the nearest pixel centres (m): left, right, bottom, top
OFFSETS = (0.002, 0.01, 0.03, 0.06)
HEIGHT = 0.5  # of the standing emitters
LEAN = math.radians(8.0)  # the right quad's angle over the floor
QUAD = [[0, 1, 2], [0, 2, 3]]


def _arena(n: int) -> Scene:
    """The arena seen by an n x n orthographic camera whose view is [-1, 1]^2."""
    c = 1.0 - 3.0 / n  # the centre of the second pixel from the image's edge
    xl, xr, yb, yt = -c - OFFSETS[0], c + OFFSETS[1], -c - OFFSETS[2], c + OFFSETS[3]
    h = HEIGHT
    materials = [Material("grey", (0.7, 0.7, 0.7)), Material("warm", (0, 0, 0), (1.0, 0.7, 0.4), 4.0),
                 Material("cool", (0, 0, 0), (0.5, 0.8, 1.0), 4.0)]
    out = 0.6  # the leaning quad's length away from the floor
    ox, oz = out * math.cos(LEAN), out * math.sin(LEAN)
    quads = {
        "floor": ([[xl, yb, 0], [xr, yb, 0], [xr, yt, 0], [xl, yt, 0]], 0),
        "left": ([[xl, yb, 0], [xl, yt, 0], [xl, yt, h], [xl, yb, h]], 1),
        "top": ([[xl, yt, 0], [xr, yt, 0], [xr, yt, h], [xl, yt, h]], 2),
        "right": ([[xr, yb, 0], [xr, yt, 0], [xr + ox, yt, oz], [xr + ox, yb, oz]], 1),
    }
    meshes = [Mesh(name, np.array(v, float), QUAD, m) for name, (v, m) in quads.items()]
    lights = [
        _standing(((xl + xr) / 2, yb, h / 2), (0.0, 1.0, 0.0), xr - xl, h, 20.0, "bottom", (0.6, 0.8, 1.0)),
        Light("resting_sphere", "point", (0.8, 1.0, 0.6), 10.0, translation(0.3, 0.2, 0.15), radius=0.15,
              soft_falloff=False),
        Light("resting_soft", "point", (1.0, 0.9, 0.7), 10.0, translation(-0.3, -0.2, 0.12), radius=0.12),
    ]
    cam = Camera(look_at((0.0, 0.0, 5.0), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0)), n, n, type="ORTHO",
                 ortho_scale=2.0)
    return Scene(meshes, materials, lights, cam, name="contact")


def contact(full: bool) -> Case:
    """Receivers 2 mm .. 6 cm from emitters that touch the floor: emissive quads standing and leaning (grazing), a
    rectangle light standing, a sphere light and a soft point light resting; analytic reference, and the relMSE at
    8, 32, 128 (full: 64, 256, 1024) frames must fall as 1 / N."""
    return Case("contact", "receivers 2 mm..6 cm from emitters touching the floor", _arena(32 if full else 16),
                runs=24 if full else 16, frames=64 if full else 16, settings=dict(sampler="random"),
                convergence=(64, 256, 1024) if full else (8, 32, 128), convergence_runs=16 if full else 8)
