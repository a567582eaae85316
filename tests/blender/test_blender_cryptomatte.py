"""Cryptomatte through the add-on: the view layer's Object, Material and Asset toggles and Levels register Cycles'
passes (CryptoObject00, ...), an F12 render fills them with ids ranked by coverage and writes each layer's
manifest into the EXR's metadata under Cycles' keys. Checked against Cycles' own render of the scene: the ids of the
objects, materials and assets (MurmurHash3 of their names, render/cryptomatte.py) are the floats Cycles writes,
pixel for pixel where Cycles saw one id alone, with coverage 1 there; Cycles' manifest holds ours; and Blender's
compositor's Cryptomatte node picks the same object from our render as from Cycles'."""

from __future__ import annotations

import json

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402
from restircl.render.cryptomatte import murmur3_32, name_hash, name_id  # noqa: E402

from .test_blender_index_passes import objects_scene, ours_then_cycles  # noqa: E402
from .test_blender_light_passes import _addon  # noqa: E402, F401  (autouse: the engine's crashes fail the test)
from .test_blender_support import needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


def _scene():
    sc, obs, mats = objects_scene()
    lid = scenes.box("Lid", (0.6, 0.6, 0.3), mats["Grey"], location=(0.0, 0.0, 0.75))
    lid.parent = obs["Box"]  # an asset of two objects: Box
    vl = sc.view_layers[0]
    vl.use_pass_cryptomatte_object = vl.use_pass_cryptomatte_material = vl.use_pass_cryptomatte_asset = True
    vl.pass_cryptomatte_depth = 4
    sc.restircl.samples = 16
    return sc


def _read(path) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """Channels by lower-case name ('CryptoObject00.r') and the string metadata of a Blender multilayer EXR."""
    import OpenEXR

    chans, meta = {}, {}
    with OpenEXR.File(str(path), separate_channels=True) as f:
        for part in f.parts:
            meta.update({k: v for k, v in part.header.items() if isinstance(v, str)})
            for name, ch in part.channels.items():
                chans[".".join(name.split(".")[-2:]).lower()] = np.asarray(ch.pixels, np.float32)
    return chans, meta


def test_murmur3_of_the_specs_examples():
    # MurmurHash3_x86_32 reference values (seed 0), and the exponent rule of the Cryptomatte spec
    assert murmur3_32(b"") == 0
    assert murmur3_32(b"hello") == 0x248BFA47
    assert murmur3_32(b"The quick brown fox jumps over the lazy dog") == 0x2E4FF723
    for name in ("Floor", "Box", "a", "bunny"):
        e = (name_hash(name) >> 23) & 0xFF
        assert 0 < e < 255 and np.isfinite(name_id(name))


def test_f12_cryptomatte_agrees_with_cycles(tmp_path):
    ours_then_cycles(_scene(), tmp_path, 16)
    ours, ours_meta = _read(tmp_path / "ours.exr")
    cyc, cyc_meta = _read(tmp_path / "cycles.exr")
    for layer in ("CryptoObject", "CryptoMaterial", "CryptoAsset"):
        for k in ("00", "01"):
            assert f"{layer.lower()}{k}.r" in ours, f"{layer}{k}"
        rank0, cov0 = ours[f"{layer.lower()}00.r"], ours[f"{layer.lower()}00.g"]
        want = cyc[f"{layer.lower()}00.r"]
        inner = cyc[f"{layer.lower()}00.g"] > 0.999  # Cycles saw one id alone there
        assert inner.mean() > 0.4  # enough such pixels to compare (5.0.1: over half, 5.3 filters more: 0.497)
        np.testing.assert_array_equal(rank0[inner].view(np.uint32), want[inner].view(np.uint32))
        # coverage 1 there, but at an edge the two renderers' samples may fall otherwise (Cycles filters them)
        assert np.mean(cov0[inner & (rank0 != 0)] > 0.99) > 0.95
        # the manifest: under the layer's key, names to hashes, the ones of ours also in Cycles'
        key = f"cryptomatte/{murmur3_32(f'ViewLayer.{layer}'.encode()):08x}"[:19]
        mine = json.loads(ours_meta[f"{key}/manifest"])
        theirs = json.loads(cyc_meta[f"{key}/manifest"])
        assert ours_meta[f"{key}/hash"] == "MurmurHash3_32" and ours_meta[f"{key}/name"] == f"ViewLayer.{layer}"
        assert mine and all(theirs.get(n) == h for n, h in mine.items()), (mine, theirs)
    asset_key = f"cryptomatte/{murmur3_32(b'ViewLayer.CryptoAsset'):08x}"[:19]
    assert "Lid" not in json.loads(ours_meta[f"{asset_key}/manifest"])  # the lid is part of the Box asset


def _matte(sc, tmp_path, name: str) -> np.ndarray:
    """The compositor's Cryptomatte node (Blender 5's node-group compositor) picking object `name` from the render
    of `sc`: its Matte output, (H, W)."""
    import OpenEXR

    tree = bpy.data.node_groups.new("Comp", "CompositorNodeTree")
    sc.compositing_node_group = tree
    layers = tree.nodes.new("CompositorNodeRLayers")
    layers.scene = sc
    crypto = tree.nodes.new("CompositorNodeCryptomatteV2")
    crypto.source, crypto.scene, crypto.layer_name, crypto.matte_id = "RENDER", sc, "ViewLayer.CryptoObject", name
    out = tree.nodes.new("NodeGroupOutput")
    tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    tree.links.new(layers.outputs["Image"], crypto.inputs["Image"])
    tree.links.new(crypto.outputs["Matte"], out.inputs[0])
    sc.render.use_compositing = True
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.filepath = str(tmp_path / f"matte_{sc.render.engine}.exr")
    bpy.ops.render.render(write_still=True)
    with OpenEXR.File(sc.render.filepath, separate_channels=True) as f:
        return np.asarray(f.parts[0].channels["R"].pixels, np.float32)


@pytest.mark.skipif("compositing_node_group" not in bpy.types.Scene.bl_rna.properties, reason="Blender 5 compositor")
def test_the_compositors_cryptomatte_node_picks_an_object(tmp_path):
    sc = _scene()
    ours = _matte(sc, tmp_path, "Box")
    sc.render.engine = "CYCLES"
    sc.cycles.samples = 16
    cyc = _matte(sc, tmp_path, "Box")
    print(f"Box's matte: {100 * (ours > 0.5).mean():.2f} % of the image (Cycles {100 * (cyc > 0.5).mean():.2f} %), "
          f"mean |difference| {np.abs(ours - cyc).mean():.4f}")
    assert 0.02 < (ours > 0.5).mean() < 0.5  # the box, and only it
    assert np.array_equal(ours > 0.5, cyc > 0.5)
    assert np.abs(ours - cyc).mean() < 0.02  # the edges' coverage differs a little (Cycles filters its samples)
