"""Stability on stiff and extreme cases (`restircl stress`, DESIGN section 5), and the benchmark of specialised
against general kernel builds (DESIGN section 6).

Every case is a built-in scene generated here, in a small version (the tests) and a full one (the CLI, --full).
Each is rendered with every method -- uniform, light_array, ris, restir biased (bias_correction "none") and
unbiased ("pairwise") -- and checked against its reference:

    analytic    direct light computed on the host in float64 at the renderer's own G-buffer points: point and
                spot lights, spheres and soft-falloff disks, suns, quads and triangles (Lambert's polygon formula)
                fully above or below each point's horizon; only for scenes where nothing occludes a light
    exhaustive  the `reference` method (every light, one sample each), averaged over batches of frames; a
                scene of delta lights only needs one frame
    zero        the image must be exactly 0 (every light behind the surfaces)

A case is judged by its statistics, never by a tuned threshold. Independent runs (fresh history, own seed) give
run means whose spread is the standard error; an unbiased method passes when at most `allowed_outliers` pixels
are more than 4 standard errors from the reference (t with runs - 1 degrees of freedom; pixels where both
sides are exact must agree to float32 rounding) and the image mean is within 4 standard errors. The biased ReSTIR
mode must not be brighter than the reference beyond 4 standard errors and not darker than the 15% that
tests/test_restir.py bounds its darkening by. Every case requires zero NaN/Inf: the renderer's guard counters
(Frame.guards) plus a scan of every array it returned. relMSE = mean (x - r)^2 / (r^2 + 0.01) of the mean image;
`expected` is what the measured variances alone predict for it (a ratio near 1 means no visible bias).

Kinds of case: `still` (runs of a still camera, render_still), `sequence` (per run: a few frames, then the frame
under test; its 1-sample image is the run's value, the mean of 8 samples of that frame for methods without
history) and `long` (one very long animation with TAA and ReSTIR,
compared by batch means over its second part; the ReSTIR M and the TAA history length are checked to stay
capped).
"""

from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pyopencl as cl

from .. import layouts as L
from ..lights import LUMINANCE, scene_lights
from ..pipeline import Frame, Renderer, Settings
from ..scene import Camera, Light, Material, Mesh, Scene, look_at, translation
from ..scenes import box, quad

# name -> Settings overrides
METHODS: dict[str, dict] = {
    "uniform": dict(method="uniform"),
    "light_array": dict(method="light_array"),
    "ris": dict(method="ris"),
    "restir_biased": dict(method="restir", bias_correction="none"),
    "restir_unbiased": dict(method="restir", bias_correction="pairwise"),
}
Z = 4.0  # standard errors
BIASED_DARKENING = 0.15  # the bound tests/test_restir.py puts on the biased mode's darkening
F32_EPS = 2.0**-24

# ReSTIR's temporal and spatial reuse with the default cap (20 x candidates) make run means heavy-tailed (a lucky
# sample persists for tens of frames, tests/test_restir.py); the still cases use the cap 4x so that a few dozen
# runs can judge them. The long animation keeps the default cap: that is where the cap itself is under test.
STILL_SETTINGS = dict(jitter=False, taa=False, m_cap=4.0)

# A 4-standard-error test of a mean needs the mean to be close to normal. One-sample estimates of the many-light
# cases are strongly skewed where a light is picked rarely but contributes much: computed from the per-light
# contributions of million_lights, the per-sample skewness is 4.1 for uniform picks and 1.6 for the light array
# (median over pixels); in power_span, uniform picks of its 1e6 W light alone (p = 1/13) give about 3. The skewness
# of a mean of n samples falls as 1/sqrt(n): uniform and light_array get 4x and 2x the frames (they are also the
# cheapest), so that their run means are about as close to normal as RIS's. (With 2.5 m between the lights and the
# floor and strengths over four decades, million_lights had 14 and 5, and uniform failed 3 of 7 seed sweeps.)
FRAMES_FACTOR = {"uniform": 4, "light_array": 2}


# ---- the cases ----------------------------------------------------------------------------------------


@dataclass
class Case:
    name: str
    description: str
    scene: Scene
    kind: str = "still"  # still | sequence | long
    reference: str = "analytic"  # analytic | exhaustive | zero
    runs: int = 16  # still, sequence: independent runs
    frames: int = 16  # still: frames per run; long: frames in all
    before: tuple[int, ...] = ()  # sequence: frames rendered before the one under test
    eval_repeats: int = 8  # sequence, methods without history: samples of the frame under test per run
    eval_frame: int = 0
    zero_after: tuple[int, ...] = ()  # sequence: frames rendered after it whose image must be exactly 0
    ref_batches: int = 16  # exhaustive reference: batches of ref_frames frames
    ref_frames: int = 32
    settings: dict = field(default_factory=dict)  # overrides for every method
    cut_expected: bool = False  # sequence: the frame under test must run without temporal reuse
    no_ghost: bool = False  # sequence: with TAA on, the frame under test must be its own sample (history rejected)
    long_batch: int = 100  # long: frames per batch mean
    long_warmup: int = 100  # long: frames before the batches start


def _floor(size: float = 4.0, material: int = 0, z: float = 0.0) -> Mesh:
    v, t = quad(size, size)
    return Mesh("floor", v + (0.0, 0.0, z), t, material)


def _grey() -> list[Material]:
    return [Material("grey", (0.7, 0.7, 0.7))]


def _cam(eye, target, w: int, h: int, lens: float = 28.0, frames: int = 1, cuts: tuple[int, ...] = ()) -> Camera:
    m = look_at(eye, target)
    return Camera(np.repeat(m[None], frames, axis=0), w, h, lens=lens, cuts=cuts)


def _standing(centre, facing, w: float, h: float, power: float, name: str, color=(1.0, 1.0, 1.0)) -> Light:
    """A rectangular area light standing on the floor (its lower edge at z = 0), emitting along `facing`."""
    c = np.asarray(centre, float)
    m = look_at(c, c + np.asarray(facing, float))
    return Light(name, "area", color, power, m, shape="RECTANGLE", size=w, size_y=h)


