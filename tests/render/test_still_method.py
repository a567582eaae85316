"""The still estimator (render/still_method.py): which settings a still render of each kind of scene gets, that the
user's choice overrides the rule, that the methods without reuse are left as set, and that the CLI's still mode
uses it while its animation mode and Renderer.render_still take the settings as given. (The estimators it picks
are tested for unbiasedness where they are defined: RIS in render/test_estimators.py, spatial-only ReSTIR in
render/test_restir.py's "spatial" configuration, BSDF candidates and the BSDF MIS sample in
render/test_bsdf_candidates.py and environment/test_estimators.py.)"""

from __future__ import annotations

import pytest
from restircl import (
    Camera,
    Environment,
    Light,
    Material,
    Mesh,
    Scene,
    SettingError,
    Settings,
    look_at,
    scenes,
    still_settings,
    translation,
)
from restircl.cli.main import main
from restircl.render.still_method import (
    BOUNCED_CANDIDATES,
    FEW_LIGHTS,
    FEW_LIGHTS_CANDIDATES,
    ONE_LIGHT_CANDIDATES,
    OVERRIDES,
    SUNNY_CANDIDATES,
    scene_kind,
)
from restircl.scenes.hdri_sky import sky_map
from restircl.settings.table import METHODS, STILL_METHODS


def _scene(light_types: tuple[str, ...] = (), emissive: bool = False) -> Scene:
    """A floor under the given analytic lights, and an emissive quad over it when `emissive`."""
    fv, ft = scenes.quad(4, 4)
    meshes = [Mesh("floor", fv, ft, 0)]
    materials = [Material("floor", (0.8, 0.8, 0.8))]
    if emissive:
        lv, lt = scenes.quad(0.5, 0.5)
        meshes.append(Mesh("lamp", lv + (0.0, 0.0, 1.0), lt, 1))
        materials.append(Material("lamp", (0, 0, 0), (1.0, 1.0, 1.0), 4.0))
    lights = [Light(f"{t}{i}", t, (1, 1, 1), 50.0, translation(0, 0, 2)) for i, t in enumerate(light_types)]
    cam = Camera(look_at((0.0, -3.0, 2.0), (0.0, 0.0, 0.0)), 16, 12)
    return Scene(meshes, materials, lights, cam)


KINDS = {
    "mesh_lights": _scene(("point",), emissive=True),
    "analytic_lights": _scene(("point", "spot", "sun", "area")),
}


