"""Light and shadow linking against Cycles: the scene of tests/lights/linking_scene.py (a light that lights one object
only and is not shadowed by the plank, a light that excludes that object, an emissive mesh that excludes the plank
and is not shadowed by the fence before it), rendered by Cycles with the same links (restircl.eval.cycles.bridge.
to_bpy writes them as Blender's receiver and blocker collections). Converged agreement of the still estimators with
direct light, and of the path pass with bounces; the negative controls (the kernels built ignoring the blockers, or
the receivers) fail the same bound."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl import Renderer, Settings  # noqa: E402
from restircl.eval.cycles import bridge as cycles  # noqa: E402

from ..bias_controls import built_with  # noqa: E402
from ..lights.linking_scene import linking_scene, rel_mse  # noqa: E402

pytestmark = pytest.mark.blender

BOUND = 0.01  # relMSE, as tests/blender/test_blender_cycles.py


@pytest.fixture(scope="module")
def cycles_direct() -> np.ndarray:
    return cycles.render(cycles.to_bpy(linking_scene(fence=True)), samples=256, seed=1, threads=2).image


def _check(ours: np.ndarray, cyc: np.ndarray, label: str, record_property) -> float:
    err = rel_mse(ours, cyc)
    record_property("relmse", err)
    print(f"{label}: relMSE {100 * err:.4f} %  sum ours/cycles {ours.sum() / cyc.sum():.4f}")
    return err


def test_blender_links_the_lights_as_the_scene_says():
    sc = cycles.to_bpy(linking_scene(fence=True))
    key = bpy.data.objects["key"].light_linking
    states = {e.name: c.light_linking.link_state
              for e, c in zip(key.receiver_collection.objects, key.receiver_collection.collection_objects,
                              strict=True)}
    assert states == {"floor_a": "INCLUDE"}
    assert [o.name for o in key.blocker_collection.objects] == ["plank"]
    assert bpy.data.objects["glow"].light_linking.receiver_collection.collection_objects[0].light_linking.link_state \
        == "EXCLUDE"
    assert sc.camera is not None


@pytest.mark.parametrize("method", ["reference", "ris", "restir"])
def test_linked_lights_agree_with_cycles(method, cycles_direct, record_property):
    r = Renderer(linking_scene(fence=True), Settings(method=method, seed=2))
    ours = r.render_still(0, samples=256).color[..., :3]
    assert _check(ours, cycles_direct, method, record_property) < BOUND


@pytest.mark.parametrize("control", ["TEST_LINKING_WITHOUT_BLOCKERS", "TEST_LINKING_WITHOUT_RECEIVERS"])
def test_links_ignored_fail_the_agreement(monkeypatch, control, cycles_direct, record_property):
    built_with(monkeypatch, control)
    r = Renderer(linking_scene(fence=True), Settings(method="ris", seed=2))
    ours = r.render_still(0, samples=256).color[..., :3]
    assert _check(ours, cycles_direct, control, record_property) > BOUND


def test_linked_lights_with_bounces_agree_with_cycles(record_property):
    sc = linking_scene(fence=True)
    st = Settings(method="ris", seed=2, max_bounces=2)
    cyc = cycles.render(cycles.to_bpy(sc), samples=1024, seed=1, threads=2, paths=st).image
    ours = Renderer(sc, st).render_still(0, samples=512).color[..., :3]
    assert _check(ours, cyc, "paths, 2 bounces", record_property) < BOUND


@pytest.mark.parametrize("settings", [dict(method="ris", light_tiles="on", still_method="as_set"),
                                      dict(method="ris", light_proposal="tree", still_method="as_set"),
                                      dict(method="restir", light_tiles="on", light_proposal="tree"),
                                      dict(method="ris", bsdf_mis_sample=True, still_method="as_set"),
                                      dict(method="ris", bsdf_sampling="on", bsdf_candidates=2, still_method="as_set")],
                         ids=["ris_tiles", "ris_tree", "restir_tree", "bsdf_mis_sample", "bsdf_candidates"])
def test_every_light_pick_honours_the_links(settings, cycles_direct, record_property):
    """Tiles, the tree, and the BSDF strategies, whose rays must leave the panel (its shadows linked: the fence
    does not block it) to light sampling (0.3 % too bright with the BSDF MIS sample when they did not)."""
    r = Renderer(linking_scene(fence=True), Settings(seed=3, **settings))
    ours = r.render_still(0, samples=256).color[..., :3]
    assert "light_linking" in r.features
    assert _check(ours, cycles_direct, str(settings), record_property) < BOUND
    assert ours.sum() / cycles_direct.sum() == pytest.approx(1.0, abs=0.002)
