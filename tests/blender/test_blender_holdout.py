"""Holdout against Cycles: the box of the comparison scene made a holdout three ways (a view layer's collection set
to Holdout, the object's Visibility > Holdout, the Holdout shader) renders as a hole, colour and alpha 0 with the
film opaque or transparent, while its shadow stays; the negative control leaves the box in and must fail. At the
hole's edges the alpha is the pixel's covered share, as Cycles' (its negative control: the same alpha made 0 or 1)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval.blender_scenes import comparison_scene  # noqa: E402

from .test_blender_support import (  # noqa: E402
    cycles_image,
    ensure_registered,
    needs_renderer,
    read_exr_passes,
    relmse,
    render_to,
)

pytestmark = [pytest.mark.blender, needs_renderer]


def holdout_scene(how: str, transparent: bool):
    ensure_registered()
    sc = comparison_scene("mixed", 64, 48)
    sc.render.film_transparent = transparent
    box = bpy.data.objects["Box"]
    if how == "collection":
        col = bpy.data.collections.new("Hold")
        sc.collection.children.link(col)
        sc.collection.objects.unlink(box)
        col.objects.link(box)
        sc.view_layers[0].layer_collection.children["Hold"].holdout = True
    elif how == "object":
        box.is_holdout = True
    else:
        mat = bpy.data.materials.new("Hole")
        mat.use_nodes = True
        tree = mat.node_tree
        tree.nodes.clear()
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        tree.links.new(tree.nodes.new("ShaderNodeHoldout").outputs[0], out.inputs["Surface"])
        box.data.materials.clear()
        box.data.materials.append(mat)
    return sc


def both(tmp_path, how: str, transparent: bool) -> tuple[np.ndarray, np.ndarray]:
    """Cycles' and our image of holdout_scene(how, transparent); Cycles' is shared by the tests of one scene."""
    return both_of(tmp_path, holdout_scene(how, transparent), shared=("holdout", how, transparent))


def both_of(tmp_path, sc, shared: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Cycles' image of `sc` (256 spp, shared under `shared` where given) and ours (the reference method, 64)."""
    cyc = cycles_image(tmp_path, sc, 256, shared=shared)
    sc.render.engine = "RESTIRCL"
    sc.restircl.method = "reference"
    sc.restircl.samples = 64
    render_to(sc, tmp_path / "ours.exr")
    return cyc, read_exr_passes(tmp_path / "ours.exr")["Combined"]


@pytest.mark.parametrize(("how", "transparent"), [("collection", False), ("object", True), ("shader", False)])
def test_holdout_agrees_with_cycles(tmp_path, how, transparent, record_property):
    cyc, ours = both(tmp_path, how, transparent)
    hole = cyc[..., 3] < 0.5
    assert 0.01 < hole.mean() < 0.2, "the box is not a hole in Cycles' image: nothing is tested"
    # alpha 0 only where every sample met the hole: edge pixels may differ, no more
    assert np.mean((ours[..., 3] == 0) != hole) < 0.02
    assert np.all(ours[..., :3][ours[..., 3] == 0] == 0)
    err = relmse(ours, cyc)
    record_property("relmse", err)
    print(f"holdout {how}: relMSE {100 * err:.3f} %")
    assert err < 0.01


def test_holdout_negative_control(tmp_path, monkeypatch):
    from restircl_blender.export import holdout

    monkeypatch.setattr(holdout, "mark", lambda *args: None)
    cyc, ours = both(tmp_path, "collection", False)
    assert relmse(ours, cyc) > 0.01


EDGE_BOUND = 0.02  # relMSE of the alpha over the pixels Cycles gives an alpha strictly between 0 and 1


def alpha_relmse(ours: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((ours - ref) ** 2 / (ref * ref + 1e-2)))


@pytest.mark.parametrize("transparent", [False, True])
def test_holdout_edges_alpha_is_the_covered_share(tmp_path, transparent, record_property):
    cyc, ours = both(tmp_path, "object", transparent)
    edge = (cyc[..., 3] > 0.02) & (cyc[..., 3] < 0.98)
    assert edge.sum() >= 16, "Cycles' hole has no antialiased edge: nothing is tested"
    err = alpha_relmse(ours[..., 3][edge], cyc[..., 3][edge])
    hard = alpha_relmse(np.round(ours[..., 3][edge]), cyc[..., 3][edge])  # negative control: a 0 / 1 alpha
    record_property("edge_alpha_relmse", err)
    print(f"holdout edge alpha (transparent film {transparent}): relMSE {100 * err:.2f} %, 0/1 alpha "
          f"{100 * hard:.1f} %, over {int(edge.sum())} pixels")
    assert err < EDGE_BOUND
    assert hard > EDGE_BOUND
    assert alpha_relmse(ours[..., 3], cyc[..., 3]) < 1e-3  # the rest of the image: opaque where Cycles is
