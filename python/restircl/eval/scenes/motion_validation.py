"""Many-light scenes with a moving camera, for ReSTIR against RIS in motion (tools/experiments/restir_motion.py;
docs/measurements/temporal-stability.md, "ReSTIR DI in motion against RIS").

    garden_orbit       TUNING scene: the held-out garden (300 point lights over 24 x 24 m, eval/scenes/held_out.py)
                       seen from a camera orbiting its centre, 1 degree per frame. The defaults of ReSTIR in
                       motion were chosen on it.
    market_validation  VALIDATION scene, never tuned on: a market of stalls along three lanes, 420 lights of
                       three kinds (sphere lamps on strings above the lanes, spots under the awnings pointing down,
                       small square area lights on the stall fronts) of powers over three decades, seen from a camera
                       that flies down the middle lane while turning (1.5 degrees and 0.25 m per frame). It was
                       written after the defaults were chosen and is only rendered for the final before / after.
    market_orbit       VALIDATION scene, never tuned on: the same market seen from a camera orbiting its centre
                       from 15 m out and 7 m up, 1 degree per frame (the tuning scene's motion on another scene).
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
from .held_out import garden, placed, rot_z


def garden_orbit(width: int, height: int, frames: int, step_deg: float = 1.0) -> Scene:
    """The held-out garden with its camera orbiting the centre, `step_deg` per frame, from its own viewpoint on."""
    sc = garden(width, height)
    start = math.atan2(-17.0, 0.0)
    eyes = [(17.0 * math.cos(start + math.radians(step_deg * f)), 17.0 * math.sin(start + math.radians(step_deg * f)),
             7.5) for f in range(frames)]
    sc.camera = Camera(np.stack([look_at(e, (0.0, 0.0, 0.0)) for e in eyes]), width, height, lens=26.0)
    sc.name = "garden_orbit"
    return sc.validate()


def market_validation(width: int, height: int, frames: int, seed: int = 11) -> Scene:
    """Stalls along three lanes lit by lamps, spots and small panels; the camera flies down the middle lane."""
    rng = np.random.default_rng(seed)
    materials = [Material("paving", (0.45, 0.42, 0.4)), Material("stall", (0.6, 0.45, 0.3)),
                 Material("cloth", (0.7, 0.25, 0.2)), Material("crate", (0.5, 0.55, 0.35))]
    parts = [placed(quad(40, 40), np.eye(4), 0)]
    lights: list[Light] = []
    lanes = (-6.0, 0.0, 6.0)
    for lane in lanes:
        for side in (-1.0, 1.0):
            for k in range(9):
                y = -16.0 + 4.0 * k + rng.uniform(-0.4, 0.4)
                x = lane + side * 2.2
                h = rng.uniform(1.8, 2.6)
                parts.append(placed(box((1.6, 3.0, h)), translation(x, y, h / 2) @ rot_z(rng.uniform(-5, 5)), 1))
                parts.append(placed(box((2.0, 3.2, 0.08)), translation(x - side * 0.3, y, h + 0.3), 2))  # awning
                for _ in range(2):
                    c = rng.uniform(0.3, 0.6)
                    parts.append(placed(box((c, c, c)), translation(x - side * 1.2, y + rng.uniform(-1.2, 1.2), c / 2)
                                        @ rot_z(rng.uniform(0, 90)), 3))
                # a spot under the awning, pointing down at the counter, and a panel on the stall's front
                lights.append(Light(f"spot{len(lights)}", "spot", (1.0, 0.85, 0.6), float(np.exp(rng.uniform(
                    math.log(5.0), math.log(200.0)))), look_at((x - side * 0.9, y, h + 0.15), (x - side * 1.1, y, 0.0)),
                    radius=0.03, spot_size=math.radians(rng.uniform(50, 90)), spot_blend=0.3))
                lights.append(Light(f"panel{len(lights)}", "area", (0.8, 0.9, 1.0), float(np.exp(rng.uniform(
                    math.log(2.0), math.log(60.0)))), look_at((x - side * 0.81, y, 0.9), (x - side * 3.0, y, 0.9)),
                    shape="SQUARE", size=rng.uniform(0.15, 0.4)))
    # strings of sphere lamps across and along the lanes, 3-4 m up
    n_lamps = 420 - len(lights)
    for k in range(n_lamps):
        lane = lanes[k % 3]
        x = lane + rng.uniform(-1.4, 1.4)
        y = rng.uniform(-17.0, 17.0)
        z = 3.0 + 0.6 * math.cos((x - lane) * 1.1) + rng.uniform(0.0, 0.3)
        hue = rng.uniform(0, 1)
        col = (0.6 + 0.4 * math.cos(2 * math.pi * hue), 0.6 + 0.4 * math.cos(2 * math.pi * (hue - 1 / 3)),
               0.6 + 0.4 * math.cos(2 * math.pi * (hue - 2 / 3)))
        lights.append(Light(f"lamp{k}", "point", col, float(np.exp(rng.uniform(math.log(0.3), math.log(300.0)))),
                            translation(x, y, z), radius=float(rng.uniform(0.02, 0.08))))
    v, t, m = merge(parts)
    cams = []
    for f in range(frames):
        y = -18.0 + 0.25 * f
        yaw = math.radians(-20.0 + 1.5 * f)
        eye = (0.3, y, 2.2)
        cams.append(look_at(eye, (eye[0] + 6.0 * math.sin(yaw), y + 6.0 * math.cos(yaw), 0.8)))
    cam = Camera(np.stack(cams), width, height, lens=24.0)
    return Scene([Mesh("market", v, t, m)], materials, lights, cam, name="market_validation").validate()


def market_orbit(width: int, height: int, frames: int, step_deg: float = 1.0) -> Scene:
    """The validation market with its camera orbiting the centre, `step_deg` per frame."""
    sc = market_validation(width, height, 1)
    start = math.radians(-70.0)
    eyes = [(15.0 * math.cos(start + math.radians(step_deg * f)), 15.0 * math.sin(start + math.radians(step_deg * f)),
             7.0) for f in range(frames)]
    sc.camera = Camera(np.stack([look_at(e, (0.0, 0.0, 1.0)) for e in eyes]), width, height, lens=26.0)
    sc.name = "market_orbit"
    return sc.validate()


MOTION_SCENES = {"garden_orbit": garden_orbit, "market_validation": market_validation, "market_orbit": market_orbit}


def motion_scene(name: str, width: int, height: int, frames: int) -> Scene:
    if name not in MOTION_SCENES:
        raise ValueError(f"no motion scene {name!r}; scenes: {', '.join(MOTION_SCENES)}")
    return MOTION_SCENES[name](width, height, frames)
