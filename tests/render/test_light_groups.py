"""Light groups (Scene.light_groups; opencl/film/light_groups.h): each group's pass holds the light of its emitters
(seen by the camera, direct and bounced), so that where every emitter is in a group the passes add up to Combined
(to float rounding), for every still estimator, with bounces and with light linking, and in animation frames to the
frame's sample; each group's pass converges to a render of that group's emitters alone (the other group's lights
taken out, its emissive panel black), which checks that every contribution goes to the right group."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Material, Renderer, Settings
from restircl.environment.world import Environment
from restircl.lights.light_groups import light_group_count
from restircl.scene.errors import SceneError

from ..lights.linking_scene import linking_scene

# the emissive panel in the second group: a group index read as 0 anywhere would put its light in the first
GROUPS = {"cool": ("fill", "World"), "warm": ("key", "glow")}


def grouped_scene(linked: bool = False, only: str | None = None, world: bool = True):
    sc = linking_scene(linked=linked)
    sc.light_groups = list(GROUPS)
    if world:
        sc.environment = Environment(color=(0.05, 0.1, 0.2), lightgroup="cool")
    for name, members in GROUPS.items():
        for part in (*sc.lights, *sc.meshes):
            if part.name in members:
                part.lightgroup = name
    if only is not None:  # the other group's emitters out
        sc.lights = [lt for lt in sc.lights if lt.lightgroup == only]
        if "glow" not in GROUPS[only]:  # the panel black, as its material is but for its emission
            sc.materials[1] = Material(name="off", albedo=(0.0, 0.0, 0.0))
        if sc.environment is not None and sc.environment.lightgroup != only:
            sc.environment = None
    return sc


@pytest.mark.parametrize("method,bounces,linked", [("reference", 0, False), ("ris", 2, False), ("restir", 1, True),
                                                    ("ris", 1, True)])
def test_the_groups_add_up_to_combined(method, bounces, linked):
    f = Renderer(grouped_scene(linked), Settings(method=method, seed=1, max_bounces=bounces)).render_still(
        0, samples=8)
    assert f.light_groups is not None and set(f.light_groups) == set(GROUPS)
    total = f.light_groups["warm"] + f.light_groups["cool"]
    combined = f.color[..., :3]
    assert np.abs(total - combined).max() <= 2e-6 * max(1.0, float(combined.max()))
    assert f.light_groups["warm"].mean() > 0.02 and f.light_groups["cool"].mean() > 0.02  # both groups light it


def test_animation_frames_split_their_sample():
    r = Renderer(grouped_scene(), Settings(method="restir", seed=1, max_bounces=1))
    assert not r.settings.gi_reuse  # the groups' bounced light comes from the path pass (render/light_passes.py)
    for k in range(2):
        f = r.render_frame(0)
        assert f.light_groups is not None
        assert np.abs(f.light_groups["warm"] + f.light_groups["cool"] - f.noisy).max() < 2e-6, k


def test_an_emitter_outside_the_groups_counts_in_none():
    sc = grouped_scene()
    sc.lights[1].lightgroup = "elsewhere"  # fill: a group the scene does not list
    f = Renderer(sc, Settings(method="reference", seed=1)).render_still(0, samples=8)
    missing = f.color[..., :3] - f.light_groups["warm"] - f.light_groups["cool"]
    alone = Renderer(grouped_scene(only="cool", world=False), Settings(method="reference", seed=1)).render_still(
        0, samples=8).color[..., :3]
    assert missing.mean() == pytest.approx(alone.mean(), rel=0.05)  # fill's light, in no pass


@pytest.mark.parametrize("method", ["ris", "restir"])
def test_each_group_converges_to_its_emitters_alone(method):
    st = Settings(method=method, seed=3, max_bounces=1)
    f = Renderer(grouped_scene(linked=True), st).render_still(0, samples=96)
    for group in GROUPS:
        alone = Renderer(grouped_scene(linked=True, only=group), Settings(method="reference", seed=4,
                                                                          max_bounces=1)).render_still(
            0, samples=96).color[..., :3]
        print(f"{method} {group}: pass mean {f.light_groups[group].mean():.5f}, alone {alone.mean():.5f}")
        assert f.light_groups[group].mean() == pytest.approx(alone.mean(), rel=0.02)


def test_group_names_are_checked():
    sc = grouped_scene()
    sc.light_groups = ["a", "a"]
    with pytest.raises(SceneError, match="twice"):
        light_group_count(sc)
    sc.light_groups = [f"g{k}" for k in range(33)]
    with pytest.raises(SceneError, match="at most"):
        light_group_count(sc)


def test_the_scene_file_keeps_the_groups(tmp_path):
    from restircl import Scene
    from restircl.scene.file import load_scene, save_scene

    sc = grouped_scene()
    save_scene(sc, tmp_path / "groups.npz")
    back = load_scene(tmp_path / "groups.npz", Scene)
    assert back.light_groups == ["cool", "warm"]
    assert [lt.lightgroup for lt in back.lights] == ["warm", "cool"]
    assert [m.lightgroup for m in back.meshes] == ["", "", "", "warm"]
    assert back.environment is not None and back.environment.lightgroup == "cool"
