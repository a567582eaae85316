"""The validation kind `user` of `restircl compare` (restircl/eval/scenes/user_scene.py): a typical user's scene
built in Blender and exported by the add-on without warnings, with what the issue names (Principled glossy, metal
and textured materials, an HDRI world, 43 lights of every Blender type), the same for our side and Cycles'; and the
Cycles variants of `restircl compare` (eval/cycles/compare.py CYCLES) change the scene's Cycles settings for their
renders only."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")
from restircl.eval.cycles import compare as C  # noqa: E402
from restircl.eval.scenes import kinds as K  # noqa: E402
from restircl.eval.scenes import user_scene as U  # noqa: E402
from restircl.materials.textures import is_texture  # noqa: E402

pytestmark = pytest.mark.blender


def test_user_scene_has_what_the_issue_names():
    scene, sc = U.user_scene(48, 27)
    assert "user" in K.KINDS and (scene.camera.width, scene.camera.height) == (48, 27)
    types = [lt.type for lt in scene.lights]
    assert len(types) == 43
    assert {t: types.count(t) for t in set(types)} == {"sun": 1, "area": 4, "spot": 10, "point": 28}
    assert {lt.shape for lt in scene.lights if lt.type == "area"} == {"SQUARE", "RECTANGLE", "DISK", "ELLIPSE"}
    env = scene.environment
    assert env is not None and env.image is not None and env.strength == pytest.approx(U.WORLD_STRENGTH)
    mats = {m.name: m for m in scene.materials}
    assert is_texture(mats["Floor"].albedo) and is_texture(mats["Wall"].albedo)
    assert is_texture(mats["Lacquer"].roughness)
    assert float(mats["Gold"].metallic) == 1.0 and float(mats["Steel"].metallic) == 1.0
    assert float(mats["BlueGloss"].roughness) == pytest.approx(0.15) and float(mats["BlueGloss"].specular) > 0
    # Cycles renders the very bpy scene the add-on exported: its lights and world are there
    assert sum(ob.type == "LIGHT" for ob in sc.objects) == 43 and sc.world.node_tree.nodes.get("Environment Texture")


def test_scene_pair_gives_the_user_kind_as_blender_has_it():
    scene, sc = C.scene_pair("user", 32, 18)
    assert scene.name == "user" and sc.render.resolution_x == 32
    assert len(K.scene_of_kind("user", 32, 18).lights) == 43


def test_cycles_variant_switches_its_setting_for_its_renders_only():
    _, sc = C.scene_pair("studio", 32, 18)
    assert sc.cycles.use_light_tree
    with C.cycles_variant(sc, "cycles_no_tree"):
        assert not sc.cycles.use_light_tree
    assert sc.cycles.use_light_tree
    with C.cycles_variant(sc, "cycles"):
        assert sc.cycles.use_light_tree
    assert set(C.CYCLES) <= set(C.ALL_METHODS)


def test_reference_key_is_the_same_in_another_process(tmp_path):
    # Blender lists a mesh's loop triangles in another order in each process (the spheres' here): the reference's
    # key (eval/report/reference.py) is taken of the scene's canonical form and its probe rendered from it, so a
    # second process finds the first one's reference
    import os
    import subprocess
    import sys

    code = ("import sys\n"
            "from restircl.eval.report.reference import get_reference\n"
            "from restircl.eval.scenes.user_scene import user_scene\n"
            "r = get_reference(user_scene(16, 9)[0], 0, frames=2, cache_dir=sys.argv[1], log=print)\n"
            "print('PATH', r.path)\n")
    runs = [subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True,
                           env=dict(os.environ), check=True).stdout for _ in range(2)]
    paths = [next(line for line in out.splitlines() if line.startswith("PATH")) for out in runs]
    assert "reference: saved" in runs[0] and "reference: cached" in runs[1], runs
    assert paths[0] == paths[1]
