"""Material.alpha, the coverage (materials/alpha.py): the forms a ray can evaluate, their validation, and their
records appended to the Tri array (upload/alpha.py), read back as the device reads them."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import CheckerTexture, ImageTexture, Invert, Material, Scene, SceneError
from restircl.core import layouts as L
from restircl.eval.scenes.alpha_cards import alpha_cards, card
from restircl.materials.alpha import AlphaError, alpha_source, is_transparent
from restircl.upload.alpha import ALPHA_MATERIAL, ALPHA_TRIANGLE, transparency_tail

IMG = np.array([[[0, 0, 0, 255], [255, 255, 255, 0]]], np.uint8)  # 1 x 2: left opaque black, right clear white


def test_forms():
    assert alpha_source(0.25).constant == 0.25 and alpha_source(1).image is None
    s = alpha_source(ImageTexture(IMG, alpha=True))
    assert s.image is not None and s.channel == "alpha" and not s.invert
    s = alpha_source(Invert(color=ImageTexture(IMG), factor=1.0))
    assert s.channel == "grey" and s.invert
    for bad in (1.5, -0.1, float("nan"), CheckerTexture(), ImageTexture(IMG, coords="generated"),
                Invert(color=ImageTexture(IMG), factor=0.5), Invert(color=0.3), "a"):
        with pytest.raises(AlphaError):
            alpha_source(bad)


def test_validation_names_the_material():
    sc = alpha_cards(8, 6)
    sc.materials[2].alpha = 2.0
    with pytest.raises(SceneError, match="pane.*alpha"):
        sc.validate()


def test_transparent_materials():
    assert not is_transparent(Material())
    assert is_transparent(Material(alpha=0.99)) and is_transparent(Material(alpha=ImageTexture(IMG)))


def test_tail_records():
    """Two materials, the second transparent with an image: its record, its triangles' UV records and the scalar
    texels (alpha, bottom row first), at the float4 indices e1.w names."""
    mats = [Material("opaque"), Material("leaf", alpha=ImageTexture(IMG, alpha=True, interpolation="Closest",
                                                                       extension="CLIP"))]
    meshes = [card("a", (0, 0, 0), (1, 0, 0), (0, 1, 0), 0), card("b", (0, 0, 1), (1, 0, 0), (0, 1, 0), 1)]
    sc = Scene(meshes, mats, [], None)
    material = np.array([1, 0, 1, 0])  # leaf order of the four triangles
    uvs = np.arange(24, dtype=np.float64).reshape(4, 3, 2)
    base = 30
    e1w, tail = transparency_tail(sc, material, uvs, base)
    assert list(e1w[[1, 3]]) == [-1, -1]
    first = base + ALPHA_MATERIAL
    assert list(e1w[[0, 2]]) == [first, first + ALPHA_TRIANGLE]
    rec = tail[:ALPHA_MATERIAL]
    assert rec[0].tolist() == [1.0, 0.0, 1.0, 0.0]  # constant 1, not inverted, an image
    info = L.float_bits_to_int(rec[1])
    texels = base + ALPHA_MATERIAL + 2 * ALPHA_TRIANGLE
    assert info.tolist() == [texels, 2, 1, 1 | (2 << 4)]  # Closest, Clip
    assert rec[2].tolist() == [1, 0, 0, 0] and rec[3].tolist() == [0, 1, 0, 0]  # no mapping
    tri0 = tail[ALPHA_MATERIAL:ALPHA_MATERIAL + 2]
    assert tri0[0, :3].tolist() == [0, 2, 4] and tri0[1, :3].tolist() == [1, 3, 5]
    assert L.float_bits_to_int(tri0[0, 3:]).tolist() == [base]
    assert tail[texels - base].tolist() == [1.0, 0.0, 0.0, 0.0]  # alpha 255, 0 (and padding)
    assert len(tail) == texels - base + 1


def test_scene_file_keeps_alpha(tmp_path):
    from restircl.scene.file import load_scene, save_scene

    save_scene(alpha_cards(8, 6), tmp_path / "alpha.json")
    back = load_scene(tmp_path / "alpha.json", Scene)
    leaf, pane = back.materials[1].alpha, back.materials[2].alpha
    assert isinstance(leaf, ImageTexture) and leaf.alpha and leaf.image.shape == (32, 32, 4)
    assert pane == 0.5 and back.materials[0].alpha == 1.0
