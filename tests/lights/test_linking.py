"""Light and shadow linking (lights/linking.py, opencl/lights/linking.h): the light sets of a scene's objects and the
masks of its emitters as Blender's rules give them (written out by hand here), how they are packed for the device,
that a scene without links compiles none of it, and that the renderer honours them: the light a linked emitter adds
to each object of the scene in linking_scene.py, measured region by region against renders of the same scene with
that emitter taken out or the plank removed."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Scene, Settings
from restircl.lights import linking
from restircl.lights.device_lights import scene_lights
from restircl.scene.errors import SceneError
from restircl.scene.file import load_scene, save_scene
from restircl.scene.linking import Linking

from .linking_scene import linking_scene, quad

ALL = linking.ALL_SETS


def _scene(*links: Linking, names=("a", "b", "c")) -> Scene:
    from restircl import Light

    meshes = [quad(n, 0, 1, 0, 1, 0) for n in names]
    return Scene(meshes=meshes, lights=[Light(f"l{i}", "point", linking=lk) for i, lk in enumerate(links)])


def test_sets_and_masks_follow_blenders_rules():
    sc = _scene(Linking(receivers={"a": "INCLUDE"}),  # only a
                Linking(receivers={"b": "EXCLUDE"}),  # all but b
                Linking(receivers={"a": "INCLUDE", "c": "EXCLUDE"}),  # an INCLUDE makes it exclusive: only a
                Linking(blockers={"c": "INCLUDE"}),  # only c shadows it
                Linking())
    sets = linking.link_sets(sc)
    # a is named INCLUDE, -, INCLUDE: set 1; b named -, EXCLUDE, -: set 2; c named -, -, EXCLUDE: set 3
    assert sets.receiver_set.tolist() == [1, 2, 3]
    assert sets.blocker_set.tolist() == [0, 0, 1]
    recv = [m[0] for m in sets.light_masks]
    block = [m[1] for m in sets.light_masks]
    assert recv[0] == 0b0010  # set 1 only; not the default set 0
    assert recv[1] == ALL & ~0b0100  # all but b's set 2
    assert recv[2] == 0b0010
    assert recv[3] == recv[4] == ALL  # no receiver links: every set
    assert block[3] == 0b10 and block[0] == block[4] == ALL
    assert sets.mesh_masks == [(ALL, ALL)] * 3


def test_more_sets_than_cycles_allows_are_refused():
    names = [f"m{k}" for k in range(70)]
    # each object named by a different subset of 7 lights' EXCLUDE lists: 70 signatures
    links = [Linking(receivers={n: "EXCLUDE" for k, n in enumerate(names) if (k + 1) >> j & 1}) for j in range(7)]
    with pytest.raises(SceneError, match="at most 64"):
        linking.link_sets(_scene(*links, names=names))


def test_link_records_in_the_light_buffer():
    sc = linking_scene()
    ds_lights = scene_lights(sc, 0)
    flags = ds_lights.records.view(np.uint32).reshape(-1, 16)[:, 15]
    index = flags >> linking.LINK_SHIFT
    data = ds_lights.device_array().view(np.uint32).reshape(-1, 16)
    key, fill = index[0], index[1]
    assert key and fill and key != fill  # two different link records
    sets = linking.link_sets(sc)
    a, b, plank = sets.receiver_set.tolist()[:3]
    recv_key = int(data[key, 0]) | int(data[key, 1]) << 32
    block_key = int(data[key, 2]) | int(data[key, 3]) << 32
    assert recv_key == 1 << a  # floor_a alone
    assert not block_key >> int(sets.blocker_set[2]) & 1 and block_key & 1  # the plank does not shadow it, the rest do
    assert flags[0] & linking.FLAG_SHADOW_LINKED and not flags[1] & linking.FLAG_SHADOW_LINKED
    recv_fill = int(data[fill, 0]) | int(data[fill, 1]) << 32
    assert not recv_fill >> a & 1 and recv_fill >> b & 1 and recv_fill >> plank & 1
    glow = index[2:]  # the emissive panel's two triangles share one record that leaves the plank out
    assert len(set(glow.tolist())) == 1 and glow[0] not in (0, key, fill)


def test_scenes_without_links_compile_none_of_it():
    plain = Renderer(linking_scene(linked=False), Settings(method="ris"))
    assert not plain.flags["HAS_LIGHT_LINKING"]
    assert not np.any(plain.device_scene.lights.records.view(np.uint32).reshape(-1, 16)[:, 15] >> linking.LINK_SHIFT)
    assert not np.any(plain.device_scene.lights.data)  # no link records
    assert Renderer(linking_scene(), Settings(method="ris")).flags["HAS_LIGHT_LINKING"]


def _objects(r: Renderer) -> np.ndarray:
    """Object id of each pixel of the renderer's last G-buffer; -1 at misses and at pixels beside another object
    (their samples' jitter reaches it)."""
    g = r.read_gbuffer()
    obj = np.where(g["normal"][..., 3].view(np.int32) >= 0, g["albedo"][..., 3].view(np.int32) & 0xFFFFF, -1)
    pad = np.pad(obj, 1, mode="edge")
    same = np.ones(obj.shape, bool)
    for dy, dx in ((0, 1), (2, 1), (1, 0), (1, 2)):
        same &= pad[dy:dy + obj.shape[0], dx:dx + obj.shape[1]] == obj
    return np.where(same, obj, -1)


def _render(sc: Scene, samples: int = 128) -> tuple[np.ndarray, Renderer]:
    r = Renderer(sc, Settings(method="reference", seed=3))
    return r.render_still(0, samples=samples).color[..., :3].mean(axis=-1), r


def _without(sc: Scene, lights: tuple[str, ...] = (), meshes: tuple[str, ...] = ()) -> Scene:
    sc.lights = [lt for lt in sc.lights if lt.name not in lights]
    sc.meshes = [m for m in sc.meshes if m.name not in meshes]
    return sc


def _linked_regions(monkeypatch=None, *defines: str) -> dict[str, tuple[float, float]]:
    """Per object: (mean of the linked render, mean of what the links say it is, from unlinked renders)."""
    if defines:
        from tests.bias_controls import built_with

        built_with(monkeypatch, *defines)
    img, r = _render(linking_scene())
    obj = _objects(r)
    names = [m.name for m in r.scene.meshes]
    plain = lambda: linking_scene(linked=False)  # noqa: E731
    # floor_b: fill and glow, not key
    floor_b, _ = _render(_without(plain(), lights=("key",)))
    # floor_a: key without the plank's shadow, glow with it, no fill
    key_alone, _ = _render(_without(plain(), lights=("fill",), meshes=("plank", "glow")))
    glow_alone, _ = _render(_without(plain(), lights=("key", "fill")))
    # the plank: fill alone (glow and key leave it out)
    plank, _ = _render(_without(plain(), lights=("key",), meshes=("glow",)))
    expected = {"floor_a": key_alone + glow_alone, "floor_b": floor_b, "plank": plank}
    return {name: (float(img[obj == names.index(name)].mean()), float(want[obj == names.index(name)].mean()))
            for name, want in expected.items()}


def test_each_object_gets_the_light_its_links_give():
    regions = _linked_regions()
    for name, (got, want) in regions.items():
        print(f"{name}: linked {got:.4f}, expected {want:.4f}")
        assert got == pytest.approx(want, rel=0.01), name


@pytest.mark.parametrize("control,broken", [("TEST_LINKING_WITHOUT_BLOCKERS", "floor_a"),
                                            ("TEST_LINKING_WITHOUT_RECEIVERS", "floor_b")])
def test_the_region_check_sees_links_ignored(monkeypatch, control, broken):
    regions = _linked_regions(monkeypatch, control)
    got, want = regions[broken]
    print(f"{control}: {broken} linked {got:.4f}, expected {want:.4f}")
    assert abs(got / want - 1) > 0.05


def test_the_scene_file_keeps_the_links(tmp_path):
    sc = linking_scene()
    save_scene(sc, tmp_path / "linked.npz")
    back = load_scene(tmp_path / "linked.npz", Scene)
    assert [lt.linking for lt in back.lights] == [lt.linking for lt in sc.lights]
    assert [m.linking for m in back.meshes] == [m.linking for m in sc.meshes]
    assert back.lights[0].linking.receivers == {"floor_a": "INCLUDE"}