def power_span(full: bool) -> Case:
    """Thirteen (full: 61) lights of every type whose powers span 1e-6..1e6, over a floor with an occluding
    block; exhaustive reference."""
    w, h = (64, 48) if full else (16, 12)
    rng = np.random.default_rng(11)
    exps = np.linspace(-6, 6, 61 if full else 13)
    bv, bt = box((0.6, 0.6, 0.8))
    meshes = [_floor(6.0), Mesh("block", bv + (0.3, 0.2, 0.4), bt, 0)]
    materials = _grey()
    lights: list[Light] = []
    kinds = ("point", "soft", "sphere", "spot", "quad", "disk", "triangle", "sun")
    for k, e in enumerate(exps):
        p = float(10.0**e)
        kind = kinds[k % len(kinds)]
        x, y = rng.uniform(-2.0, 2.0, 2)
        z = float(rng.uniform(0.6, 2.5))
        col = tuple(rng.uniform(0.4, 1.0, 3))
        if p >= 1e5:  # the brightest lights stay far, so that the image does not saturate to one light
            z = 30.0
        name = f"{kind}_{e:+.1f}"
        if kind == "point":
            lights.append(Light(name, "point", col, p, translation(x, y, z)))
        elif kind == "soft":
            lights.append(Light(name, "point", col, p, translation(x, y, z), radius=0.15))
        elif kind == "sphere":
            lights.append(Light(name, "point", col, p, translation(x, y, z), radius=0.1, soft_falloff=False))
        elif kind == "spot":
            lights.append(Light(name, "spot", col, p, look_at((x, y, z), (x * 0.5, y * 0.5, 0)), spot_size=0.9,
                                spot_blend=0.2))
        elif kind == "quad":
            lights.append(Light(name, "area", col, p, translation(x, y, z), size=0.4))
        elif kind == "disk":
            lights.append(Light(name, "area", col, p, translation(x, y, z), shape="DISK", size=0.5))
        elif kind == "sun":
            lights.append(Light(name, "sun", col, p, look_at((x, y, 3.0), (0, 0, 0)), angle=0.05))
        else:  # an emissive triangle of radiance p / (pi A): power p like the area lights
            tv = np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.3, 0.0]]) + (x, y, z)
            materials.append(Material(name, (0, 0, 0), col, p / (math.pi * 0.045)))
            meshes.append(Mesh(name, tv, [[0, 1, 2]], len(materials) - 1))
    cam = _cam((0.0, -4.5, 3.2), (0.0, 0.2, 0.2), w, h)
    return Case("power_span", "powers 1e-6..1e6, every light type, an occluder", Scene(meshes, materials, lights, cam,
                name="power_span"), reference="exhaustive", runs=24 if full else 16, frames=64 if full else 16,
                ref_batches=32 if full else 16, ref_frames=64 if full else 32)


def million_lights(full: bool) -> Case:
    """1e6 (small: 2e4) emissive triangles of strengths over two decades in a plane 6 m above a floor; analytic
    reference (the triangles share one plane, so none shadows another)."""
    w, h = (24, 18) if full else (16, 12)
    n = 1_000_000 if full else 20_000
    rng = np.random.default_rng(5)
    side = int(math.ceil(math.sqrt(n)))
    cell = 20.0 / side
    idx = rng.permutation(side * side)[:n]
    gx, gy = np.divmod(idx, side)
    cx = (gx + rng.uniform(0.2, 0.8, n)) * cell - 10.0
    cy = (gy + rng.uniform(0.2, 0.8, n)) * cell - 10.0
    size = 0.2 * cell  # centre to corner
    ang = rng.uniform(0, 2 * math.pi, n)
    verts = np.zeros((n, 3, 3))
    for k in range(3):
        a = ang + k * 2 * math.pi / 3
        verts[:, k, 0] = cx + size * np.cos(a)
        verts[:, k, 1] = cy + size * np.sin(a)
    verts[:, :, 2] = 6.0
    n_mat = 32
    strengths = np.logspace(0, 2, n_mat)
    materials = _grey() + [Material(f"lamp{k}", (0, 0, 0), tuple(0.5 + 0.5 * rng.random(3)), float(strengths[k]))
                           for k in range(n_mat)]
    mats = 1 + rng.integers(0, n_mat, n)
    lamps = Mesh("lamps", verts.reshape(-1, 3), np.arange(3 * n).reshape(n, 3), mats)
    eye = np.array([0.0, -3.0, 1.2])
    cam = _cam(eye, eye + (0.0, math.cos(0.55), -math.sin(0.55)), w, h, lens=35.0)
    scene = Scene([_floor(24.0), lamps], materials, [], cam, name="million_lights")
    return Case("million_lights", f"{n} emissive triangles", scene, runs=16, frames=32)


def area_extremes(full: bool) -> Case:
    """A quad light of area 1e4 (100 m x 100 m, 50 m up), a quad light and an emissive triangle of area 1e-8
    close to the floor; analytic reference."""
    w, h = (64, 48) if full else (16, 12)
    tv = np.array([[0.0, 0.0, 0.0], [1e-4, 0.0, 0.0], [0.0, 2e-4, 0.0]]) + (0.8, -0.4, 0.3)
    materials = _grey() + [Material("speck", (0, 0, 0), (0.6, 0.8, 1.0), 3e6)]
    lights = [
        Light("huge", "area", (1.0, 0.95, 0.9), 2.4e4, translation(0, 0, 50.0), size=100.0),
        Light("tiny", "area", (1.0, 0.7, 0.4), 0.05, translation(-0.8, 0.5, 0.4), size=1e-4),
    ]
    cam = _cam((0.0, -3.5, 2.5), (0.0, 0.0, 0.0), w, h)
    scene = Scene([_floor(6.0), Mesh("speck", tv, [[0, 1, 2]], 1)], materials, lights, cam, name="area_extremes")
    return Case("area_extremes", "lights of area 1e4 and 1e-8", scene, runs=24 if full else 16,
                frames=64 if full else 16)


def touching(full: bool) -> Case:
    """Shading points touching lights: a rectangle light standing on the floor, a sphere light and a soft-falloff
    point light resting on it, a point light 1e-4 above it; analytic reference."""
    w, h = (64, 48) if full else (16, 12)
    lights = [
        _standing((-0.6, 0.4, 0.15), (0.3, -1.0, 0.0), 0.5, 0.3, 20.0, "standing", (1.0, 0.8, 0.6)),
        Light("resting_sphere", "point", (0.6, 0.8, 1.0), 30.0, translation(0.7, 0.3, 0.2), radius=0.2,
              soft_falloff=False),
        Light("resting_soft", "point", (0.8, 1.0, 0.6), 30.0, translation(-0.3, -0.6, 0.15), radius=0.15),
        Light("skimming", "point", (1.0, 1.0, 1.0), 0.5, translation(0.5, -0.7, 1e-4)),
    ]
    cam = _cam((0.0, -2.6, 1.8), (0.0, 0.0, 0.0), w, h)
    return Case("touching", "d -> 0: lights resting on the floor", Scene([_floor(4.0)], _grey(), lights, cam,
                name="touching"), runs=24 if full else 16, frames=64 if full else 16)


