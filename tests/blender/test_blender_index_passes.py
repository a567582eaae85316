"""Object Index and Material Index through the add-on: the view layer's toggles (use_pass_object_index,
use_pass_material_index) register the passes under Blender's names, and an F12 render writes each object's and
material's Pass Index where it shows, as Cycles' own passes do (compared away from the objects' edges, where the
two renderers' one sample per pixel may fall on either side)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_light_passes import _addon  # noqa: E402, F401  (autouse: the engine's crashes fail the test)
from .test_blender_support import needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


def objects_scene():
    """A floor, a red box and a grey ball under an area light (also the Cryptomatte tests' scene): the scene, its
    objects and its materials by name."""
    sc = scenes.new_scene(40, 28, engine="RESTIRCL")
    mats = {"Grey": scenes.diffuse_material("Grey", (0.8, 0.8, 0.8)),
            "Red": scenes.principled_material("Red", (0.8, 0.2, 0.2))}
    obs = {"Floor": scenes.quad("Floor", 10.0, 10.0, mats["Grey"]),
           "Box": scenes.box("Box", (1.2, 1.2, 1.2), mats["Red"], location=(0.3, 0, 0.6)),
           "Ball": scenes.uv_sphere("Ball", 0.5, material=mats["Grey"], location=(-1.3, 0.2, 0.5))}
    scenes.light("AREA", "Key", (1.0, -1.0, 3.0), energy=100.0, size=1.0)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    return sc, obs, mats


def ours_then_cycles(sc, tmp_path, samples: int):
    """F12 of `sc` with restircl into tmp_path/ours.exr, then with Cycles (`samples`) into tmp_path/cycles.exr."""
    render_to(sc, tmp_path / "ours.exr")
    sc.render.engine = "CYCLES"
    sc.cycles.samples = samples
    render_to(sc, tmp_path / "cycles.exr")


def _scene():
    sc, obs, mats = objects_scene()
    obs["Floor"].pass_index, obs["Box"].pass_index, obs["Ball"].pass_index = 2, 5, 9
    mats["Grey"].pass_index, mats["Red"].pass_index = 1, 4
    vl = sc.view_layers[0]
    vl.use_pass_object_index = vl.use_pass_material_index = True
    sc.restircl.samples = 2
    return sc


def _names(version) -> tuple[str, str]:
    return ("Object Index", "Material Index") if version >= (5, 0, 0) else ("IndexOB", "IndexMA")


def test_f12_index_passes_agree_with_cycles(tmp_path):
    ours_then_cycles(_scene(), tmp_path, 1)
    ours, cyc = read_exr_passes(tmp_path / "ours.exr"), read_exr_passes(tmp_path / "cycles.exr")
    for name in _names(bpy.app.version):
        a, b = ours[name][..., 0], cyc[name][..., 0]
        # away from edges: the pixel and its four neighbours agree in Cycles' pass
        pad = np.pad(b, 1, mode="edge")
        inner = np.all([pad[1 + dy:1 + dy + b.shape[0], 1 + dx:1 + dx + b.shape[1]] == b
                        for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))], axis=0)
        assert inner.mean() > 0.7
        np.testing.assert_array_equal(a[inner], b[inner])
    assert set(np.unique(ours[_names(bpy.app.version)[0]]).tolist()) == {0.0, 2.0, 5.0, 9.0}
    assert set(np.unique(ours[_names(bpy.app.version)[1]]).tolist()) == {0.0, 1.0, 4.0}


def test_no_toggle_no_pass(tmp_path):
    sc = _scene()
    vl = sc.view_layers[0]
    vl.use_pass_object_index = vl.use_pass_material_index = False
    render_to(sc, tmp_path / "ours.exr")
    assert not set(_names(bpy.app.version)) & set(read_exr_passes(tmp_path / "ours.exr"))
