"""The tuning scene of global illumination (restircl/eval/scenes/gi_tuning.py): a room of the validation interior's
kind (spots with a radius, coloured walls, a glossy floor, a metal sphere, an emissive mesh) that is not that room,
valid, deterministic and resolved by its kind."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.eval.scenes import gi_tuning as T
from restircl.eval.scenes import kinds as K
from restircl.eval.scenes import validation as V

from .test_validation_scenes import _areas_by_material, _emissive_triangles


def test_valid_deterministic_and_resolved_by_kind():
    a, b = T.gi_tuning("gi_tuning_room"), K.scene_of_kind("gi_tuning_room")
    assert (a.camera.width, a.camera.height) == (192, 108) and a.name == "gi_tuning_room"
    assert all(np.array_equal(x.vertices, y.vertices) for x, y in zip(a.meshes, b.meshes, strict=True))
    with pytest.raises(ValueError, match="no tuning scene 'interior'"):
        T.gi_tuning("interior")


def test_same_kind_as_interior_but_another_room():
    s, interior = T.gi_tuning_room(), V.interior()
    mats = {m.name: m for m in s.materials}
    assert (mats["floor"].roughness, mats["floor"].specular, mats["floor"].metallic) == (0.35, 0.5, 0.0)
    assert (mats["gold"].metallic, mats["gold"].roughness) == (1.0, 0.22)
    # 20 spots with a radius 6 cm below the 3 m ceiling, inside the 4.5 x 6.5 m room, pointing down
    assert len(s.lights) == 20 and all(lt.type == "spot" and lt.radius == 0.03 for lt in s.lights)
    for lt in s.lights:
        m = lt.transforms[0]
        x, y, z = m[:3, 3]
        assert abs(x) < 2.25 and abs(y) < 3.25 and z == pytest.approx(2.94), lt.name
        assert -m[2, 2] < -0.9, lt.name
    # the light strip: an open tube of 24 x 8 quads, the only emitter among the meshes
    assert _emissive_triangles(s) == 2 * 24 * 8
    area = _areas_by_material(s)
    assert area["left"] == pytest.approx(6.5 * 3.0 - 1.7 * 1.2, rel=1e-9)  # less the window
    assert area["ceiling"] == pytest.approx(4.5 * 6.5, rel=1e-9)
    # not the validation room: other lights, other size
    assert len(interior.lights) != len(s.lights)
    assert _areas_by_material(interior)["ceiling"] != pytest.approx(area["ceiling"])


def test_yard_is_of_the_outdoor_kind_with_another_sun():
    s, outdoor = T.gi_tuning("gi_tuning_yard"), V.outdoor()
    assert s.name == "gi_tuning_yard" and not s.lights and s.environment is not None
    assert _emissive_triangles(s) == 12  # the glowing box
    assert any(m.metallic == 1.0 for m in s.materials) and any(m.specular == 0.5 for m in s.materials)
    assert not np.array_equal(s.environment.image, outdoor.environment.image)