def grazing(full: bool) -> Case:
    """Light at grazing angles (cos -> 0): a delta sun 0.001 rad above the horizon, a 0.01 rad sun 0.006 rad above
    it, a point light 1e-3 above the floor, a spot shining along the floor, a rectangle light standing at the
    far edge; a camera 0.15 above the floor; analytic reference."""
    w, h = (64, 48) if full else (16, 12)

    def sun_at(elev: float, azim: float) -> np.ndarray:
        d = np.array([math.cos(elev) * math.cos(azim), math.cos(elev) * math.sin(azim), math.sin(elev)])
        return look_at(d, (0, 0, 0))

    lights = [
        Light("sun_delta", "sun", (1.0, 0.9, 0.8), 200.0, sun_at(1e-3, 0.3)),
        Light("sun_disk", "sun", (0.8, 0.9, 1.0), 50.0, sun_at(6e-3, 2.0), angle=0.01),
        Light("skimming", "point", (1.0, 1.0, 1.0), 40.0, translation(-2.5, 2.5, 1e-3)),
        Light("spot_along", "spot", (1.0, 0.6, 0.6), 60.0, look_at((2.5, -2.0, 0.05), (0.0, 2.0, 0.05)),
              spot_size=1.2, spot_blend=0.3),
        _standing((0.0, 3.2, 0.2), (0.0, -1.0, 0.0), 3.0, 0.4, 30.0, "far_wall_light"),
    ]
    cam = _cam((0.0, -3.0, 0.15), (0.0, 1.5, 0.0), w, h, lens=24.0)
    return Case("grazing", "cos -> 0: suns at the horizon, lights skimming the floor",
                Scene([_floor(6.0)], _grey(), lights, cam, name="grazing"), runs=24 if full else 16,
                frames=64 if full else 16)


OFFSET = np.array([1e5, -1e5, 1e5])


def offset(full: bool) -> Case:
    """A floor lit by point, spot, quad and sun lights, the whole scene (camera included) moved by (1e5, -1e5,
    1e5): a fixed ray epsilon would shadow the floor by itself. Analytic reference at the G-buffer points."""
    w, h = (64, 48) if full else (16, 12)
    o = OFFSET
    lights = [
        Light("point", "point", (1.0, 0.9, 0.8), 60.0, translation(*(o + (0.5, 0.25, 1.5)))),
        Light("spot", "spot", (0.7, 0.8, 1.0), 80.0, look_at(o + (-1.0, -0.5, 2.0), o + (-0.5, 0.0, 0.0)),
              spot_size=1.0, spot_blend=0.25),
        Light("quad", "area", (1.0, 0.8, 0.6), 40.0, translation(*(o + (-0.75, 0.5, 1.25))), size=0.5),
        Light("sun", "sun", (1.0, 1.0, 0.9), 1.5, look_at((0.3, -0.5, 1.0), (0, 0, 0)), angle=0.02),
    ]
    fv, ft = quad(4.0, 4.0)
    cam = _cam(o + (0.0, -3.0, 2.25), o + (0.0, 0.0, 0.0), w, h)
    return Case("offset_1e5", "whole scene offset by 1e5", Scene([Mesh("floor", fv + o, ft, 0)], _grey(), lights,
                cam, name="offset_1e5"), runs=24 if full else 16, frames=64 if full else 16)


def degenerate(full: bool) -> Case:
    """Degenerate triangles (repeated vertices, collinear, zero in float32 only), slivers of aspect 1e7 as
    occluders and as emitters, a light with zero power and a rectangle light 1e-6 wide; exhaustive reference."""
    w, h = (64, 48) if full else (16, 12)
    materials = _grey() + [Material("glow", (0, 0, 0), (1.0, 0.8, 0.5), 50.0)]
    rng = np.random.default_rng(2)
    tris = []
    for _ in range(40):
        c = np.array([*rng.uniform(-1.5, 1.5, 2), rng.uniform(0.2, 1.2)])
        kind = rng.integers(0, 4)
        if kind == 0:  # repeated vertex
            tris.append([c, c, c + rng.normal(size=3) * 0.3])
        elif kind == 1:  # collinear
            d = rng.normal(size=3) * 0.3
            tris.append([c, c + d, c + 2.5 * d])
        elif kind == 2:  # a triangle that vanishes in float32 only
            d = rng.normal(size=3) * 0.3
            tris.append([c, c + d, c + 2 * d + 1e-9])
        else:  # sliver of aspect 1e7, standing
            a = rng.uniform(0, math.pi)
            d = np.array([math.cos(a), math.sin(a), 0.0]) * 0.6
            tris.append([c, c + d, c + 0.5 * d + (0, 0, 6e-8)])
    tris = np.array(tris)
    slivers = []
    for k in range(6):  # emissive slivers, lying and standing
        c = np.array([-1.2 + 0.5 * k, 0.8, 0.6 + 0.1 * k])
        d = np.array([0.4, 0.1 * k, 0.0])
        e = np.array([0.0, 0.0, 4e-8]) if k % 2 else np.array([-4e-8 * d[1], 4e-8 * d[0], 0.0])
        slivers.append([c, c + d, c + 0.5 * d + e])
    slivers.append([np.array([0.5, 1.2, 0.5])] * 2 + [np.array([0.9, 1.2, 0.5])])  # emissive, zero area
    slivers = np.array(slivers)
    lights = [
        Light("quad", "area", (1.0, 0.9, 0.8), 30.0, translation(-0.5, -0.3, 1.8), size=0.6),
        Light("point", "point", (0.7, 0.8, 1.0), 40.0, translation(0.8, -0.6, 1.4), radius=0.05),
        Light("dark", "point", (1.0, 1.0, 1.0), 0.0, translation(0.0, 0.0, 1.0)),
        Light("thread", "area", (1.0, 0.6, 0.6), 5.0, translation(0.2, 0.9, 1.0), shape="RECTANGLE", size=1.0,
              size_y=1e-6),
    ]
    meshes = [
        _floor(4.0),
        Mesh("debris", tris.reshape(-1, 3), np.arange(3 * len(tris)).reshape(-1, 3), 0),
        Mesh("slivers", slivers.reshape(-1, 3), np.arange(3 * len(slivers)).reshape(-1, 3), 1),
    ]
    cam = _cam((0.0, -3.0, 2.2), (0.0, 0.2, 0.3), w, h)
    return Case("degenerate", "degenerate and sliver triangles, zero-power and 1e-6-wide lights",
                Scene(meshes, materials, lights, cam, name="degenerate"), reference="exhaustive",
                runs=24 if full else 16, frames=64 if full else 16, ref_batches=32 if full else 16,
                ref_frames=64 if full else 32)


