"""The validation scenes of global illumination (restircl/eval/scenes/validation.py): what they are made of (the
materials, lights, emitters and world the issue names), valid, deterministic, sized, resolved by kind beside the
tuning scenes (eval/scenes/kinds.py), and rendered finite with and without bounces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.eval.scenes import held_out as H
from restircl.eval.scenes import kinds as K
from restircl.eval.scenes import validation as V


def _areas_by_material(scene) -> dict[str, float]:
    out: dict[str, float] = {}
    for mesh in scene.meshes:
        v, t = mesh.vertices, mesh.triangles
        area = 0.5 * np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)
        for i, a in zip(mesh.material_ids, area, strict=True):
            name = scene.materials[i].name
            out[name] = out.get(name, 0.0) + float(a)
    return out


def _emissive_triangles(scene) -> int:
    return sum(int(sum(scene.materials[i].is_emissive for i in m.material_ids)) for m in scene.meshes)


@pytest.mark.parametrize("kind", V.KINDS)
def test_valid_deterministic_and_sized(kind):
    a, b = V.validation(kind), V.validation(kind)
    assert (a.camera.width, a.camera.height) == (192, 108) and a.name == kind and a.frames == 1
    assert all(np.array_equal(x.vertices, y.vertices) for x, y in zip(a.meshes, b.meshes, strict=True))
    small = V.validation(kind, 48, 27)
    assert (small.camera.width, small.camera.height) == (48, 27)
    # diffuse, glossy (a dielectric specular layer) and metal surfaces, and an emissive mesh, in each
    solid = [m for m in a.materials if not m.is_emissive]
    assert any(m.metallic == 1.0 for m in solid)
    assert any(m.metallic == 0.0 and m.specular == 0.5 for m in solid)
    assert any(m.metallic == 0.0 and m.specular == 0.0 for m in solid)
    assert _emissive_triangles(a) > 0


def test_kinds_resolve_beside_the_held_out_ones():
    assert set(K.KINDS) == set(H.KINDS) | {"interior", "outdoor", "gallery", "gi_tuning_room", "gi_tuning_yard",
                                           "glass_table", "globe_frosted", "globe_clear", "globe_frosted_unshadowed",
                                           "user"}
    assert K.scene_of_kind("gallery", 48, 27).name == "gallery"
    assert K.scene_of_kind("glass_table", 48, 27).name == "glass_table_glass"
    assert K.scene_of_kind("interior", 48, 27).name == "interior"
    assert K.scene_of_kind("garden", 48, 27).name == "garden"
    with pytest.raises(ValueError, match="no scene kind 'forest'"):
        K.scene_of_kind("forest")
    with pytest.raises(ValueError, match="no validation scene 'garden'"):
        V.validation("garden")


def test_interior_room_lights_and_materials():
    s = V.interior()
    mats = {m.name: m for m in s.materials}
    assert (mats["floor"].roughness, mats["floor"].specular, mats["floor"].metallic) == (0.3, 0.5, 0.0)
    assert (mats["copper"].metallic, mats["copper"].roughness) == (1.0, 0.25)
    # 24 ceiling spots with a radius (BSDF rays meet them), inside the room, pointing down
    assert len(s.lights) == 24 and all(lt.type == "spot" and lt.radius > 0 for lt in s.lights)
    for lt in s.lights:
        m = lt.transforms[0]
        x, y, z = m[:3, 3]
        assert abs(x) < 3.0 and abs(y) < 2.5 and 2.7 < z < 2.8, lt.name
        assert -m[2, 2] < -0.9, lt.name  # local -Z, the spot's axis, points down
    # the lamp's shade: an open tube of 8 x 36 quads, the only emitter among the meshes
    assert _emissive_triangles(s) == 2 * 8 * 36
    # closed but for the window: the right wall is 5 x 2.8 m less the 1.5 x 1.1 m window
    area = _areas_by_material(s)
    assert area["right"] == pytest.approx(5.0 * 2.8 - 1.5 * 1.1, rel=1e-9)
    assert area["left"] == pytest.approx(5.0 * 2.8, rel=1e-9)
    assert area["ceiling"] == pytest.approx(6.0 * 5.0, rel=1e-9)


def test_outdoor_world_has_a_sun_and_no_light_objects():
    s = V.outdoor()
    assert not s.lights and s.environment is not None
    img = s.environment.image
    h, w = img.shape[:2]
    lum = img.mean(axis=-1)
    r, c = np.unravel_index(np.argmax(lum), lum.shape)
    # the brightest texel lies towards OUTDOOR_SUN (the map's layout: row 0 the zenith, u = 0.5 towards +x)
    theta, phi = math.pi * (r + 0.5) / h, math.pi * (1.0 - 2.0 * (c + 0.5) / w)
    d = np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])
    sun = np.array(V.OUTDOOR_SUN) / np.linalg.norm(V.OUTDOOR_SUN)
    assert d @ sun > math.cos(math.radians(2.5))
    assert lum.max() > 1000 * np.median(lum)  # a sun, not a bright patch of sky
    assert _emissive_triangles(s) == 2 * 72 * 10  # the torus in the wall's shadow


@pytest.mark.parametrize("kind", V.KINDS)
def test_renders_finite_with_and_without_bounces(kind, device):
    """Max Bounces 0 and 12: finite, non-negative, and the bounces add light (in the room most: 1.6x measured;
    outdoors the ground and walls add ~6 %)."""
    scene = V.validation(kind, 32, 18)
    means = {}
    for b in (0, 12):
        s = Settings(method="ris", max_bounces=b, diffuse_bounces=b, glossy_bounces=b, seed=5)
        img = Renderer(scene, s, device).render_still(0, 16).color[..., :3]
        assert np.all(np.isfinite(img)) and img.min() >= 0.0, (kind, b)
        means[b] = float(img.mean())
    assert means[12] > (1.3 if kind == "interior" else 1.02) * means[0], means


def test_direct_light_validation_gallery():
    """The direct-light validation kind: deterministic, valid, 48 spots, 120 points over 3 decades, an area light
    of three shapes and an emissive sign; it renders finite and lit."""
    from restircl.eval.scenes import validation_direct as VD

    a, b = VD.validation_direct("gallery", 48, 27), VD.validation_direct("gallery", 48, 27)
    assert [x.power for x in a.lights] == [x.power for x in b.lights]
    types = [x.type for x in a.lights]
    assert types.count("spot") == 48 and types.count("point") == 120 and types.count("area") == 3
    assert {x.shape for x in a.lights if x.type == "area"} == {"SQUARE", "DISK", "RECTANGLE"}
    points = [x.power for x in a.lights if x.type == "point"]
    assert max(points) / min(points) > 100
    assert _emissive_triangles(a) > 0
    img = Renderer(a, Settings(method="ris", seed=1)).render_still(0, 4).color[..., :3]
    assert np.all(np.isfinite(img)) and img.mean() > 0
    with pytest.raises(ValueError, match="no direct-light validation scene"):
        VD.validation_direct("interior")