# What `auto` must choose for each kind, written out (not read from the rule's tables): the settings that differ
# from the defaults. Emissive meshes: RIS with BSDF candidates, the default candidate count; four analytic light
# objects (no more than the few-lights limit, 16) under the Sobol sampler: RIS over 2 candidates.
EXPECTED = {
    "mesh_lights": {"method": "ris", "bsdf_sampling": "on"},
    "analytic_lights": {"method": "ris", "candidates": 2},
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_auto_replaces_restir_by_the_rule_of_the_scene_kind(kind):
    scene = KINDS[kind]
    assert scene_kind(scene) == kind
    got = still_settings(Settings(), scene)
    changed = {n: getattr(got, n) for n in Settings.names() if getattr(got, n) != getattr(Settings(), n)}
    assert changed == EXPECTED[kind]


def test_auto_leaves_the_methods_without_reuse_and_an_explicit_bsdf_choice_alone():
    scene = KINDS["mesh_lights"]
    for method in METHODS:
        if method != "restir":
            s = Settings(method=method, candidates=5)
            assert still_settings(s, scene) == s
    off = still_settings(Settings(bsdf_sampling="off"), scene)
    assert off.bsdf_sampling == "off"


def test_the_user_overrides_the_rule():
    """An explicit still method replaces the rule: `ris` sets the method alone, `restir_spatial` ReSTIR without
    temporal reuse; `as_set` changes nothing; the user's other settings are kept."""
    scene = KINDS["analytic_lights"]
    assert still_settings(Settings(still_method="as_set"), scene) == Settings(still_method="as_set")
    expected = {"ris": {"method": "ris"}, "restir_spatial": {"method": "restir", "temporal": False}}
    assert set(OVERRIDES) == set(expected)
    base = Settings(method="uniform", candidates=6, spatial_neighbours=2)
    for choice, want in expected.items():
        s = Settings(**{**base.__dict__, "still_method": choice})
        got = still_settings(s, scene)
        changed = {n: getattr(got, n) for n in Settings.names() if getattr(got, n) != getattr(s, n)}
        assert changed == want, choice


def test_auto_adds_the_bsdf_mis_sample_under_a_sunny_world_only():
    """A world with a sun (0.68 of its power in a 1.6-degree disc) gets the BSDF MIS sample and, where the
    candidates are at their default, 4 of them; a sky without a sun, a constant world, and a user's own candidate
    count or BSDF sampling off are left alone."""
    from restircl.environment.sun import SUNNY_SHARE, sun_share

    sunny, grey = _scene(("point",)), _scene(("point",))
    sunny.environment = Environment("sunny", color=(1, 1, 1), image=sky_map(128, 256))
    grey.environment = Environment("grey", color=(1, 1, 1), image=sky_map(128, 256, sun_scale=0.0))
    assert sun_share(sunny.environment) > SUNNY_SHARE > sun_share(grey.environment)
    got = still_settings(Settings(), sunny)
    assert got.method == "ris" and got.bsdf_mis_sample and got.candidates == SUNNY_CANDIDATES
    assert still_settings(Settings(candidates=6), sunny).candidates == 6
    assert not still_settings(Settings(bsdf_sampling="off"), sunny).bsdf_mis_sample
    # one light object under a world: the Sobol sampler's few-lights rule; alone: its one-light rule
    for scene, candidates in ((grey, FEW_LIGHTS_CANDIDATES), (_scene(("point",)), ONE_LIGHT_CANDIDATES)):
        got = still_settings(Settings(), scene)
        assert not got.bsdf_mis_sample and got.candidates == candidates
    constant = _scene(("point",))
    constant.environment = Environment("constant", color=(0.5, 0.5, 0.5))
    assert not still_settings(Settings(), constant).bsdf_mis_sample


def test_a_world_alone_gets_one_candidate_and_the_cumulative_table():
    """The world as the only light: with the Sobol sampler one light candidate (beside the BSDF MIS sample under a
    sun), drawn from the world's cumulative table (its inversion keeps the strata); with random numbers a sunny
    world's 4 and a grey world's default; a renderer whose frames are ReSTIR's keeps the default table."""
    from restircl import Renderer
    from restircl.lights import environment

    alone, grey = _scene(), _scene()
    alone.environment = Environment("sunny", color=(1, 1, 1), image=sky_map(64, 128))
    grey.environment = Environment("grey", color=(1, 1, 1), image=sky_map(64, 128, sun_scale=0.0))
    got = still_settings(Settings(), alone)
    assert got.method == "ris" and got.bsdf_mis_sample and got.candidates == ONE_LIGHT_CANDIDATES
    assert still_settings(Settings(sampler="random"), alone).candidates == SUNNY_CANDIDATES
    assert still_settings(Settings(candidates=3), alone).candidates == 3
    got_grey = still_settings(Settings(), grey)
    assert not got_grey.bsdf_mis_sample and got_grey.candidates == ONE_LIGHT_CANDIDATES
    assert still_settings(Settings(sampler="random"), grey).candidates == Settings.candidates
    tables = {}
    for name, s in (("still", got), ("restir", Settings())):
        r = Renderer(alone, s)
        packed = r.device_scene.lights.environment
        assert packed is not None
        tables[name] = packed.kind
        img = r.render_still(0, 4).color
        assert (img[..., :3] > 0).any() and bool(img[..., :3].min() >= 0)
    assert tables == {"still": "cdf", "restir": environment.TABLE_KIND}


def test_still_method_is_validated():
    assert set(STILL_METHODS) == {"auto", "as_set", *OVERRIDES}
    with pytest.raises(SettingError):
        Settings(still_method="fastest").validate()


def test_cli_still_mode_uses_the_still_estimator_and_animation_mode_does_not(tmp_path, capsys):
    path = tmp_path / "box.npz"
    assert main(["save-scene", "cornell_box", str(path), "--width", "16", "--height", "16"]) == 0
    capsys.readouterr()
    assert main(["render", str(path), "--frames", "2", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    picked = still_settings(Settings(), Scene.load(path))
    assert f"still method: {picked.method}" in out
    assert main(["render", str(path), "--frames", "2", "--still-method", "as_set", "--out", str(tmp_path)]) == 0
    assert "still method: restir (temporal, spatial reuse) BSDF sampling auto, as set" in capsys.readouterr().out
    assert main(["render", str(path), "--frames", "2", "--mode", "animation", "--out", str(tmp_path)]) == 0
    assert "still method" not in capsys.readouterr().out


def test_auto_takes_few_candidates_with_the_sobol_sampler_on_few_light_objects():
    few = KINDS["analytic_lights"]  # four light objects
    many = _scene(("point",) * (FEW_LIGHTS + 1))
    assert still_settings(Settings(), few).candidates == FEW_LIGHTS_CANDIDATES
    assert still_settings(Settings(sampler="sobol"), few).candidates == FEW_LIGHTS_CANDIDATES
    assert still_settings(Settings(sampler="random"), few).candidates == Settings().candidates
    assert still_settings(Settings(), many).candidates == Settings().candidates
    assert still_settings(Settings(), KINDS["mesh_lights"]).candidates == Settings().candidates
    # a user's own candidate count, and an explicit still method, keep the candidates as set
    assert still_settings(Settings(candidates=6), few).candidates == 6
    assert still_settings(Settings(still_method="ris"), few).candidates == Settings().candidates


def test_with_bounces_the_few_lights_and_sunny_rules_take_one_candidate():
    """Max Bounces > 0: the rules that lower the candidates (few light objects, a sunny world) lower them to
    BOUNCED_CANDIDATES where there are at most FEW_LIGHTS light objects; many light objects and emissive meshes
    without a sun keep the default, a sunny world over many lamps its SUNNY_CANDIDATES, and so do a user's own count
    and the random sampler."""
    few = KINDS["analytic_lights"]
    sunny, sunny_many = _scene(("point",) * FEW_LIGHTS), _scene(("point",) * (FEW_LIGHTS + 1))
    sunny_many.environment = Environment("sunny", color=(1, 1, 1), image=sky_map(128, 256))
    sunny.environment = Environment("sunny", color=(1, 1, 1), image=sky_map(128, 256))
    bounced = Settings(max_bounces=4)
    assert BOUNCED_CANDIDATES < FEW_LIGHTS_CANDIDATES < SUNNY_CANDIDATES
    assert still_settings(bounced, few).candidates == BOUNCED_CANDIDATES
    assert still_settings(bounced, sunny).candidates == BOUNCED_CANDIDATES
    assert still_settings(Settings(max_bounces=0), sunny).candidates == SUNNY_CANDIDATES
    assert still_settings(bounced, sunny_many).candidates == SUNNY_CANDIDATES
    assert still_settings(bounced, _scene(("point",) * (FEW_LIGHTS + 1))).candidates == Settings().candidates
    assert still_settings(bounced, KINDS["mesh_lights"]).candidates == Settings().candidates
    assert still_settings(Settings(max_bounces=4, candidates=3), few).candidates == 3
    assert still_settings(Settings(max_bounces=4, sampler="random"), sunny).candidates == SUNNY_CANDIDATES


def test_auto_takes_one_candidate_on_one_light_object():
    one = _scene(("area",))
    assert still_settings(Settings(), one).candidates == ONE_LIGHT_CANDIDATES
    assert still_settings(Settings(sampler="random"), one).candidates == Settings().candidates
    assert still_settings(Settings(candidates=3), one).candidates == 3