def all_behind(full: bool) -> Case:
    """Every light is behind the lit surface (w_sum = 0 everywhere): the image must be exactly 0."""
    w, h = (64, 48) if full else (16, 12)
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    lights = [
        Light("below", "point", (1, 1, 1), 500.0, translation(0, 0, -0.5)),
        Light("below_sphere", "point", (1, 1, 1), 500.0, translation(0.5, 0.5, -0.4), radius=0.2,
              soft_falloff=False),
        Light("below_soft", "point", (1, 1, 1), 500.0, translation(-0.5, 0.5, -0.4), radius=0.2),
        Light("facing_down_below", "area", (1, 1, 1), 500.0, translation(0.3, 0.2, -0.3), size=1.0),
        Light("facing_up_above", "area", (1, 1, 1), 500.0, translation(-0.3, 0.2, 1.0) @ flip, size=1.0),
        Light("disk_facing_up", "area", (1, 1, 1), 500.0, translation(0.6, -0.4, 1.2) @ flip, shape="DISK",
              size=0.6),
        Light("spot_up", "spot", (1, 1, 1), 500.0, look_at((0.0, 0.0, 0.5), (0.0, 0.0, 3.0)), spot_size=0.8),
        Light("sun_below", "sun", (1, 1, 1), 3.0, look_at((0.2, 0.1, -1.0), (0, 0, 0)), angle=0.1),
    ]
    tv = np.array([[0.0, 0.0, -0.2], [0.5, 0.0, -0.2], [0.0, 0.5, -0.2]])
    materials = _grey() + [Material("under", (0, 0, 0), (1, 1, 1), 100.0)]
    cam = _cam((0.0, -3.0, 2.0), (0.0, 0.0, 0.0), w, h)
    scene = Scene([_floor(4.0), Mesh("under", tv, [[0, 1, 2]], 1)], materials, lights, cam, name="all_behind")
    return Case("all_behind", "every light behind the surface: w_sum = 0", scene, reference="zero", runs=4,
                frames=8)


def _two_places(w: int, h: int, cuts: tuple[int, ...]) -> Scene:
    """Place A at the origin and place B 1000 m along x, each a floor with its own lights; the camera looks at A
    (towards -x) in frame 0 and at B (towards +x) in frame 1."""
    far = np.array([1000.0, 0.0, 0.0])
    fv, ft = quad(4.0, 4.0)
    lights = [
        Light("a_point", "point", (1.0, 0.8, 0.6), 80.0, translation(0.3, 0.4, 1.2), radius=0.1),
        Light("a_quad", "area", (0.6, 0.8, 1.0), 40.0, translation(-0.6, -0.4, 1.5), size=0.5),
        Light("b_point", "point", (0.8, 1.0, 0.7), 60.0, translation(*(far + (-0.4, 0.5, 1.0)))),
        Light("b_quad", "area", (1.0, 0.7, 0.7), 50.0, translation(*(far + (0.5, -0.3, 1.3))), size=0.6),
        Light("b_soft", "point", (0.7, 0.7, 1.0), 30.0, translation(*(far + (0.2, 0.6, 0.5))), radius=0.2),
    ]
    cam = Camera(np.stack([look_at((1.8, 0.0, 2.0), (0.0, 0.0, 0.0)), look_at(far + (-1.8, 0.0, 2.0), far)]), w, h,
                 lens=24.0, cuts=cuts)
    return Scene([Mesh("floor_a", fv, ft, 0), Mesh("floor_b", fv + far, ft, 0)], _grey(), lights, cam,
                 name="two_places")


def teleport_cut(full: bool) -> Case:
    """The camera jumps 1000 m with a cut marker: no temporal reuse, TAA restarts; analytic reference."""
    w, h = (64, 48) if full else (16, 12)
    return Case("teleport_cut", "camera jumps 1000 m, cut marked", _two_places(w, h, (1,)), kind="sequence",
                runs=128 if full else 48, before=(0,) * (8 if full else 2), eval_frame=1, cut_expected=True,
                no_ghost=True)


def teleport(full: bool) -> Case:
    """The camera jumps 1000 m without a cut marker: reprojection must reject every history sample."""
    w, h = (64, 48) if full else (16, 12)
    return Case("teleport", "camera jumps 1000 m, no cut marker", _two_places(w, h, ()), kind="sequence",
                runs=128 if full else 48, before=(0,) * (8 if full else 2), eval_frame=1, no_ghost=True)


def switch_off(full: bool) -> Case:
    """The dominant light (1000 W) switches off in frame 1, every light in frame 2: frame 1 must be an unbiased
    image of the others, frame 2 exactly 0. Analytic reference."""
    w, h = (64, 48) if full else (16, 12)
    lights = [
        Light("dominant", "point", (1.0, 1.0, 1.0), 1000.0, translation(0.4, 0.2, 1.5), radius=0.1,
              power_per_frame=np.array([1.0, 0.0, 0.0])),
        Light("quad", "area", (1.0, 0.8, 0.6), 30.0, translation(-0.8, 0.3, 1.2), size=0.5,
              power_per_frame=np.array([1.0, 1.0, 0.0])),
        Light("soft", "point", (0.6, 0.8, 1.0), 20.0, translation(0.6, -0.7, 0.8), radius=0.1,
              power_per_frame=np.array([1.0, 1.0, 0.0])),
    ]
    cam = _cam((0.0, -3.0, 2.5), (0.0, 0.0, 0.0), w, h, frames=3)
    scene = Scene([_floor(4.0)], _grey(), lights, cam, name="switch_off", frame_count=3)
    return Case("switch_off", "dominant light off in frame 1, all off in frame 2", scene, kind="sequence",
                runs=128 if full else 48, before=(0,) * (8 if full else 2), eval_frame=1, zero_after=(2,))


def long_animation(full: bool) -> Case:
    """An animation of a still camera, 5000 (small: 700) frames with TAA and ReSTIR at their default caps: M and
    the TAA history length must stay capped and the time average must match the analytic reference."""
    w, h = (32, 24) if full else (16, 12)
    frames = 5000 if full else 700
    lights = [
        Light("point", "point", (1.0, 0.9, 0.7), 60.0, translation(0.5, 0.3, 1.4), radius=0.1),
        Light("quad", "area", (0.7, 0.8, 1.0), 40.0, translation(-0.7, -0.2, 1.2), size=0.5),
        Light("sun", "sun", (1.0, 1.0, 0.9), 1.0, look_at((0.3, -0.5, 1.0), (0, 0, 0)), angle=0.02),
    ]
    cam = _cam((0.0, -3.0, 2.2), (0.0, 0.0, 0.0), w, h, frames=frames)
    scene = Scene([_floor(4.0)], _grey(), lights, cam, name="long_animation", frame_count=frames)
    return Case("long_animation", f"{frames} frames, still camera, TAA + ReSTIR", scene, kind="long",
                frames=frames, settings=dict(jitter=False, taa=True, m_cap=Settings().m_cap))


CASES: dict[str, Callable[[bool], Case]] = {
    f.__name__ if f.__name__ != "offset" else "offset_1e5": f
    for f in (power_span, million_lights, area_extremes, touching, grazing, offset, degenerate, all_behind,
              teleport_cut, teleport, switch_off, long_animation)
}


def cases(full: bool = False, names: list[str] | None = None) -> list[Case]:
    chosen = names or list(CASES)
    unknown = [n for n in chosen if n not in CASES]
    if unknown:
        raise ValueError(f"unknown stress cases {unknown}; cases: {', '.join(CASES)}")
    return [CASES[n](full) for n in chosen]


# ---- analytic direct light ------------------------------------------------------------------------------


