"""Real glTF sample models (restircl.eval.assets: $RESTIRCL_ASSETS or ~/.cache/restircl/assets; tools/fetch_assets.py
gets them) through Blender's own glTF importer: the node types each uses and how the export reads them, and the
issue's scene against Cycles (slow). Every test skips, saying why, when its asset is absent."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import assets  # noqa: E402
from restircl.eval import blender_scenes as scenes  # noqa: E402

from .asset_corpus import CORPUS  # noqa: E402
from .test_blender_materials import fresh_scene  # noqa: E402
from .test_blender_support import ensure_registered, needs_renderer  # noqa: E402

pytestmark = pytest.mark.blender

# The DamagedHelmet's material as the importer sets it up (bpy 5.0.1), and how the export reads each node type.
HELMET_NODES = {"ShaderNodeBsdfPrincipled": 1, "ShaderNodeOutputMaterial": 1, "ShaderNodeGroup": 1,
                "ShaderNodeTexImage": 5, "ShaderNodeSeparateColor": 2, "ShaderNodeNormalMap": 1, "ShaderNodeUVMap": 1}


@pytest.fixture
def helmet_path():
    path, why = assets.find("DamagedHelmet.glb")
    if path is None:
        pytest.skip(why)
    ensure_registered()
    return path


def test_the_helmet_import_has_the_packed_orm_setup(helmet_path):
    from .gltf_scenes import import_real_helmet

    fresh_scene()
    ob = import_real_helmet(helmet_path)
    (mat,) = ob.data.materials
    kinds: dict[str, int] = {}
    for n in mat.node_tree.nodes:
        kinds[n.bl_idname] = kinds.get(n.bl_idname, 0) + 1
    assert kinds == HELMET_NODES
    assert ob.data.uv_layers.keys() == ["UVMap", "UVMap.001"]  # the occlusion reads the second through a UV Map node


def test_the_helmet_material_is_read_natively(helmet_path):
    """Metallic and roughness are channels 2 and 1 of one ORM image lookup, nothing is baked, the occlusion group
    is ignored as Cycles ignores it, and the emissive image is the emission."""
    from restircl import ImageTexture, NormalMap, SeparateColor

    from .gltf_scenes import import_real_helmet
    from .test_blender_materials import export

    fresh_scene()
    ob = import_real_helmet(helmet_path)
    exp = export(bake_resolution=16)
    (m,) = [m for m in exp.scene.materials if m.name == ob.data.materials[0].name]
    orm = None
    for field, channel in (("roughness", 1), ("metallic", 2)):
        node = getattr(m, field)
        assert isinstance(node, SeparateColor) and node.channel == channel
        assert isinstance(node.color, ImageTexture) and node.color.colorspace == "Non-Color"
        orm = np.asarray(node.color.image) if orm is None else orm
        np.testing.assert_array_equal(np.asarray(node.color.image), orm)  # one image read for both channels
    texels = orm
    assert texels.shape[:2] == (2048, 2048) and texels[..., 2].mean() > 100  # mostly metal (blue channel)
    assert isinstance(m.albedo, ImageTexture) and isinstance(m.normal, NormalMap)
    assert isinstance(m.emission, ImageTexture) and m.emission_strength == 1.0
    assert not any("bake" in w or "Group" in w or "glTF" in w for w in exp.warnings), exp.warnings


@pytest.mark.slow
@needs_renderer
def test_the_real_helmet_agrees_with_cycles(helmet_path, tmp_path, record_property):
    """The issue's scene (tests/blender/gltf_scenes.py real_helmet_scene) at 48x36, direct light: F12 (its default
    still estimator, textures read at full resolution) against Cycles, relMSE < 1e-2 and image means within 2 %.
    Both sides converged: Cycles at 4096 samples is 0.11 % from itself under another seed, F12 at 1024 estimates
    its own relMSE at 0.23 % (measured when written: relMSE 0.26 %, mean 0.998). Negative control: the same still
    reading the mip level of the pixel's ray cone (which averages the 2048^2 normal and roughness maps, minified
    ~40x, before shading) was 4.5 % off."""
    from .gltf_scenes import real_helmet_scene
    from .test_blender_support import read_exr_passes, relmse, render_to

    sc = real_helmet_scene(helmet_path, 48, 36)
    scenes.cycles_direct_only(sc, samples=4096, seed=1, threads=2)
    render_to(sc, tmp_path / "cycles.exr")
    cyc = read_exr_passes(tmp_path / "cycles.exr")["Combined"][..., :3]
    assert cyc.mean() > 0.01, "the comparison scene is dark: nothing is tested"
    sc.render.engine = "RESTIRCL"
    sc.restircl.samples, sc.restircl.bake_resolution = 1024, 64
    errs = {}
    for mode in ("auto", "mip"):
        sc.restircl.texture_filter = mode
        render_to(sc, tmp_path / f"ours_{mode}.exr")
        ours = read_exr_passes(tmp_path / f"ours_{mode}.exr")["Combined"][..., :3]
        errs[mode] = relmse(ours, cyc)
        print(f"DamagedHelmet, texture_filter {mode}: relMSE {100 * errs[mode]:.3f} %  "
              f"mean ours/cycles {ours.mean() / cyc.mean():.4f}")
        if mode == "auto":
            ratio = float(ours.mean() / cyc.mean())
    record_property("relmse", errs["auto"])
    assert errs["auto"] < 1e-2, f"DamagedHelmet: relMSE {100 * errs['auto']:.3f} % against Cycles"
    assert ratio == pytest.approx(1.0, abs=0.02)
    assert errs["mip"] > 2 * 1e-2  # the bound tells the filters apart


@pytest.mark.parametrize("name", CORPUS)
def test_corpus_materials_are_read_natively(name):
    """Every node of every material of the corpus that feeds what Cycles renders is read natively: nothing baked,
    nothing noted (the table of docs/blender.md, tools/asset_corpus.py table)."""
    from .asset_corpus import corpus_scene, coverage
    from .test_blender_materials import export

    path, why = assets.find(name)
    if path is None:
        pytest.skip(why)
    ensure_registered()
    corpus_scene(path, 16, 12)
    exp = export(bake_resolution=16)
    mats = {s.material for o in bpy.context.scene.objects if o.type == "MESH" and o.name != "Floor"
            for s in o.material_slots if s.material is not None}
    assert mats
    for mat in mats:
        cov = coverage(mat, exp.warnings)
        assert not cov.baked and not cov.notes, (mat.name, cov)
        assert "ShaderNodeBsdfPrincipled" in cov.native and "ShaderNodeTexImage" in cov.native


@pytest.mark.slow
@needs_renderer
@pytest.mark.parametrize("bounces", [0, 4])
@pytest.mark.parametrize("name", CORPUS)
def test_corpus_asset_agrees_with_cycles(name, bounces, tmp_path, record_property):
    """Each asset of the corpus, scaled to the helmet's size on the helmet's stage (asset_corpus.py), F12 against
    Cycles at 48x36 (Cycles 2048 samples, F12 1024 of its default still estimator), direct light and with Light
    Paths Max Bounces 4: relMSE < 1e-2, image means within 2 %. Measured when written (docs/blender.md): helmet
    0.231 % / 0.365 %, WaterBottle 0.057 % / 0.067 %, Avocado 0.011 % / 0.016 %."""
    from .asset_corpus import compare, corpus_scene

    path, why = assets.find(name)
    if path is None:
        pytest.skip(why)
    r = compare(corpus_scene(path, 48, 36), 2048, 1024, bounces, tmp_path)
    record_property("relmse", r["relmse"])
    print(f"{name}, {bounces} bounces: relMSE {100 * r['relmse']:.3f} %  mean ours/cycles {r['mean_ratio']:.4f}")
    assert r["relmse"] < 1e-2
    assert r["mean_ratio"] == pytest.approx(1.0, abs=0.02)
