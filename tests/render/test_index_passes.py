"""The Object Index and Material Index passes (render/index_passes.py): each pixel holds the pass index of the
object and of the material its camera ray hit, 0 where it hit nothing, for stills and animation frames; checked
against which object the G-buffer says each pixel shows (the object ids it carries), and the names and channels of
the passes (Cycles' IndexOB / IndexMA, "Object Index" / "Material Index" since Blender 5.0)."""

from __future__ import annotations

import numpy as np
from restircl import Renderer, Settings
from restircl.render.passes import PASSES, blender_name

from ..lights.linking_scene import linking_scene


def _scene():
    sc = linking_scene(linked=True)  # the object ids carry light sets in their high bits: masked off
    for k, m in enumerate(sc.meshes):
        m.pass_index = 10 + 5 * k  # floor_a 10, floor_b 15, plank 20, glow 25
    sc.materials[0].pass_index = 3
    sc.materials[1].pass_index = 7
    return sc


def test_each_pixel_holds_the_pass_index_of_what_it_shows():
    sc = _scene()
    r = Renderer(sc, Settings(method="ris", seed=1))
    for still in (True, False):
        f = r.render_still(0, samples=2) if still else r.render_frame(0)
        g = r.read_gbuffer()
        hit = g["normal"][..., 3].view(np.int32) >= 0
        obj = np.where(hit, g["albedo"][..., 3].view(np.int32) & 0xFFFFF, -1)
        want_ob = np.where(hit, 10 + 5 * obj, 0)
        want_ma = np.where(hit, np.where(obj == 3, 7, 3), 0)  # the panel (object 3) has material 1
        # a still's passes come from its last frame, whose jitter may differ from this G-buffer's at an edge
        pad = np.pad(obj, 1, mode="edge")
        inner = np.ones(obj.shape, bool) if not still else np.all(
            [pad[1 + dy:1 + dy + obj.shape[0], 1 + dx:1 + dx + obj.shape[1]] == obj
             for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0))], axis=0)
        assert f.object_index is not None and f.material_index is not None
        assert f.object_index.dtype == np.float32 and f.object_index.shape == (sc.camera.height, sc.camera.width)
        np.testing.assert_array_equal(f.object_index[inner], want_ob[inner])
        np.testing.assert_array_equal(f.material_index[inner], want_ma[inner])
        assert inner.mean() > 0.8
        assert set(np.unique(f.object_index).tolist()) == {0.0, 10.0, 15.0, 20.0, 25.0}  # every object and the miss


def test_pass_names():
    by_attr = {p.attr: p for p in PASSES}
    for attr, old, new in (("object_index", "IndexOB", "Object Index"), ("material_index", "IndexMA",
                                                                          "Material Index")):
        p = by_attr[attr]
        assert p.channels == "X" and p.blender_type == "VALUE"
        assert blender_name(p, (4, 2, 0)) == old and blender_name(p, (5, 0, 1)) == new