class NotAnalytic(ValueError):
    """The analytic reference does not cover this light (a disk light, or a light across a point's horizon)."""


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _polygon_psa(x: np.ndarray, n: np.ndarray, verts: np.ndarray, one_sided: np.ndarray) -> np.ndarray:
    """Projected solid angle (integral of cos over the solid angle) of polygons verts (T, V, 3) seen from points
    x (P, 3) with normals n (P, 3), by Lambert's formula: 1/2 |sum_i theta_i n . unit(g_i x g_i+1)|, (P, T). Each
    polygon must lie on one side of each point's horizon. A one-sided polygon emits along its winding's normal."""
    nv = verts.shape[1]
    nx, ny, nz = (n[:, k : k + 1] for k in range(3))
    g, above, below = [], None, None
    for i in range(nv):  # unit vectors from the points to vertex i, as three (P, T) arrays
        gx, gy, gz = (verts[None, :, i, k] - x[:, k : k + 1] for k in range(3))
        dist = np.sqrt(gx * gx + gy * gy + gz * gz)
        height = gx * nx + gy * ny + gz * nz
        tol = 1e-5 * dist  # float32 positions: a vertex on the horizon may land this far on either side
        a, b = height >= -tol, height <= tol
        above = a if above is None else above & a
        below = b if below is None else below & b
        g.append((gx / dist, gy / dist, gz / dist))
    if np.any(~above & ~below):
        raise NotAnalytic("a polygon light crosses the horizon of a shading point")
    total = np.zeros(above.shape)
    for i in range(nv):
        (ax, ay, az), (bx, by, bz) = g[i], g[(i + 1) % nv]
        cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
        sn = np.sqrt(cx * cx + cy * cy + cz * cz)
        theta = np.arctan2(sn, ax * bx + ay * by + az * bz)
        ok = sn > 0
        total += np.where(ok, theta * (cx * nx + cy * ny + cz * nz) / np.where(ok, sn, 1.0), 0.0)
    psa = 0.5 * np.abs(total)
    psa[~above] = 0.0
    # one-sided emitters: nothing reaches a point behind the emitting side
    nl = np.cross(verts[:, 1] - verts[:, 0], verts[:, 2] - verts[:, 0])  # (T, 3)
    side = sum((x[:, k : k + 1] - verts[None, :, 0, k]) * nl[None, :, k] for k in range(3))
    psa[one_sided[None, :] & ~(side > 0)] = 0.0
    return psa


def _spot_mask(rec: np.ndarray, x: np.ndarray) -> np.ndarray:
    """opencl/lights.h spot_mask for spot records (S, 16) at points x (P, 3): (P, S)."""
    out = x[:, None, :] - rec[None, :, 0:3]
    out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    c = np.einsum("psk,sk->ps", out, rec[:, 4:7])
    cos_half, smooth = rec[:, 8][None], rec[:, 9][None]
    t = np.clip((c - cos_half) / np.where(smooth > 0, smooth, 1.0), 0.0, 1.0)
    m = np.where(smooth > 0, t * t * (3 - 2 * t), 1.0)
    return np.where(c > cos_half, m, 0.0)


