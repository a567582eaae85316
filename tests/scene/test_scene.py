"""Scene model: validation gives a clear error naming the object; save/load round trip; corrupt files."""

import math
import zipfile

import numpy as np
import pytest
from restircl import Camera, Light, Material, Mesh, Scene, SceneError, SceneFileError, scenes, translation


def small_scene() -> Scene:
    v, t = scenes.quad(2, 2)
    return Scene(
        [Mesh("floor", v, t, 0)],
        [Material("grey", (0.5, 0.5, 0.5)), Material("lamp", (0, 0, 0), (1, 1, 1), 5.0)],
        [Light("key", "point", (1, 1, 1), 100.0, translation(0, 0, 2))],
        Camera(translation(0, 0, 5), 32, 24),
    )


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda s: setattr(s, "camera", None), "no camera"),
        (lambda s: setattr(s.camera, "width", 0), "width"),
        (lambda s: setattr(s.camera, "height", 100000), "height"),
        (lambda s: s.camera.transforms.__setitem__((0, 0, 3), np.nan), "camera: transform"),
        (lambda s: s.meshes[0].vertices.__setitem__((0, 0), np.inf), "mesh 'floor': vertices"),
        (lambda s: s.meshes[0].transforms.__setitem__((0, 1, 3), np.nan), "mesh 'floor': transform"),
        (lambda s: s.meshes[0].triangles.__setitem__((0, 0), 99), "mesh 'floor': triangle vertex index"),
        (lambda s: s.meshes[0].material_ids.__setitem__(0, 7), "mesh 'floor': material id"),
        (lambda s: setattr(s.lights[0], "power", -1.0), "light 'key': power"),
        (lambda s: setattr(s.lights[0], "power", math.nan), "light 'key': power"),
        (lambda s: setattr(s.lights[0], "type", "laser"), "light 'key': type"),
        (lambda s: s.lights[0].transforms.__setitem__((0, 2, 3), np.inf), "light 'key': transform"),
        (lambda s: setattr(s.materials[1], "emission_strength", -2.0), "material 1 'lamp'"),
        (lambda s: setattr(s.materials[0], "albedo", (0.5, math.nan, 0.5)), "material 0 'grey': albedo"),
    ],
)
def test_validate_rejects_bad_input(mutate, message):
    s = small_scene()
    s.validate()
    mutate(s)
    with pytest.raises(SceneError, match=message):
        s.validate()


def test_degenerate_triangles_are_dropped_with_a_warning():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]], float)
    t = np.array([[0, 1, 2], [0, 1, 3]])  # the second is a line
    s = small_scene()
    s.meshes.append(Mesh("sliver", v, t, 0))
    with pytest.warns(UserWarning, match="sliver"):
        w = s.world_triangles(0)
    assert len(w) == 3


def test_glass_materials_survive_the_round_trip(tmp_path):
    """Glass, Refraction and a Principled BSDF's Transmission Weight keep their kind, IOR, roughness and weight."""
    from restircl import Material

    s = scenes.cornell_box(8, 8)
    s.materials = [*s.materials, Material("g", (0.9, 0.9, 1.0), kind="glass", roughness=0.2, ior=1.33),
                   Material("r", kind="refraction", roughness=0.0, ior=1.6),
                   Material("p", transmission=0.75, ior=1.45, specular=0.5)]
    path = tmp_path / "glass.npz"
    s.save(path)
    got = [(m.kind, m.ior, m.roughness, m.transmission, tuple(m.albedo)) for m in Scene.load(path).materials[-3:]]
    assert got == [(m.kind, m.ior, m.roughness, m.transmission, tuple(m.albedo)) for m in s.materials[-3:]]


def test_save_load_round_trip(tmp_path):
    s = scenes.many_lights(width=64, height=36, frames=3, lamps=20, point_lights=5, objects=4)
    s.lights[0].power_per_frame = np.array([1.0, 0.0, 1.0])
    path = tmp_path / "scene.npz"
    s.save(path)
    r = Scene.load(path)
    assert r.name == s.name and r.frames == s.frames
    assert len(r.meshes) == len(s.meshes) and len(r.lights) == len(s.lights)
    for a, b in zip(s.meshes, r.meshes, strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)
        np.testing.assert_array_equal(a.triangles, b.triangles)
        np.testing.assert_array_equal(a.material_ids, b.material_ids)
        np.testing.assert_array_equal(a.transforms, b.transforms)
    for a, b in zip(s.lights, r.lights, strict=True):
        assert (a.name, a.type, a.power, a.radius, a.soft_falloff) == (b.name, b.type, b.power, b.radius,
                                                                      b.soft_falloff)
    np.testing.assert_array_equal(r.lights[0].power_per_frame, [1.0, 0.0, 1.0])
    assert [m.radiance.tolist() for m in r.materials] == [m.radiance.tolist() for m in s.materials]
    np.testing.assert_array_equal(r.camera.transforms, s.camera.transforms)
    assert r.camera.tan_half_fov() == s.camera.tan_half_fov()
    r.validate()


def test_corrupt_and_foreign_files_give_clear_errors(tmp_path):
    bad = tmp_path / "garbage.npz"
    bad.write_bytes(b"this is not a zip file at all")
    with pytest.raises(SceneFileError, match="not a restircl scene file"):
        Scene.load(bad)
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, x=np.arange(3))
    with pytest.raises(SceneFileError, match="not a restircl scene file"):
        Scene.load(foreign)
    good = tmp_path / "good.npz"
    small_scene().save(good)
    truncated = tmp_path / "truncated.npz"
    truncated.write_bytes(good.read_bytes()[:200])
    with pytest.raises(SceneFileError):
        Scene.load(truncated)
    # a file whose header is fine but which lacks an array
    missing = tmp_path / "missing.npz"
    with zipfile.ZipFile(good) as zin, zipfile.ZipFile(missing, "w") as zout:
        for item in zin.infolist():
            if "mesh0_vertices" not in item.filename:
                zout.writestr(item, zin.read(item.filename))
    with pytest.raises(SceneFileError, match="corrupt"):
        Scene.load(missing)


def test_blender_sensor_fit_rules():
    cam = Camera(None, 200, 100, lens=50.0, sensor_width=36.0, sensor_height=24.0, sensor_fit="AUTO")
    tx, ty, _, _ = cam.tan_half_fov()
    assert tx == pytest.approx(18.0 / 50.0) and ty == pytest.approx(9.0 / 50.0)
    cam.width, cam.height = 100, 200  # portrait: AUTO fits the sensor width to the larger (vertical) side
    tx, ty, _, _ = cam.tan_half_fov()
    assert ty == pytest.approx(18.0 / 50.0) and tx == pytest.approx(9.0 / 50.0)
    cam.sensor_fit = "VERTICAL"
    tx, ty, _, _ = cam.tan_half_fov()
    assert ty == pytest.approx(12.0 / 50.0)
    cam.set_fov(math.radians(90), "horizontal")
    assert cam.tan_half_fov()[0] == pytest.approx(1.0)
