"""The stress suite's cases of glass (opencl/bsdf/microfacet_dielectric.h): spheres of glass nested three deep, a
camera inside a glass block (most of its rays reflect totally at the faces), interfaces of IOR 1 (rays pass
straight on) and IOR 100 (nearly a mirror), each smooth and rough. Lit by a point light of radius 0, which only
next-event estimation finds: every method then sees the same light at the primary hit (the exhaustive reference's
direct part samples lights only), and the bounced light is the path pass's on both sides. No NaN or Inf, bounded
time, and the methods agree with the reference."""

from __future__ import annotations

from ...materials.material import Material
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import translation
from ...scenes.shapes import box, icosphere
from .cases import Case, _cam, _floor

BOUNCES = dict(max_bounces=16, diffuse_bounces=4, glossy_bounces=16, transmission_bounces=16)


def _glass(name: str, roughness: float, ior: float) -> Material:
    return Material(name, (1.0, 1.0, 1.0), kind="glass", roughness=roughness, ior=ior, distribution="ggx")


def _bulb(power: float = 150.0) -> list[Light]:
    return [Light("bulb", "point", (1.0, 0.95, 0.9), power, translation(0.8, -1.2, 2.2))]


def _case(name: str, description: str, scene: Scene, full: bool) -> Case:
    return Case(name, description, scene, reference="exhaustive", runs=16 if full else 8, settings=dict(BOUNCES))


def _size(full: bool) -> tuple[int, int]:
    return (32, 24) if full else (12, 9)


def nested_glass(full: bool) -> Case:
    """Three glass spheres one inside the other (IOR 1.5, 1.33 and 2.4; smooth, rough 0.4, smooth) on a grey floor:
    every path crosses up to six interfaces, entering and leaving with the right relative IOR."""
    w, h = _size(full)
    mats = [Material("grey", (0.6, 0.6, 0.6)), _glass("outer", 0.0, 1.5), _glass("middle", 0.4, 1.33),
            _glass("inner", 0.0, 2.4)]
    meshes = [_floor()]
    for k, r in enumerate((0.8, 0.55, 0.3)):
        sv, st = icosphere(2, r)
        meshes.append(Mesh(f"shell{k}", sv, st, 1 + k, translation(0.0, 0.0, 0.81)))
    scene = Scene(meshes, mats, _bulb(), _cam((0.0, -3.0, 1.4), (0.0, 0.0, 0.7), w, h), name="nested_glass")
    return _case("nested_glass", "three nested glass spheres, 16 bounces", scene, full)


def total_internal_reflection(full: bool) -> Case:
    """The camera inside a glass block (IOR 1.5, smooth walls and one rough): a ray meets a face beyond the critical
    angle (41.8 degrees) in most pixels, reflects totally, and bounces inside until it leaves."""
    w, h = _size(full)
    mats = [Material("grey", (0.6, 0.6, 0.6)), _glass("block", 0.0, 1.5), _glass("frosted", 0.3, 1.5)]
    bv, bt = box((2.0, 2.0, 1.2))
    sv, st = icosphere(1, 0.25)
    meshes = [_floor(), Mesh("block", bv, bt, 1, translation(0.0, 0.0, 0.7)),
              Mesh("pebble", sv, st, 2, translation(0.3, 0.4, 0.5))]
    scene = Scene(meshes, mats, _bulb(), _cam((-0.6, -0.7, 0.8), (0.5, 0.6, 0.5), w, h, lens=16.0),
                  name="total_internal_reflection")
    return _case("total_internal_reflection", "the camera inside a glass block, 16 bounces", scene, full)


def _two_balls(name: str, ior: float, full: bool) -> Scene:
    w, h = _size(full)
    mats = [Material("grey", (0.6, 0.6, 0.6)), _glass("smooth", 0.0, ior), _glass("rough", 0.5, ior)]
    sv, st = icosphere(2, 0.5)
    meshes = [_floor(), Mesh("smooth", sv, st, 1, translation(-0.6, 0.0, 0.51)),
              Mesh("rough", sv, st, 2, translation(0.6, 0.0, 0.51))]
    return Scene(meshes, mats, _bulb(), _cam((0.0, -3.0, 1.5), (0.0, 0.0, 0.4), w, h), name=name)


def ior_one(full: bool) -> Case:
    """Glass of IOR 1, smooth and rough: nothing reflects, every ray passes straight on (Cycles' singular case)."""
    return _case("ior_one", "glass of IOR 1, smooth and rough, 16 bounces", _two_balls("ior_one", 1.0, full), full)


def ior_hundred(full: bool) -> Case:
    """Glass of IOR 100, smooth and rough: it reflects 96 % at normal incidence and refracts the rest almost along
    the normal."""
    return _case("ior_hundred", "glass of IOR 100, smooth and rough, 16 bounces",
                 _two_balls("ior_hundred", 100.0, full), full)
