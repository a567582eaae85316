"""The tuning scenes of `restircl compare` (restircl/eval/scenes/held_out.py): the three kinds of issue 23 with the
lights, counts and powers the issue names, valid and deterministic."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import SceneError
from restircl.eval.scenes import held_out as H


def _edges_shared_twice(tris: np.ndarray) -> bool:
    """A closed mesh: every undirected edge belongs to exactly two triangles."""
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def _emissive_triangles(scene) -> int:
    return sum(int(sum(scene.materials[i].is_emissive for i in m.material_ids)) for m in scene.meshes)


@pytest.mark.parametrize("kind", H.KINDS)
def test_valid_deterministic_and_sized(kind):
    a, b = H.held_out(kind), H.held_out(kind)
    assert (a.camera.width, a.camera.height) == (192, 108)
    assert a.frames == 1 and a.name == kind
    assert all(np.array_equal(x.vertices, y.vertices) for x, y in zip(a.meshes, b.meshes, strict=True))
    assert [lt.power for lt in a.lights] == [lt.power for lt in b.lights]
    small = H.held_out(kind, 48, 27)
    assert (small.camera.width, small.camera.height) == (48, 27)
    # diffuse only: the comparison with Cycles is of the light sampling, not of materials
    assert all(m.specular == 0 and not m.layers for m in a.materials)


def test_unknown_kind_is_named():
    with pytest.raises(ValueError, match="no tuning scene 'forest'"):
        H.held_out("forest")


def test_studio_has_every_area_shape_spots_and_a_sun():
    s = H.studio()
    by_type = {t: [lt for lt in s.lights if lt.type == t] for t in ("area", "spot", "sun", "point")}
    assert sorted(lt.shape for lt in by_type["area"]) == ["DISK", "ELLIPSE", "RECTANGLE", "SQUARE"]
    for lt in by_type["area"]:
        assert 1.0 <= max(lt.size, lt.size_y) <= 2.0, lt.name
        # close to the objects: within 2.5 m of the origin-centred pair of objects
        assert np.linalg.norm(lt.transforms[0][:3, 3]) < 3.0, lt.name
    assert len(by_type["spot"]) == 2 and all(lt.spot_blend > 0 for lt in by_type["spot"])
    assert len(by_type["sun"]) == 1 and not by_type["point"]
    assert all(lt.power > 0 for lt in s.lights)
    v, t = H.blob(4, 0.6)
    assert len(t) == 5120 and _edges_shared_twice(t)
    assert s.triangle_count > 5120 + 1280  # the blob, the ball, floor and backdrop


def test_neon_has_thousands_of_light_triangles_and_no_light_objects():
    s = H.neon()
    assert not s.lights
    lit = _emissive_triangles(s)
    assert lit == 2 * 96 * 12 + 6 * 2 * 40 * 6 + 320, lit  # torus, six strips, the bulb
    emitters = {s.materials[i].name for m in s.meshes for i in np.unique(m.material_ids)
                if s.materials[i].is_emissive}
    assert emitters == {"torus", "strip_cyan", "strip_amber", "bulb"}
    v, t = H.torus(0.8, 0.06, 96, 12)
    assert _edges_shared_twice(t)
    walls = [m for m in s.materials if not m.is_emissive]
    assert all(min(m.albedo) > 0 for m in walls)


def test_garden_has_300_point_lights_over_four_decades():
    s = H.garden()
    assert len(s.lights) == 300 and all(lt.type == "point" for lt in s.lights)
    p = np.array([lt.power for lt in s.lights])
    assert p.min() >= 0.1 and p.max() <= 1000.0
    assert math.log10(p.max() / p.min()) > 3.5  # spans about four decades
    xyz = np.array([lt.transforms[0][:3, 3] for lt in s.lights])
    assert np.all(np.abs(xyz[:, :2]) <= 12.0) and np.ptp(xyz[:, 0]) > 20 and np.ptp(xyz[:, 1]) > 20
    assert np.all(xyz[:, 2] > 0)
    assert {lt.radius for lt in s.lights} == {0.0, 0.05}
    assert s.triangle_count == 2 + 60 * 12


def test_bad_sizes_are_rejected_by_name():
    with pytest.raises(SceneError, match="camera: width"):
        H.held_out("garden", 0, 27)
