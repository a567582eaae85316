"""Textured emission as a light (lights/textured_emission.py) against Cycles: a ceiling panel whose Emission Color is
a two-texel image, black on one half and white on the other, lights a grey floor; the camera looks down at the
floor from below the panel (it sees the light cast, not the panel). Direct light, F12 against Cycles, relMSE < 1e-2.
The test's power: our render against Cycles' render of the same panel emitting white everywhere (what a textured
emission lit before: its white bound) fails the bound."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


def _panel(textured: bool):
    """The panel: a 4x4 grid (its UV map covers [0, 1]^2, each triangle on one side of u = 1/2), facing down."""
    mat = bpy.data.materials.new("Panel")
    tree = mat.node_tree
    p = tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    p.inputs["Emission Strength"].default_value = 12.0
    p.inputs["Emission Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    if textured:
        img = bpy.data.images.new("HalfWhite", 2, 1, alpha=True)
        img.pixels.foreach_set(np.array([0, 0, 0, 1, 1, 1, 1, 1], np.float32))
        img.pack()
        tex = tree.nodes.new("ShaderNodeTexImage")
        tex.image = img
        tex.interpolation = "Closest"
        tree.links.new(tex.outputs["Color"], p.inputs["Emission Color"])
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=4, size=1.2, location=(0, 0, 1.6),
                                    rotation=(math.pi, 0, 0))
    ob = bpy.context.object
    ob.data.materials.append(mat)
    return ob


def _scene(textured: bool):
    sc = scenes.new_scene(48, 36)
    scenes.quad("Floor", 8.0, material=scenes.diffuse_material("FloorGrey", (0.5, 0.5, 0.5)))
    _panel(textured)
    scenes.camera((0.0, -0.4, 1.2), (0.0, 0.0, 0.0), lens=20.0)
    return sc


def test_an_emission_image_lights_the_floor_as_cycles_does(tmp_path, record_property):
    from .test_blender_support import cycles_and_ours, read_exr_passes, relmse, render_to

    sc = _scene(textured=True)
    err, ratio = cycles_and_ours(tmp_path, sc, 256, 64, "half-white panel")
    record_property("relmse", err)
    assert err < 1e-2, f"half-white panel: relMSE {100 * err:.3f} % against Cycles"
    assert ratio == pytest.approx(1.0, abs=0.02)
    ours = read_exr_passes(tmp_path / "ours.exr")["Combined"]
    white = _scene(textured=False)
    scenes.cycles_direct_only(white, samples=256, seed=1, threads=2)
    render_to(white, tmp_path / "white.exr")
    cyc_white = read_exr_passes(tmp_path / "white.exr")["Combined"]
    wrong = relmse(ours, cyc_white)
    record_property("relmse_white", wrong)
    print(f"half-white panel against Cycles' white panel: relMSE {100 * wrong:.3f} %")
    assert wrong > 10 * max(err, 1e-3), f"the white panel is not told apart: relMSE {100 * wrong:.3f} %"
