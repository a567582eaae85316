"""Deformation within a still's shutter (scene/deformation.py, Mesh.deform): the vertices between two steps are
interpolated linearly, held outside them; the world triangles of a time are the deformed ones moved by the
transform of that time; bad steps are refused naming the mesh; the steps survive a scene file and a retime."""

import numpy as np
import pytest
from restircl import Camera, Material, Mesh, Scene, SceneError, translation
from restircl.scene.retime import retime

TRI = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def deforming(times=(2.0, 4.0, 8.0)) -> Mesh:
    """A triangle whose second vertex is at x = 1, 3, 2 at the three times (the others fixed)."""
    steps = np.stack([TRI, TRI, TRI])
    steps[:, 1, 0] = (1.0, 3.0, 2.0)
    return Mesh("tri", TRI, [[0, 1, 2]], 0, deform=steps, deform_times=times)


@pytest.mark.parametrize(("frame", "x"), [
    (0.0, 1.0), (2.0, 1.0), (2.5, 1.5), (3.0, 2.0), (4.0, 3.0), (5.0, 2.75), (7.0, 2.25), (8.0, 2.0), (9.5, 2.0)])
def test_vertices_between_steps_are_linear_and_held_outside(frame, x):
    v = deforming().vertices_at(frame)
    assert v[1, 0] == pytest.approx(x)
    np.testing.assert_array_equal(v[[0, 2]], TRI[[0, 2]])


def test_normals_between_steps_are_linear():
    mesh = deforming()
    up = np.tile([0.0, 0.0, 1.0], (1, 3, 1))
    tilted = np.tile([1.0, 0.0, 1.0], (1, 3, 1))
    mesh.normals, mesh.deform_normals = up, np.stack([up, tilted, up])
    np.testing.assert_allclose(mesh.normals_at(3.0), np.tile([0.5, 0.0, 1.0], (1, 3, 1)))
    np.testing.assert_allclose(mesh.normals_at(6.0), np.tile([0.5, 0.0, 1.0], (1, 3, 1)))
    np.testing.assert_allclose(mesh.normals_at(1.0), up)
    mesh.deform_normals = None  # smooth, its normals not stepped: the frame's at every time
    np.testing.assert_allclose(mesh.normals_at(3.0), up)


def test_a_mesh_without_steps_keeps_its_vertices():
    m = Mesh("tri", TRI, [[0, 1, 2]])
    assert m.vertices_at(3.7) is m.vertices
    assert not m.deforms


def scene_of(mesh: Mesh) -> Scene:
    return Scene([mesh], [Material("grey", (0.5, 0.5, 0.5))], [], Camera(translation(0, 0, 5), 32, 24))


def test_world_triangles_are_deformed_then_moved():
    mesh = deforming()
    mesh.transforms = np.stack([translation(float(f), 0, 0) for f in range(10)])  # x = frame
    sc = scene_of(mesh)
    assert sc.has_moving_objects
    w = sc.world_triangles(5.0)
    np.testing.assert_allclose(w.v0[0], (5.0, 0.0, 0.0))
    np.testing.assert_allclose(w.v1[0], (5.0 + 2.75, 0.0, 0.0))
    still = scene_of(deforming())  # deformation alone moves the scene
    assert still.has_moving_objects


@pytest.mark.parametrize(("deform", "times", "message"), [
    (np.zeros((2, 3, 3)), None, "go together"),
    (np.zeros((2, 4, 3)), [0.0, 1.0], "shape"),
    (np.zeros((1, 3, 3)), [0.0], "S >= 2"),
    (np.full((2, 3, 3), np.nan), [0.0, 1.0], "NaN"),
    (np.zeros((2, 3, 3)), [1.0, 1.0], "increase"),
    (None, None, "deform_normals without deform"),
    (np.zeros((2, 3, 3)), [0.0, 1.0], "deform_normals must be finite, shape \\(2, 1, 3, 3\\)"),
])
def test_bad_steps_are_refused(deform, times, message):
    normals = np.ones((2, 2, 3, 3)) if "deform_normals" in message else None
    mesh = Mesh("tri", TRI, [[0, 1, 2]], normals=np.ones((1, 3, 3)), deform=deform, deform_times=times,
                deform_normals=normals)
    with pytest.raises(SceneError, match=f"mesh 'tri'.*{message}"):
        scene_of(mesh).validate()


def test_steps_survive_the_scene_file_and_a_retime(tmp_path):
    sc = scene_of(deforming())
    sc.meshes[0].normals = np.ones((1, 3, 3))
    sc.meshes[0].deform_normals = np.stack([np.ones((1, 3, 3)) * k for k in (1.0, 2.0, 3.0)])
    sc.validate()
    sc.save(tmp_path / "d.npz")
    back = Scene.load(tmp_path / "d.npz").meshes[0]
    np.testing.assert_array_equal(back.deform, sc.meshes[0].deform)
    np.testing.assert_array_equal(back.deform_times, [2.0, 4.0, 8.0])
    np.testing.assert_array_equal(back.deform_normals, sc.meshes[0].deform_normals)
    twice = retime(sc, 2).meshes[0]
    np.testing.assert_array_equal(twice.deform_times, [4.0, 8.0, 16.0])
    assert twice.vertices_at(10.0)[1, 0] == pytest.approx(2.75)
