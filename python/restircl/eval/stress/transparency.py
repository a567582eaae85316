"""The stress suite's cases of transparent surfaces (Material.alpha, opencl/bvh/transparent.h): coverage 0 on every
surface, and a thousand stacked cards of coverage 0.5 that every camera and shadow ray meets."""

from __future__ import annotations

import dataclasses

from ...materials.material import Material
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import translation
from ...scenes.shapes import box
from ..scenes.alpha_cards import card_stack
from .cases import Case, _cam, _floor


def alpha_zero(full: bool) -> Case:
    """A floor, a block and a wall of coverage 0 under an area light, no world: every ray passes every surface
    (more of them than Transparent Max Bounces allows on some rays, which then end black), so the image is 0."""
    w, h = (32, 24) if full else (12, 9)
    bv, bt = box((0.6, 0.6, 0.6))
    wv, wt = box((0.1, 4.0, 2.0))
    meshes = [_floor(4.0), Mesh("block", bv + (0.0, 0.0, 0.3), bt, 0), Mesh("wall", wv + (1.0, 0.0, 1.0), wt, 0)]
    meshes += [dataclasses.replace(_floor(4.0, z=0.1 * k), name=f"layer{k}") for k in range(1, 12)]
    lights = [Light("panel", "area", (1.0, 1.0, 1.0), 80.0, translation(0.0, 0.0, 2.5), size=1.0)]
    scene = Scene(meshes, [Material("clear", (0.7, 0.7, 0.7), alpha=0.0)], lights,
                  _cam((0.0, -3.0, 2.0), (0.0, 0.0, 0.3), w, h), name="alpha_zero")
    return Case("alpha_zero", "coverage 0 everywhere, 14 layers", scene, reference="zero", runs=4 if full else 2)


def stacked_cards(full: bool) -> Case:
    """A thousand cards of coverage 0.5, 1 mm apart, over a lit floor: Transparent Max Bounces (8) bounds the work
    of every ray; exhaustive reference. ReSTIR's biased mode darkens more than elsewhere (-26 to -29 %, 12x9):
    a shadow ray passes the stack by chance (bvh/transparent.h), and a neighbour whose ray was blocked counts in M
    with nothing; the unbiased modes re-test visibility and hold."""
    w, h = (32, 24) if full else (12, 9)
    scene = card_stack(1000, 0.5, w, h, spacing=1e-3)
    return Case("stacked_cards", "a thousand stacked cards of coverage 0.5", scene, reference="exhaustive",
                runs=16 if full else 8, biased_darkening=0.35)
