"""The extreme scenes of the stress suite (eval/stress/suite.py), each in a small version (the tests) and a full one
(`restircl stress --full`), with how each is rendered and which reference it is compared with."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import box, quad
from ...settings.table import Settings


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
    convergence: tuple[int, ...] = ()  # still: frame counts whose relMSE must fall as 1 / N (stress/convergence.py)
    convergence_runs: int = 8  # independent runs the relMSE at each of those counts is averaged over
    biased_darkening: float | None = None  # the biased mode's darkening allowed here (None: judging.BIASED_DARKENING)


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
