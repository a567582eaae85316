"""Objects hidden from the camera against Cycles: the box of the comparison scene with Ray Visibility > Camera off,
or in a view layer's Indirect Only collection, is not seen while its shadow stays; the negative control shows it."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval.blender_scenes import comparison_scene  # noqa: E402

from .test_blender_support import assert_agrees, cycles_and_ours, ensure_registered, needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


def hidden_box_scene(how: str):
    ensure_registered()
    sc = comparison_scene("mixed", 64, 48)
    box = bpy.data.objects["Box"]
    if how == "ray_visibility":
        box.visible_camera = False
    else:
        col = bpy.data.collections.new("Indirect")
        sc.collection.children.link(col)
        sc.collection.objects.unlink(box)
        col.objects.link(box)
        sc.view_layers[0].layer_collection.children["Indirect"].indirect_only = True
    return sc


@pytest.mark.parametrize("how", ["ray_visibility", "indirect_only"])
def test_a_hidden_object_agrees_with_cycles(tmp_path, how, record_property):
    assert_agrees(tmp_path, hidden_box_scene(how), 256, 64, f"box hidden from the camera ({how})", record_property,
                  shared=(how,))


def test_camera_visibility_negative_control(tmp_path, monkeypatch):
    from restircl_blender.export import camera_visibility

    monkeypatch.setattr(camera_visibility, "mark", lambda *args: None)
    err, _ = cycles_and_ours(tmp_path, hidden_box_scene("ray_visibility"), 256, 64, "box seen after all",
                             ("ray_visibility",))
    assert err > 0.01
