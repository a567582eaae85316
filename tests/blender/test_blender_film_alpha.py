"""A transparent film's alpha at an object's edge against the world (the comparison scene's box and lamp without
the room), against Cycles: a still's alpha is the share
of the pixel's samples whose camera ray met a surface (opencl/still/holdout.cl counts the misses), as Cycles'
antialiased alpha; its negative control is the same alpha rounded to 0 or 1, what the last sample's depth gave."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval.blender_scenes import comparison_scene  # noqa: E402

from .test_blender_holdout import EDGE_BOUND, alpha_relmse, both_of  # noqa: E402
from .test_blender_support import ensure_registered, needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


def test_transparent_film_edges_alpha_is_the_covered_share(tmp_path, record_property):
    ensure_registered()
    sc = comparison_scene("mixed", 64, 48)
    sc.render.film_transparent = True
    for name in ("Floor", "Wall"):  # the box and the lamp against the world
        bpy.data.objects.remove(bpy.data.objects[name])
    cyc, ours = (img[..., 3] for img in both_of(tmp_path, sc))
    edge = (cyc > 0.02) & (cyc < 0.98)
    assert edge.sum() >= 16, "Cycles' image has no antialiased edge against the world: nothing is tested"
    assert 0.05 < np.mean(cyc < 0.02) < 0.99, "no world seen, or nothing else: nothing is tested"
    err = alpha_relmse(ours[edge], cyc[edge])
    hard = alpha_relmse(np.round(ours[edge]), cyc[edge])  # negative control: a 0 / 1 alpha
    record_property("edge_alpha_relmse", err)
    print(f"transparent film edge alpha: relMSE {100 * err:.2f} %, 0/1 alpha {100 * hard:.1f} %, "
          f"over {int(edge.sum())} pixels")
    assert err < EDGE_BOUND
    assert hard > EDGE_BOUND
    assert alpha_relmse(ours, cyc) < 1e-3
