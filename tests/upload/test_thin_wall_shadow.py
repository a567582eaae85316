"""The records of thin walls that shadow rays pass (upload/thin_wall_shadow.py, opencl/bvh/thin_wall_shadow.h): which
materials qualify, what the record holds, and where it sits in the Tri array's tail (upload/alpha.py)."""

from __future__ import annotations

import numpy as np
from restircl import Material, Scene
from restircl.eval.scenes.alpha_cards import card
from restircl.materials.textures import ImageTexture
from restircl.upload.alpha import ALPHA_MATERIAL, transparency_tail
from restircl.upload.thin_wall_shadow import scene_has_thin_shadow, thin_wall_record

IMG = np.zeros((1, 2, 4), np.float32)


def pane(**kw) -> Material:
    args = {"albedo": (0.9, 0.75, 0.5), "roughness": 0.0, "ior": 1.45, "transmission": 0.8, "metallic": 0.25,
            "specular_tint": (1.0, 0.5, -1.0), "thin_wall": True, **kw}
    return Material("pane", **args)


def test_a_smooth_constant_thin_wall_has_a_record():
    rec = thin_wall_record(pane())
    assert rec is not None
    assert np.allclose(rec[0], [0.9, 0.75, 0.5, 1.45])
    assert np.allclose(rec[1], [1.0, 0.5, 0.0, 0.8 * 0.75])  # tint clamped at 0; weight Transmission x (1 - Metallic)


def test_walls_the_rays_cannot_evaluate_or_that_are_rough_have_none():
    assert thin_wall_record(pane(thin_wall=False)) is None
    assert thin_wall_record(pane(roughness=0.2)) is None
    assert thin_wall_record(pane(transmission=0.0)) is None
    assert thin_wall_record(pane(metallic=1.0)) is None
    assert thin_wall_record(pane(albedo=ImageTexture(IMG))) is None
    assert thin_wall_record(Material.mixed(pane(), Material("d"))) is None
    assert thin_wall_record(pane(roughness=0.003)) is not None  # alpha^2 = 8.1e-11: Cycles' delta
    assert thin_wall_record(pane(roughness=0.004)) is None  # 2.6e-10


def test_an_opaque_thin_wall_gets_a_coverage_record_of_1_and_its_wall():
    mats = [Material("floor"), pane()]
    sc = Scene([card("a", (0, 0, 0), (1, 0, 0), (0, 1, 0), 0), card("b", (0, 0, 1), (1, 0, 0), (0, 1, 0), 1)],
               mats, [], None)
    assert scene_has_thin_shadow(sc) and not scene_has_thin_shadow(Scene(sc.meshes, [mats[0], mats[0]], [], None))
    e1w, tail = transparency_tail(sc, np.array([1, 0, 1, 0]), np.zeros((4, 3, 2)), 30)
    assert list(e1w[[1, 3]]) == [-1, -1] and e1w[0] == 30 + ALPHA_MATERIAL
    assert tail[0].tolist() == [1.0, 0.0, 0.0, 1.0]  # coverage 1, no image, a smooth thin wall
    assert np.allclose(tail[4:6], thin_wall_record(pane()))
