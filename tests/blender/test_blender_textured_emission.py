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


def _quad_scene():
    """A quad of two triangles (Blender's plane, 1.6 wide, 1.1 above the floor, facing down) whose 2x2 emission image
    has one white texel: it lies inside one triangle and covers half of it, so each triangle's light varies within
    it. The camera, below the quad, looks at the floor."""
    sc = scenes.new_scene(48, 36)
    scenes.quad("Floor", 8.0, material=scenes.diffuse_material("FloorGrey", (0.5, 0.5, 0.5)))
    mat = bpy.data.materials.new("Quadrant")
    tree = mat.node_tree
    p = tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    p.inputs["Emission Strength"].default_value = 10.0
    img = bpy.data.images.new("OneWhite", 2, 2, alpha=True)
    img.pixels.foreach_set(np.array([0, 0, 0, 1] * 2 + [1, 1, 1, 1] + [0, 0, 0, 1], np.float32))  # u < 1/2, v > 1/2
    img.pack()
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = img, "Closest"
    tree.links.new(tex.outputs["Color"], p.inputs["Emission Color"])
    bpy.ops.mesh.primitive_plane_add(size=1.6, location=(0, 0, 1.1), rotation=(math.pi, 0, 0))
    bpy.context.object.data.materials.append(mat)
    scenes.camera((0.0, -0.3, 0.9), (0.0, 0.2, 0.0), lens=16.0)
    return sc


def test_the_emission_image_is_read_at_the_sampled_point(tmp_path, record_property, monkeypatch):
    """Each triangle's light is its image at the point the light sample lands on (its mean only picks it): the floor
    agrees with Cycles. Negative control: the triangles shining with their means fail the bound. Measured when
    written (48x36, Cycles 1024 samples, ours 256 of `reference`): relMSE 0.31 %, sum 1.004; the means 2.79 %."""
    from restircl.lights import device_lights

    from .test_blender_support import cycles_and_ours, read_exr_passes, relmse, render_to

    sc = _quad_scene()
    err, ratio = cycles_and_ours(tmp_path, sc, 1024, 256, "one-white-texel quad")
    record_property("relmse", err)
    assert err < 1e-2, f"one-white-texel quad: relMSE {100 * err:.3f} % against Cycles"
    assert ratio == pytest.approx(1.0, abs=0.02)
    cyc = read_exr_passes(tmp_path / "cycles.exr")["Combined"]
    monkeypatch.setattr(device_lights, "point_emission_data", lambda *a: np.zeros(0, np.float32))
    from restircl_blender import engine

    engine._SESSIONS.clear()  # F12 keeps the renderer of an identical scene: the lights must be made anew
    render_to(sc, tmp_path / "means.exr")
    wrong = relmse(read_exr_passes(tmp_path / "means.exr")["Combined"], cyc)
    record_property("relmse_means", wrong)
    print(f"one-white-texel quad, triangles at their means: relMSE {100 * wrong:.3f} %")
    assert wrong > max(1e-2, 5 * err), f"the means are not told apart: relMSE {100 * wrong:.3f} %"
