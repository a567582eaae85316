"""The stress suite's cases of light that bounces (Settings.max_bounces > 0): a closed room of mirrors, an emitter
seen only through bounces, Max Bounces 1000 in a closed white room, a black world; each against the exhaustive
reference of its own bounces (the direct light exhaustive, the bounced light by the path pass, averaged)."""

from __future__ import annotations

from ...environment.world import Environment
from ...materials.material import Material
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import translation
from ...scenes.shapes import box, quad
from .cases import Case, _cam, _floor, _grey


def _closed_room(size: float, material: int) -> Mesh:
    """A box seen from inside: its faces turned inwards."""
    v, t = box((size, size, size))
    return Mesh("room", v, t[:, ::-1].copy(), material)


def mirror_room(full: bool) -> Case:
    """A closed room of near-mirror metal walls (roughness 0.02) around a small sphere light and a diffuse block,
    64 bounces: paths that bounce between mirrors many times; exhaustive reference."""
    w, h = (32, 24) if full else (12, 9)
    mats = [Material("mirror", (0.95, 0.95, 0.95), metallic=1.0, roughness=0.02), Material("grey", (0.7, 0.7, 0.7))]
    bv, bt = box((0.5, 0.5, 0.5))
    meshes = [_closed_room(4.0, 0), Mesh("block", bv + (0.6, 0.4, -1.7), bt, 1)]
    lights = [Light("bulb", "point", (1.0, 0.9, 0.8), 200.0, translation(-0.5, 0.3, 0.8), radius=0.1)]
    cam = _cam((0.0, -1.6, 0.4), (0.3, 0.5, -1.2), w, h, lens=20.0)
    scene = Scene(meshes, mats, lights, cam, name="mirror_room")
    return Case("mirror_room", "a closed room of mirrors, 64 bounces", scene, reference="exhaustive",
                runs=16 if full else 8, settings=dict(max_bounces=64, diffuse_bounces=64, glossy_bounces=64))


def hidden_emitter(full: bool) -> Case:
    """A tiny, very bright emitter behind a wall that the camera sees no direct light from: the floor in view is
    lit only by what bounces off the wall and ceiling (4 bounces); exhaustive reference."""
    w, h = (32, 24) if full else (12, 9)
    fv, ft = quad(8.0, 8.0)
    wv, wt = box((0.1, 6.0, 2.0))
    cv, ct = quad(8.0, 8.0)
    meshes = [Mesh("floor", fv, ft, 0), Mesh("wall", wv + (1.0, 0.0, 1.0), wt, 0),
              Mesh("ceiling", cv[:, [0, 1, 2]] * (1, -1, 1) + (0.0, 0.0, 2.5), ct, 0)]
    lights = [Light("spark", "point", (1.0, 1.0, 1.0), 1e5, translation(2.0, 0.0, 0.3), radius=1e-3)]
    cam = _cam((-3.0, -2.5, 1.5), (-1.0, 0.5, 0.0), w, h)
    scene = Scene(meshes, _grey(), lights, cam, name="hidden_emitter")
    return Case("hidden_emitter", "a tiny bright emitter seen only through bounces", scene, reference="exhaustive",
                runs=16 if full else 8, settings=dict(max_bounces=4, diffuse_bounces=4, glossy_bounces=4))


def thousand_bounces(full: bool) -> Case:
    """A closed white room (albedo 0.95) with one light inside, Max Bounces 1000: Russian roulette ends the paths
    and the estimate stays finite; exhaustive reference."""
    w, h = (32, 24) if full else (12, 9)
    lights = [Light("bulb", "point", (1.0, 1.0, 1.0), 100.0, translation(0.0, 0.0, 1.0), radius=0.2)]
    cam = _cam((0.0, -1.5, 0.0), (0.0, 1.0, -0.5), w, h, lens=20.0)
    scene = Scene([_closed_room(4.0, 0)], [Material("white", (0.95, 0.95, 0.95))], lights, cam,
                  name="thousand_bounces")
    return Case("thousand_bounces", "a closed white room, Max Bounces 1000", scene, reference="exhaustive",
                runs=16 if full else 8,
                settings=dict(max_bounces=1000, diffuse_bounces=1000, glossy_bounces=1000))


def black_world(full: bool) -> Case:
    """A black world (colour 0) around a floor and a block lit by one area light, 8 bounces: rays that escape
    find nothing; exhaustive reference."""
    w, h = (32, 24) if full else (12, 9)
    bv, bt = box((0.6, 0.6, 0.6))
    lights = [Light("panel", "area", (1.0, 1.0, 1.0), 80.0, translation(0.0, 0.0, 2.0), size=1.0)]
    cam = _cam((0.0, -3.0, 2.0), (0.0, 0.0, 0.3), w, h)
    scene = Scene([_floor(4.0), Mesh("block", bv + (0.0, 0.0, 0.3), bt, 0)], _grey(), lights, cam,
                  name="black_world", environment=Environment(color=(0.0, 0.0, 0.0)))
    return Case("black_world", "a black world, 8 bounces", scene, reference="exhaustive", runs=16 if full else 8,
                settings=dict(max_bounces=8, diffuse_bounces=8, glossy_bounces=8))
