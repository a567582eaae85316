"""Scenes where BSDF-sampled candidates matter (opencl/direct/bsdf_candidates.h), for `restircl report` and tests:
`neon`, diffuse walls lit by emissive geometry close to them (a torus, strips and a small sphere: about 3,600 light
triangles), and `glossy_many_lights`, the built-in many_lights with a polished floor and glossy and metal objects.
Written to a scene file by `python -m restircl.eval.scenes.bsdf NAME PATH`."""

from __future__ import annotations

import sys

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at
from ...scenes.builtin import many_lights
from ...scenes.shapes import box, icosphere, quad
from .held_out import torus


def neon(width: int = 160, height: int = 90) -> Scene:
    """A floor and a back wall (diffuse) with neon lights near them: an upright torus by the wall, three strips
    lying on the floor and a small glowing sphere, of three colours."""
    materials = [Material("wall", (0.7, 0.7, 0.7)), Material("floor", (0.5, 0.45, 0.4)),
                 Material("pink", (0, 0, 0), (1.0, 0.2, 0.6), 12.0), Material("cyan", (0, 0, 0), (0.2, 0.8, 1.0), 8.0),
                 Material("amber", (0, 0, 0), (1.0, 0.6, 0.1), 20.0)]
    meshes = []
    fv, ft = quad(8, 6)
    meshes.append(Mesh("floor", fv, ft, 1))
    rot_x = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float)
    wv, wt = quad(8, 4)
    meshes.append(Mesh("wall", wv @ rot_x.T + (0, 1.5, 2.0), wt, 0))
    tv, tt = torus(0.6, 0.05, 96, 12)
    meshes.append(Mesh("torus", tv @ rot_x.T + (-0.8, 1.3, 1.3), tt, 2))
    for k, x in enumerate((-0.6, 0.4, 1.4)):
        sv, st = box((0.04, 1.2, 0.04))
        meshes.append(Mesh(f"strip{k}", sv + (x, 0.2, 0.03), st, 3))
    bv, bt = box((0.6, 0.6, 0.6))
    meshes.append(Mesh("block", bv + (0.9, 0.8, 0.3), bt, 0))
    iv, it = icosphere(3, 0.12)
    meshes.append(Mesh("orb", iv + (0.2, 0.9, 0.9), it, 4))
    cam = Camera(look_at((0.0, -3.4, 1.6), (0.1, 0.6, 0.7)), width, height, lens=30.0)
    return Scene(meshes, materials, [], cam, name="neon")


def glossy_many_lights(width: int = 160, height: int = 90, frames: int = 24) -> Scene:
    """many_lights with its four surface materials made glossy: a polished floor (dielectric, roughness 0.2),
    brushed metal (0.25), a glossy red plastic (0.35) and a blue metal (0.2); the lamps as they are. (Scene files
    do not keep the glossy inputs yet, scene/file.py: build it here rather than loading a saved copy.)"""
    scene = many_lights(width, height, frames)
    scene.materials[0] = Material("polished_floor", (0.6, 0.6, 0.6), roughness=0.2, specular=0.5)
    scene.materials[1] = Material("brushed_metal", (0.9, 0.9, 0.9), metallic=1.0, roughness=0.25)
    scene.materials[2] = Material("red_plastic", (0.8, 0.2, 0.15), roughness=0.35, specular=0.5)
    scene.materials[3] = Material("blue_metal", (0.3, 0.5, 0.9), metallic=1.0, roughness=0.2)
    scene.name = "glossy_many_lights"
    return scene


SCENES = {"neon": neon, "glossy_many_lights": glossy_many_lights}

if __name__ == "__main__":
    name, path = sys.argv[1], sys.argv[2]
    SCENES[name]().save(path)
    print(f"wrote {path}")
