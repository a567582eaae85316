"""The Bump node (issue 41) read natively (add-on export/inputs.py, opencl/textures/bump.h) against Cycles: a plane
whose height is a smooth float image (two periods of sin u sin v), bumped at Distance 0.2, lit by a sun at a
grazing angle, 48x36, direct light. Negative control: the same render against Cycles' flat plane (the bump
unlinked, what the export did before: ignored) is far from the bound."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]
N = 64


def _scene(invert: bool = False):
    sc = scenes.new_scene(48, 36)
    mat, tree, out = scenes.node_material(bpy, "Bumpy")
    d = tree.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1.0)
    img = bpy.data.images.new("Height", N, N, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"  # before the pixels: a generated image is made anew on this change
    v, u = (np.mgrid[0:N, 0:N] + 0.5) / N
    px = np.ones((N, N, 4), np.float32)
    px[..., :3] = (0.5 + 0.5 * np.sin(4 * math.pi * u) * np.sin(4 * math.pi * v))[..., None]
    img.pixels.foreach_set(px.reshape(-1))
    img.pack()
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = img
    bump = tree.nodes.new("ShaderNodeBump")
    bump.inputs["Distance"].default_value = 0.2
    bump.invert = invert
    tree.links.new(tex.outputs["Color"], bump.inputs["Height"])
    tree.links.new(bump.outputs["Normal"], d.inputs["Normal"])
    tree.links.new(d.outputs[0], out.inputs["Surface"])
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    bpy.context.object.data.materials.append(mat)
    scenes.light("SUN", "Sun", (0, 0, 5), (math.radians(75), 0, math.radians(30)), energy=4.0)
    scenes.camera((0.0, -2.2, 3.2), (0.0, 0.0, 0.0), lens=28.0)
    return sc, tree, bump


def test_the_bump_node_is_read_natively():
    from restircl import Bump, ImageTexture

    from .test_blender_materials import export
    from .test_blender_support import ensure_registered

    ensure_registered()
    _scene(invert=True)
    exp = export(bake_resolution=16)
    m = next(m for m in exp.scene.materials if m.name == "Bumpy")
    assert isinstance(m.normal, Bump) and isinstance(m.normal.height, ImageTexture)
    assert (m.normal.distance, m.normal.strength, m.normal.invert) == (pytest.approx(0.2), 1.0, True)
    assert not any("Bumpy" in w for w in exp.warnings), exp.warnings


def test_a_bumped_plane_under_a_grazing_sun_agrees_with_cycles(tmp_path, record_property):
    from .test_blender_support import cycles_and_ours, read_exr_passes, relmse, render_to

    sc, tree, bump = _scene()
    err, ratio = cycles_and_ours(tmp_path, sc, 256, 64, "bumped plane")
    record_property("relmse", err)
    assert err < 1e-2 and ratio == pytest.approx(1.0, abs=0.02)
    ours = read_exr_passes(tmp_path / "ours.exr")["Combined"]
    for link in list(bump.outputs["Normal"].links):
        tree.links.remove(link)
    scenes.cycles_direct_only(sc, samples=256, seed=1, threads=2)
    render_to(sc, tmp_path / "flat.exr")
    wrong = relmse(ours, read_exr_passes(tmp_path / "flat.exr")["Combined"])
    record_property("relmse_flat", wrong)
    print(f"bumped plane against Cycles' flat plane: relMSE {100 * wrong:.3f} %")
    assert wrong > max(1e-2, 10 * err)