def analytic_direct(pos: np.ndarray, normal: np.ndarray, records: np.ndarray, block: int = 1_000_000) -> np.ndarray:
    """Unshadowed direct irradiance-weighted radiance sum_l Le_l * (projected solid angle or cos/d^2) at points
    pos (P, 3) with unit normals (P, 3), for the device light records (N,) layouts.LIGHT, in float64: multiply
    by albedo / pi for the reflected radiance. Raises NotAnalytic for what it does not cover."""
    x = np.asarray(pos, np.float64)
    n = np.asarray(normal, np.float64)
    r = records.view(np.float32).reshape(-1, 16).astype(np.float64)
    kinds = records.view(np.float32).reshape(-1, 16)[:, 3].view(np.int32)
    flags = records.view(np.float32).reshape(-1, 16)[:, 15].view(np.int32)
    le = r[:, 12:15]
    out = np.zeros((len(x), 3))
    if np.any(kinds == L.LIGHT_DISK):
        raise NotAnalytic("disk lights have no analytic reference here")

    def blocks(count: int, per: int):
        step = max(1, block // max(per, 1))
        for s in range(0, count, step):
            yield slice(s, min(s + step, count))

    # points and spots (radius 0): I cos / d^2 (times the spot mask)
    sel = np.nonzero(np.isin(kinds, (L.LIGHT_SPHERE, L.LIGHT_SPOT)))[0]
    for sl in blocks(len(sel), len(x)):
        rec = r[sel[sl]]
        d = rec[None, :, 0:3] - x[:, None, :]  # (P, S, 3)
        dc = np.linalg.norm(d, axis=-1)
        w = d / dc[..., None]
        cos = np.einsum("psk,pk->ps", w, n)
        rad = rec[:, 7][None]
        mask = np.ones_like(cos)
        spots = kinds[sel[sl]] == L.LIGHT_SPOT
        if spots.any():
            mask[:, spots] = _spot_mask(rec[spots], x)
        soft = (flags[sel[sl]] & L.LIGHT_FLAG_SOFT_FALLOFF) != 0
        # a sphere (hard) of radius r: pi (r / D)^2 cos; a disk of radius r facing the point (soft falloff):
        # pi r^2 / (D^2 + r^2) cos; both exact when the emitter is wholly above or below the horizon
        sin_a = np.where(soft[None], rad / np.sqrt(dc * dc + rad * rad), rad / dc)
        if np.any((rad > 0) & (dc <= rad)):
            raise NotAnalytic("a shading point inside a sphere light")
        tol = 1e-6
        straddle = (rad > 0) & (np.abs(cos) < sin_a * (1 - tol))
        if np.any(straddle):
            raise NotAnalytic("a sphere light crosses the horizon of a shading point")
        geo = np.where(rad > 0, math.pi * sin_a**2 * cos, cos / (dc * dc))
        geo = np.where(cos > 0, geo * mask, 0.0)
        out += geo @ rec[:, 12:15]
    # suns: radiance Le over a cap of 1 - cos = omc around the direction: Le pi sin^2 cos, or Le cos for a delta
    for k in np.nonzero(kinds == L.LIGHT_SUN)[0]:
        wdir = r[k, 4:7]
        omc = r[k, 9]
        cos = n @ wdir
        if omc > 0:
            sin_h = math.sqrt(omc * (2 - omc))
            if np.any(np.abs(cos) < sin_h * (1 - 1e-6)):
                raise NotAnalytic("a sun crosses the horizon of a shading point")
            geo = math.pi * sin_h * sin_h * cos
        else:
            geo = cos
        out += np.where(cos > 0, geo, 0.0)[:, None] * le[k][None]
    # quads and triangles: Lambert's polygon formula
    for kind, nv in ((L.LIGHT_QUAD, 4), (L.LIGHT_TRIANGLE, 3)):
        sel = np.nonzero(kinds == kind)[0]
        if not len(sel):
            continue
        p, a, b = r[sel, 0:3], r[sel, 4:7], r[sel, 8:11]
        if nv == 4:  # light_point: p + u a + v b, emitting along cross(a, b)
            verts = np.stack([p, p + a, p + a + b, p + b], axis=1)
        else:
            verts = np.stack([p, p + a, p + b], axis=1)
        one_sided = (flags[sel] & L.LIGHT_FLAG_TWO_SIDED) == 0
        t_step = max(1, block // 8)  # polygons per block, then as many points as fit in `block` pairs
        for t0 in range(0, len(sel), t_step):
            tl = slice(t0, min(t0 + t_step, len(sel)))
            p_step = max(1, block // (tl.stop - tl.start))
            for p0 in range(0, len(x), p_step):
                ps = slice(p0, min(p0 + p_step, len(x)))
                out[ps] += _polygon_psa(x[ps], n[ps], verts[tl], one_sided[tl]) @ le[sel[tl]]
    return out


# ---- running a case -----------------------------------------------------------------------------------


@dataclass
class Result:
    case: str
    method: str
    nonfinite: int  # guard counts + NaN/Inf found in returned arrays
    max_value: float
    rel_mse: float
    expected_rel_mse: float  # what the measured variances alone predict
    outliers: int  # pixels beyond Z standard errors
    allowed: int
    z_image: float  # image mean against the reference, in standard errors
    rel_bias: float  # image mean / reference image mean - 1
    passed: bool
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0
    samples: int = 0  # frames rendered for the statistics

    def row(self) -> list[str]:
        def g(v: float) -> str:
            return "-" if not math.isfinite(v) else f"{v:.3g}"

        return [self.case, self.method, str(self.nonfinite), g(self.max_value), g(self.rel_mse),
                g(self.expected_rel_mse), f"{self.outliers}/{self.allowed}", g(self.z_image), g(self.rel_bias),
                "pass" if self.passed else "FAIL", f"{self.seconds:.1f}", "; ".join(self.notes)]


HEADER = ["case", "method", "NaN/Inf", "max", "relMSE", "expected", "z>4 px", "z image", "bias", "result", "s",
          "notes"]


def _nonfinite(frame: Frame) -> int:
    """NaN/Inf in what the renderer returned (depth is +inf where a camera ray missed: only NaN counts there)."""
    bad = sum(int((~np.isfinite(a)).sum()) for a in (frame.color, frame.noisy, frame.normal, frame.vector,
                                                     frame.albedo))
    return bad + int(np.isnan(frame.depth).sum())


def _gbuffer(r: Renderer) -> np.ndarray:
    """The G-buffer of the frame the renderer rendered last."""
    return r._read_gbuffer(r.gbuf[1 - r._cur])


def _reservoir_m(r: Renderer) -> np.ndarray:
    """M of the reservoirs the last frame left as history."""
    res = np.empty(r.pixels, L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, res, r.res_history[1 - r._cur])
    return res["M"]


def _lum(x: np.ndarray) -> np.ndarray:
    return x @ LUMINANCE


def _allowed_outliers(n: int, dof: int, z: float = Z) -> int:
    """How many of n independent t statistics (dof degrees of freedom) may exceed z: the expected count plus four
    of its binomial standard deviations, plus one (as tests/helpers.py)."""
    from scipy import stats

    p = 2 * stats.t.sf(z, dof)
    return int(math.ceil(n * p + 4 * math.sqrt(n * p * (1 - p)) + 1))


@dataclass
class Reference:
    mean: np.ndarray  # (H, W, 3)
    se: np.ndarray  # (H, W, 3) standard error of the mean (0: exact)
    lum_se: np.ndarray  # (H, W)
    image_se: float  # standard error of the image mean luminance
    terms: int  # light count: the float32 sums behind an exact pixel have this many terms
    seconds: float = 0.0


def _settings(case: Case, method: str, seed: int) -> Settings:
    base = dict(STILL_SETTINGS)
    base.update(METHODS[method])
    base.update(case.settings)
    base["seed"] = seed
    return Settings(**base)


def _deterministic(lights) -> bool:
    """Only delta lights (points and spots of radius 0, suns of angle 0): the exhaustive reference is exact."""
    rec = lights.records.view(np.float32).reshape(-1, 16)
    kinds = rec[:, 3].view(np.int32)
    point = np.isin(kinds, (L.LIGHT_SPHERE, L.LIGHT_SPOT)) & (rec[:, 7] == 0)
    sun = (kinds == L.LIGHT_SUN) & (rec[:, 9] == 0)
    return bool(np.all(point | sun))


def compute_reference(case: Case, device=None, frame: int | None = None, seed: int = 0) -> Reference:
    """The case's reference image at its evaluation frame (a still camera there)."""
    t0 = time.perf_counter()
    frame = case.eval_frame if frame is None else frame
    scene = case.scene
    if case.reference == "exhaustive":
        r = Renderer(scene, Settings(method="reference", jitter=False, taa=False, seed=9001 + 100_000 * seed), device)
        lights = scene_lights(scene, frame)
        batches, frames = (1, 1) if _deterministic(lights) else (case.ref_batches, case.ref_frames)
        means = []
        for b in range(batches):
            r.settings.seed = 9001 + 100_000 * seed + b
            means.append(r.render_still(frame, frames).color[..., :3].astype(np.float64))
        m = np.stack(means)
        if batches > 1:
            se = m.std(axis=0, ddof=1) / math.sqrt(batches)
            lum_se = _lum(m).std(axis=0, ddof=1) / math.sqrt(batches)
            image_se = float(_lum(m).mean(axis=(1, 2)).std(ddof=1) / math.sqrt(batches))
        else:
            se = np.zeros_like(m[0])
            lum_se = np.zeros(m.shape[1:3])
            image_se = 0.0
        return Reference(m.mean(axis=0), se, lum_se, image_se, len(lights), time.perf_counter() - t0)
    cam = scene.camera
    assert cam is not None
    shape = (cam.height, cam.width)
    if case.reference == "zero":
        z = np.zeros((*shape, 3))
        return Reference(z, z.copy(), np.zeros(shape), 0.0, 1, time.perf_counter() - t0)
    # analytic, at the G-buffer points of the frame under test (jitter off: the same in every run)
    r = Renderer(scene, Settings(method="light_array", jitter=False, taa=False), device)
    r.render_frame(frame, still=True)
    g = _gbuffer(r).reshape(-1)
    hit = g["normal"][:, 3].view(np.int32) >= 0
    lights = scene_lights(scene, frame)
    e = analytic_direct(g["pos"][hit, :3], g["normal"][hit, :3], lights.records)
    img = g["emission"][:, :3].astype(np.float64)
    img[hit] += g["albedo"][hit, :3] / math.pi * e
    z = np.zeros((*shape, 3))
    return Reference(img.reshape(*shape, 3), z, np.zeros(shape), 0.0, max(len(lights), 1), time.perf_counter() - t0)


def _judge(case: Case, method: str, values: np.ndarray, ref: Reference, nonfinite: int, max_value: float,
           seconds: float, samples: int, notes: list[str], dof: int | None = None) -> Result:
    """values: (runs or batches, H, W, 3) independent estimates of the reference."""
    k = values.shape[0]
    dof = k - 1 if dof is None else dof
    mean = values.mean(axis=0)
    se = values.std(axis=0, ddof=1) / math.sqrt(k)
    rel = float(np.mean((mean - ref.mean) ** 2 / (ref.mean**2 + 0.01)))
    expected = float(np.mean((se**2 + ref.se**2) / (ref.mean**2 + 0.01)))
    lum = _lum(values)
    lm = lum.mean(axis=0)
    lse = lum.std(axis=0, ddof=1) / math.sqrt(k)
    lref = _lum(ref.mean)
    sigma = np.sqrt(lse**2 + ref.lum_se**2)
    # exact pixels: both sides have no spread beyond rounding (identical float32 values give a standard deviation
    # of 1e-17 in float64, not 0); they must agree to the rounding of float32 sums of `terms` terms
    scale = np.maximum(np.abs(lref), np.abs(lm))
    live = sigma > 16 * F32_EPS * scale + 1e-30
    z = np.abs(lm - lref)[live] / sigma[live]
    outliers = int((z > Z).sum())
    allowed = _allowed_outliers(int(live.sum()), dof)
    exact = ~live
    tol = (16 + ref.terms) * F32_EPS * scale[exact] + 1e-30
    bad_exact = int((np.abs(lm - lref)[exact] > tol).sum())
    img = lum.mean(axis=(1, 2))
    img_se = math.hypot(float(img.std(ddof=1)) / math.sqrt(k), ref.image_se)
    ref_img = float(lref.mean())
    diff = float(img.mean()) - ref_img
    z_img = abs(diff) / img_se if img_se > 0 else (0.0 if abs(diff) <= 1e-6 * abs(ref_img) + 1e-30 else math.inf)
    rel_bias = diff / ref_img if ref_img != 0 else (0.0 if diff == 0 else math.inf)
    passed = nonfinite == 0
    if nonfinite:
        notes.append(f"{nonfinite} NaN/Inf")
    if case.reference == "zero":
        ok = bool(np.all(values == 0.0))
        if not ok:
            notes.append("image not exactly 0")
        passed &= ok
    elif METHODS[method].get("bias_correction") == "none":
        # biased mode: no brighter than the reference beyond noise, darker by at most BIASED_DARKENING
        rb_se = img_se / abs(ref_img) if ref_img else 0.0
        ok = -BIASED_DARKENING - Z * rb_se <= rel_bias <= Z * rb_se
        if not ok:
            notes.append(f"biased mode off by {rel_bias:+.3f} (+-{rb_se:.3f})")
        passed &= ok
    else:
        if outliers > allowed:
            notes.append(f"{outliers} pixels beyond {Z:g} se (allowed {allowed})")
        if bad_exact:
            notes.append(f"{bad_exact} exact pixels differ")
        if z_img > Z:
            notes.append(f"image mean {z_img:.1f} se off ({rel_bias:+.2e})")
        passed &= outliers <= allowed and bad_exact == 0 and z_img <= Z
    return Result(case.name, method, nonfinite, max_value, rel, expected, outliers, allowed, z_img, rel_bias,
                  passed, notes, seconds, samples)


def run_method(case: Case, method: str, ref: Reference, device=None, seed: int = 0) -> Result:
    t0 = time.perf_counter()
    notes: list[str] = []
    nonfinite = 0
    max_value = 0.0
    samples = 0
    seed0 = 1000 * (list(METHODS).index(method) + 1) + 100_000 * seed
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # degenerate triangles are dropped with a warning: expected here
        r = Renderer(case.scene, _settings(case, method, seed0), device)

    def seen(f: Frame) -> None:
        nonlocal nonfinite, max_value
        nonfinite += _nonfinite(f)
        max_value = max(max_value, float(np.nanmax(f.color[..., :3])), float(np.nanmax(f.noisy)))

    values = []
    dof = None
    if case.kind == "still":
        for k in range(case.runs):
            r.reset()
            r.settings.seed = seed0 + k
            f = r.render_still(case.eval_frame, case.frames * FRAMES_FACTOR.get(method, 1))
            seen(f)
            values.append(f.color[..., :3].astype(np.float64))
            samples += f.samples
    elif case.kind == "sequence":
        for k in range(case.runs):
            r.reset()
            r.settings.seed = seed0 + k
            for fr in case.before:
                seen(r.render_frame(fr))
            f = r.render_frame(case.eval_frame)
            seen(f)
            if case.cut_expected and "temporal" in f.stage_ms:
                notes.append("temporal reuse across a cut")
            value = f.noisy.astype(np.float64)
            # a method without history gives independent samples of the frame under test: average a few
            repeats = 1 if r.settings.method == "restir" else case.eval_repeats
            for _ in range(repeats - 1):
                f = r.render_frame(case.eval_frame)
                seen(f)
                value += f.noisy
            values.append(value / repeats)
            samples += len(case.before) + repeats
            for fr in case.zero_after:
                fz = r.render_frame(fr)
                seen(fz)
                if not (np.all(fz.noisy == 0) and np.all(fz.color[..., :3] == 0)):
                    notes.append(f"frame {fr} not exactly 0")
        if case.no_ghost:  # with TAA: the frame under test must be its own sample everywhere
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                rt = Renderer(case.scene, Settings(**{**r.settings.__dict__, "taa": True}), device)
            for fr in case.before:
                seen(rt.render_frame(fr))
            f = rt.render_frame(case.eval_frame)
            seen(f)
            if not np.array_equal(f.color[..., :3], f.noisy):
                notes.append(f"TAA kept history after the jump ({int((f.color[..., :3] != f.noisy).any(-1).sum())}"
                             " px)")
            nonfinite += sum(rt.guard_totals.values())
    else:  # long
        b = case.long_batch
        n_batches = (case.frames - case.long_warmup) // b
        start = case.frames - n_batches * b
        m_bound = _m_bound(r.settings)
        acc = np.zeros((r.height, r.width, 3))
        max_m = 0.0
        max_n = 0.0
        for fr in range(case.frames):
            f = r.render_frame(fr)
            seen(f)
            samples += 1
            if fr >= start:
                acc += f.color[..., :3]
                if (fr - start + 1) % b == 0:
                    values.append(acc / b)
                    acc = np.zeros_like(acc)
            if fr % 50 == 49 or fr == case.frames - 1:
                if r.settings.method == "restir":
                    max_m = max(max_m, float(_reservoir_m(r).max()))
                max_n = max(max_n, float(r.history_length().max()))
        if max_m > m_bound:
            notes.append(f"ReSTIR M reached {max_m:g} > bound {m_bound:g}")
        if max_n > r.settings.max_history:
            notes.append(f"TAA history length reached {max_n:g} > {r.settings.max_history}")
        if case.frames > r.settings.max_history and max_n < r.settings.max_history:
            notes.append(f"TAA history length only reached {max_n:g}")
        if r.settings.method == "restir":
            notes.append(f"max M {max_m:g} (bound {m_bound:g})")
        notes.append(f"max TAA n {max_n:g}")
    nonfinite += sum(r.guard_totals.values())
    res = _judge(case, method, np.stack(values), ref, nonfinite, max_value, time.perf_counter() - t0, samples,
                 notes, dof)
    bad = [n for n in notes if not n.startswith("max ")]
    if bad and res.passed:
        res.passed = False
    return res


def _m_bound(s: Settings) -> float:
    """The largest M a stored reservoir can have: the temporal pass caps last frame's M at m_cap * candidates
    and adds this frame's candidates; each spatial pass adds at most `spatial_neighbours` such reservoirs."""
    m = s.candidates + s.m_cap * s.candidates if s.temporal else s.candidates
    if s.spatial:
        m *= (1 + s.spatial_neighbours) ** s.spatial_passes
    return float(m)


def run(full: bool = False, methods: list[str] | None = None, names: list[str] | None = None, device=None,
        log: Callable[[str], None] | None = None, seed: int = 0) -> list[Result]:
    """Every case with every method. `seed` shifts every random seed (the tests use 0; other values give
    independent repetitions, to see how often a correct renderer fails a 4-standard-error test)."""
    methods = methods or list(METHODS)
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise ValueError(f"unknown methods {unknown}; methods: {', '.join(METHODS)}")
    results = []
    for case in cases(full, names):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ref = compute_reference(case, device, seed=seed)
        if log:
            log(f"{case.name}: {case.description}; {case.reference} reference ({ref.seconds:.1f} s)")
        for m in methods:
            res = run_method(case, m, ref, device, seed)
            results.append(res)
            if log:
                log("  " + " | ".join(res.row()))
    return results


def format_table(results: list[Result]) -> str:
    rows = [HEADER] + [r.row() for r in results]
    widths = [max(len(row[i]) for row in rows) for i in range(len(HEADER) - 1)]
    lines = []
    for k, row in enumerate(rows):
        lines.append("  ".join(c.ljust(w) for c, w in zip(row[:-1], widths, strict=True)) + "  " + row[-1])
        if k == 0:
            lines.append("-" * (sum(widths) + 2 * len(widths) + 5))
    return "\n".join(lines)


def write(results: list[Result], out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / "stress.csv", out / "stress.json"]
    with open(paths[0], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(HEADER)
        w.writerows(r.row() for r in results)
    paths[1].write_text(json.dumps([asdict(r) for r in results], indent=1, default=float))
    return paths


# ---- specialised against general builds -------------------------------------------------------------------

_BENCH_CHILD = r"""
import json, sys, time
import restircl.pipeline as P
from restircl import Renderer, Settings
from restircl.eval.stress import bench_scene
name, specialise, frames, still = sys.argv[1], sys.argv[2] == "1", int(sys.argv[3]), sys.argv[4] == "1"
build_cpu = {}
_build = P.build_program
def timed_build(*args, **kw):
    c0 = time.process_time()
    prog = _build(*args, **kw)
    build_cpu["s"] = time.process_time() - c0
    return prog
P.build_program = timed_build
scene = bench_scene(name)
r = Renderer(scene, Settings(method="restir", specialise=specialise, jitter=not still))
render = (lambda i: r.render_frame(0, still=True)) if still else (lambda i: r.render_frame(i % scene.frames))
t0, c0 = time.perf_counter(), time.process_time()
render(0)
first, first_cpu = time.perf_counter() - t0, time.process_time() - c0
walls = []
c0 = time.process_time()
for i in range(1, frames + 1):
    t0 = time.perf_counter()
    render(i)
    walls.append(time.perf_counter() - t0)
cpu = (time.process_time() - c0) / frames
walls.sort()
print(json.dumps(dict(build_s=r.build_seconds, build_cpu_s=build_cpu["s"], first_s=first, first_cpu_s=first_cpu,
                      frame_ms=1e3 * walls[len(walls) // 2], frame_cpu_ms=1e3 * cpu, features=r.features)))
"""


def bench_scene(name: str) -> Scene:
    """Scenes of the specialisation benchmark: many_lights with point lights only, with emissive meshes only,
    and a still frame of the full scene (its camera does not move)."""
    from .. import scenes

    if name == "points":  # (many_lights(lamps=0) fails in scenes._merge: drop the lamps instead)
        scene = scenes.many_lights(width=320, height=180, frames=16, lamps=1, point_lights=256)
        scene.meshes = [m for m in scene.meshes if m.name != "lamps"]
        return scene
    if name == "meshes":
        return scenes.many_lights(width=320, height=180, frames=16, lamps=500, point_lights=0)
    if name == "still":
        return scenes.many_lights(width=320, height=180, frames=1)
    raise ValueError(name)


def bench_specialisation(frames: int = 24, log: Callable[[str], None] | None = None) -> list[dict]:
    """Kernel build time, first frame (PoCL generates each kernel's machine code when it first runs) and the
    per-frame time after it (median wall, mean CPU), ReSTIR at 320x180, specialised against general builds. Each
    measurement runs in a fresh process with empty PoCL and pyopencl caches, so that builds are real. CPU times
    sum all threads of the process: on a shared machine they are the figures to compare."""
    rows = []
    for name, still in (("points", False), ("meshes", False), ("still", True)):
        for specialise in (True, False):
            with tempfile.TemporaryDirectory(prefix="restircl-bench-") as tmp:
                env = dict(os.environ, POCL_CACHE_DIR=os.path.join(tmp, "pocl"),
                           PYOPENCL_CACHE_DIR=os.path.join(tmp, "pyopencl"))
                out = subprocess.run([sys.executable, "-c", _BENCH_CHILD, name, str(int(specialise)), str(frames),
                                      str(int(still))], env=env, capture_output=True, text=True, check=True)
            row = dict(scene=name, build="specialised" if specialise else "general", **json.loads(
                out.stdout.strip().splitlines()[-1]))
            rows.append(row)
            if log:
                log(f"{name:7s} {row['build']:11s} build {row['build_s']:5.2f} s ({row['build_cpu_s']:5.2f} cpu)  "
                    f"first frame {row['first_s']:5.2f} s ({row['first_cpu_s']:5.2f} cpu)  then "
                    f"{row['frame_ms']:6.1f} ms/frame ({row['frame_cpu_ms']:6.1f} cpu)  "
                    f"[{', '.join(row['features'])}]")
    return rows
