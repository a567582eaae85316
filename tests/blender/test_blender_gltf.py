"""Real assets as Blender's glTF importer makes them (tests/blender/gltf_scenes.py): the importer's node setup, the
bake of a packed occlusion-roughness-metallic channel, and the export of the helmet material."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from .gltf_scenes import SIZE, import_helmet, orm_texels  # noqa: E402
from .test_blender_materials import fresh_scene  # noqa: E402
from .test_blender_support import ensure_registered  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def _helmet(tmp_path):
    fresh_scene()
    ob = import_helmet(tmp_path)
    return ob, ob.data.materials[0]


def test_the_importer_gives_the_packed_orm_setup(tmp_path):
    ob, mat = _helmet(tmp_path)
    kinds = sorted(n.bl_idname for n in mat.node_tree.nodes)
    assert kinds.count("ShaderNodeTexImage") >= 4 and "ShaderNodeSeparateColor" in kinds
    assert "ShaderNodeGroup" in kinds and ob.data.uv_layers.keys() == ["UVMap"]
    p = mat.node_tree.nodes["Principled BSDF"]
    for name, channel in (("Roughness", "Green"), ("Metallic", "Blue")):
        link = p.inputs[name].links[0]
        assert link.from_node.bl_idname == "ShaderNodeSeparateColor" and link.from_socket.name == channel


@pytest.mark.parametrize("channel", ["Green", "Blue"])
def test_bake_of_a_packed_channel_is_the_image_channel(tmp_path, channel):
    """Cycles' Emit bake of a Separate Color output on the imported mesh gives the ORM image's channel (the texels
    of the UV map's interior: the sphere's poles squeeze whole rows into a point)."""
    from restircl_blender.export.bake import bake_socket

    ob, mat = _helmet(tmp_path)
    sock = mat.node_tree.nodes["Principled BSDF"].inputs["Roughness" if channel == "Green" else "Metallic"]
    baked = bake_socket(mat, ob, sock.links[0].from_socket, SIZE)[::-1, :, 0]  # rows bottom first, as the image
    want = orm_texels()[..., 1 if channel == "Green" else 2]
    inner = (slice(2, SIZE - 2), slice(1, SIZE - 1))
    assert baked.max() > 0.5, "the bake wrote zeros"
    # texel centres, antialiased over the texel (the ramp's kinks blur by a texel)
    tol = 0.02 if channel == "Green" else 0.15
    np.testing.assert_allclose(baked[inner], want[inner], atol=tol)
