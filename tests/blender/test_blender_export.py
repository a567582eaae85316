"""Export of scenes built in bpy: depsgraph -> restircl.Scene, checked object by object."""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest
from restircl.eval.cycles.bridge import node_material

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered, needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def export(frames=None, camera=None):
    from restircl_blender import export as ex

    sc = bpy.context.scene
    dg = bpy.context.evaluated_depsgraph_get()
    return ex.export_scene(dg, frames, frame_set=sc.frame_set, camera=camera)


def mesh_by_name(sc, name):
    found = [m for m in sc.meshes if m.name == name]
    assert found, f"no mesh {name!r} among {[m.name for m in sc.meshes]}"
    return found


def world_vertices(mesh, frame=0):
    m = restircl.Scene.at(mesh.transforms, frame)
    return mesh.vertices @ m[:3, :3].T + m[:3, 3]


def basic_scene():
    sc = scenes.new_scene(64, 48)
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.5, 0.6, 0.7)))
    scenes.light("SUN", "Sun", (0, 0, 5), energy=2.0)
    scenes.camera((0, -6, 4), (0, 0, 0))
    return sc


# ---- geometry -------------------------------------------------------------------------------------------


def test_meshes_with_modifiers_are_evaluated():
    basic_scene()
    cube = scenes.box("Cube", (1, 1, 1), scenes.diffuse_material("Red", (0.8, 0.1, 0.1)), location=(0, 0, 0.5))
    sub = cube.modifiers.new("Subdiv", "SUBSURF")
    sub.levels = sub.render_levels = 1
    arr = scenes.box("Row", (1, 1, 1), location=(0, 3, 0.5))
    mod = arr.modifiers.new("Array", "ARRAY")
    mod.count = 3
    exp = export()
    sc = exp.scene.validate()
    assert len(mesh_by_name(sc, "Cube")[0].triangles) == 6 * 4 * 2  # one subdivision: 24 quads
    row = mesh_by_name(sc, "Row")[0]
    assert len(row.triangles) == 3 * 12
    xs = world_vertices(row)[:, 0]
    assert xs.min() == pytest.approx(-0.5) and xs.max() == pytest.approx(2.5)
    floor = mesh_by_name(sc, "Floor")[0]
    assert sc.materials[floor.material_ids[0]].albedo == pytest.approx((0.5, 0.6, 0.7))
    # objects without a material get Cycles' default grey
    assert sc.materials[row.material_ids[0]].albedo == pytest.approx((0.8, 0.8, 0.8))
    assert exp.stats["triangles"] == sc.triangle_count


def test_world_transform_and_hidden_objects():
    basic_scene()
    ob = scenes.box("Moved", (2, 1, 1), location=(1, 2, 3), rotation=(0, 0, math.pi / 2))
    ob.scale = (1, 2, 1)
    hidden = scenes.box("Hidden", (1, 1, 1))
    hidden.hide_render = True
    hidden.hide_viewport = True
    sc = export().scene
    assert not [m for m in sc.meshes if m.name == "Hidden"]
    wv = world_vertices(mesh_by_name(sc, "Moved")[0])
    # box 2 x 1 x 1, scaled y by 2, rotated 90 degrees about z, at (1, 2, 3)
    assert wv.min(axis=0) == pytest.approx((0.0, 1.0, 2.5), abs=1e-6)
    assert wv.max(axis=0) == pytest.approx((2.0, 3.0, 3.5), abs=1e-6)


def test_collection_instances():
    basic_scene()
    coll = bpy.data.collections.new("Prop")
    scenes.box("PropBox", (1, 1, 1), location=(0, 0, 0.5), collection=coll)
    for i, x in enumerate((-3.0, 3.0)):
        empty = bpy.data.objects.new(f"Instance{i}", None)
        empty.instance_type = "COLLECTION"
        empty.instance_collection = coll
        empty.location = (x, 1.0, 0.0)
        scenes.link(empty)
    exp = export()
    boxes = mesh_by_name(exp.scene, "PropBox")
    assert len(boxes) == 2
    centres = sorted(world_vertices(b).mean(axis=0)[0] for b in boxes)
    assert centres == pytest.approx([-3.0, 3.0])
    assert exp.stats["instances"] == 2


def _instance_on_points_group(count: int, spacing: float):
    ng = bpy.data.node_groups.new("Scatter", "GeometryNodeTree")
    ng.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    ng.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gin = ng.nodes.new("NodeGroupInput")
    gout = ng.nodes.new("NodeGroupOutput")
    line = ng.nodes.new("GeometryNodeMeshLine")
    line.inputs["Count"].default_value = count
    line.inputs["Offset"].default_value = (spacing, 0.0, 0.0)
    cube = ng.nodes.new("GeometryNodeMeshCube")
    cube.inputs["Size"].default_value = (0.5, 0.5, 0.5)
    iop = ng.nodes.new("GeometryNodeInstanceOnPoints")
    ng.links.new(line.outputs["Mesh"], iop.inputs["Points"])
    ng.links.new(cube.outputs["Mesh"], iop.inputs["Instance"])
    join = ng.nodes.new("GeometryNodeJoinGeometry")
    ng.links.new(gin.outputs[0], join.inputs[0])
    ng.links.new(iop.outputs["Instances"], join.inputs[0])
    ng.links.new(join.outputs[0], gout.inputs[0])
    return ng


def test_geometry_nodes_instances():
    basic_scene()
    host = scenes.quad("Host", 0.2, 0.2, location=(0.0, 2.0, 1.0))
    mod = host.modifiers.new("Scatter", "NODES")
    mod.node_group = _instance_on_points_group(4, 1.5)
    exp = export()
    sc = exp.scene.validate()
    cubes = [m for m in sc.meshes if len(m.triangles) == 12]
    assert len(cubes) == 4
    xs = sorted(float(world_vertices(m).mean(axis=0)[0]) for m in cubes)
    assert xs == pytest.approx([0.0, 1.5, 3.0, 4.5])
    assert all(world_vertices(m).mean(axis=0)[1:] == pytest.approx((2.0, 1.0)) for m in cubes)
    assert exp.stats["instances"] == 4


# ---- materials ------------------------------------------------------------------------------------------


def test_materials():
    basic_scene()
    scenes.quad("A", 1, material=scenes.principled_material("Princ", (0.2, 0.4, 0.6), (1.0, 0.5, 0.0), 3.0),
                location=(0, 0, 1))
    scenes.quad("B", 1, material=scenes.emission_material("Emit", (0.5, 1.0, 0.25), 8.0), location=(0, 0, 2))
    mix, tree, out = node_material(bpy, "Mix")  # node trees are opt-in before Blender 5
    d = tree.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (1.0, 0.0, 0.0, 1.0)
    e = tree.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (0.0, 0.0, 1.0, 1.0)
    e.inputs["Strength"].default_value = 4.0
    m = tree.nodes.new("ShaderNodeMixShader")
    m.inputs["Fac"].default_value = 0.25
    tree.links.new(d.outputs[0], m.inputs[1])
    tree.links.new(e.outputs[0], m.inputs[2])
    tree.links.new(m.outputs[0], out.inputs["Surface"])
    scenes.quad("C", 1, material=mix, location=(0, 0, 3))
    glossy, tree, out = node_material(bpy, "Glossy")  # node trees are opt-in before Blender 5
    g = tree.nodes.new("ShaderNodeBsdfGlossy" if hasattr(bpy.types, "ShaderNodeBsdfGlossy") else
                       "ShaderNodeBsdfAnisotropic")
    g.inputs["Color"].default_value = (0.3, 0.3, 0.9, 1.0)
    tree.links.new(g.outputs[0], out.inputs["Surface"])
    scenes.quad("D", 1, material=glossy, location=(0, 0, 4))
    exp = export()
    mats = {m.name: m for m in exp.scene.materials}
    assert mats["Princ"].albedo == pytest.approx((0.2, 0.4, 0.6))
    assert mats["Princ"].radiance == pytest.approx((3.0, 1.5, 0.0))
    assert mats["Emit"].albedo == pytest.approx((0.0, 0.0, 0.0))
    assert mats["Emit"].radiance == pytest.approx((4.0, 8.0, 2.0))
    assert mats["Mix"].albedo == pytest.approx((0.75, 0.0, 0.0))
    assert mats["Mix"].radiance == pytest.approx((0.0, 0.0, 1.0))
    assert mats["Glossy"].albedo == pytest.approx((0.3, 0.3, 0.9))
    assert mats["Glossy"].kind == "glossy"
    assert not any("Princ" in w or "Emit" in w or "Mix" in w or "Glossy" in w for w in exp.warnings)


# ---- lights ---------------------------------------------------------------------------------------------


def test_lights_of_every_type():
    sc = basic_scene()
    bpy.data.objects.remove(bpy.data.objects["Sun"])
    # Blender 4.2 has no light exposure and no colour temperature
    has_exposure = "exposure" in bpy.types.Light.bl_rna.properties
    has_temperature = "use_temperature" in bpy.types.Light.bl_rna.properties
    extra = {"exposure": 1.0} if has_exposure else {}
    warm = {"use_temperature": True, "temperature": 3000.0} if has_temperature else {}
    scenes.light("POINT", "Point", (1, 2, 3), energy=100.0, shadow_soft_size=0.25, use_soft_falloff=False, **extra)
    scenes.light("SPOT", "Spot", (0, 0, 4), (0.3, 0, 0), energy=50.0, spot_size=math.radians(40), spot_blend=0.2,
                 shadow_soft_size=0.1, color=(1.0, 0.5, 0.25))
    scenes.light("SUN", "Sun", (0, 0, 9), (0.2, 0.1, 0), energy=3.0, angle=math.radians(2), **warm)
    for shape in ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE"):
        scenes.light("AREA", f"Area{shape}", (0, 0, 2), energy=80.0, shape=shape, size=1.5, size_y=0.5)
    has_normalize = "normalize" in bpy.types.AreaLight.bl_rna.properties  # not in Blender 4.2
    if has_normalize:
        scenes.light("AREA", "AreaRaw", (0, 0, 2), energy=10.0, shape="RECTANGLE", size=2.0, size_y=0.5,
                     normalize=False)
    scenes.light("AREA", "Spread", (0, 0, 2), energy=10.0, spread=math.radians(90))
    exp = export()
    lights = {lt.name: lt for lt in exp.scene.validate().lights}
    assert len(lights) == 8 + has_normalize
    p = lights["Point"]
    assert (p.type, p.radius, p.soft_falloff) == ("point", 0.25, False)
    assert p.power == pytest.approx(200.0 if has_exposure else 100.0)  # exposure 1: x2
    assert p.transforms[0][:3, 3] == pytest.approx((1, 2, 3))
    s = lights["Spot"]
    assert (s.type, s.spot_size, s.spot_blend, s.radius) == pytest.approx(("spot", math.radians(40), 0.2, 0.1))
    assert s.color == pytest.approx((1.0, 0.5, 0.25))
    assert s.soft_falloff  # Blender's default
    assert -s.transforms[0][:3, 2] == pytest.approx((0.0, math.sin(0.3), -math.cos(0.3)))  # points along -Z
    sun = lights["Sun"]
    assert (sun.type, sun.power, sun.angle) == pytest.approx(("sun", 3.0, math.radians(2)))
    if has_temperature:
        assert sun.color == pytest.approx(tuple(bpy.data.objects["Sun"].data.temperature_color), rel=1e-6)
        assert sun.color[0] > sun.color[2]  # 3000 K is red
    for shape in ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE"):
        a = lights[f"Area{shape}"]
        assert (a.type, a.shape, a.size, a.power) == ("area", shape, 1.5, 80.0)
        assert a.size_y == (0.5 if shape in ("RECTANGLE", "ELLIPSE") else 1.5)
    if has_normalize:
        assert lights["AreaRaw"].power == pytest.approx(10.0 * 2.0 * 0.5)  # normalize off: power per unit area
    assert any("Spread" in w and "spread" in w for w in exp.warnings)
    assert exp.stats["lights"] == len(lights)
    del sc


def test_light_node_strength_multiplies():
    basic_scene()
    ob = scenes.light("POINT", "Noded", (0, 0, 2), energy=10.0)
    ld = ob.data
    with warnings.catch_warnings():  # deprecated from Blender 5.1 (lights always use their nodes), still needed before
        warnings.simplefilter("ignore", DeprecationWarning)
        ld.use_nodes = True
    em = next(n for n in ld.node_tree.nodes if n.bl_idname == "ShaderNodeEmission")
    em.inputs["Strength"].default_value = 3.0
    em.inputs["Color"].default_value = (1.0, 0.5, 0.5, 1.0)
    lt = next(x for x in export().scene.lights if x.name == "Noded")
    assert lt.power == pytest.approx(30.0)
    assert lt.color == pytest.approx((1.0, 0.5, 0.5))


# ---- camera ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("res", "fit", "shift"), [
    ((64, 48), "AUTO", (0.0, 0.0)),
    ((48, 64), "AUTO", (0.1, -0.2)),
    ((64, 48), "VERTICAL", (0.0, 0.15)),
    ((48, 64), "HORIZONTAL", (-0.1, 0.0)),
    ((80, 40), "VERTICAL", (0.2, 0.1)),
])
def test_camera_projection_matches_blender(res, fit, shift):
    from bpy_extras.object_utils import world_to_camera_view
    from mathutils import Vector

    sc = scenes.new_scene(*res)
    scenes.quad("Floor", 10.0, 10.0)
    cam = scenes.camera((1.0, -5.0, 3.0), (0.3, 0.5, 0.2), lens=28.0, sensor_fit=fit, sensor_width=36.0,
                        sensor_height=20.0, shift_x=shift[0], shift_y=shift[1])
    c = export().scene.camera
    assert (c.width, c.height, c.sensor_fit) == (res[0], res[1], fit)
    assert (c.shift_x, c.shift_y) == pytest.approx(shift)
    tx, ty, sx, sy = c.tan_half_fov()
    m = c.transforms[0]
    rng = np.random.default_rng(1)
    for p in rng.uniform((-3, -3, -1), (3, 3, 2), size=(20, 3)):
        d = np.linalg.inv(m) @ np.append(p, 1.0)
        z = -d[2]
        nx = (d[0] / z - sx) / tx
        ny = (d[1] / z - sy) / ty
        uvw = world_to_camera_view(sc, cam, Vector(p))
        assert (nx + 1) / 2 == pytest.approx(uvw.x, abs=1e-5)
        assert (ny + 1) / 2 == pytest.approx(uvw.y, abs=1e-5)
        assert z == pytest.approx(uvw.z, rel=1e-5)


def test_unsupported_camera_is_a_clear_error():
    from restircl_blender.export import ExportError

    basic_scene()
    bpy.context.scene.camera.data.type = "PANO"
    with pytest.raises(ExportError, match="panoramic"):
        export()


def test_no_camera_is_a_clear_error():
    from restircl_blender.export import ExportError

    basic_scene()
    bpy.context.scene.camera = None
    with pytest.raises(ExportError, match="no camera"):
        export()


def test_camera_scale_is_ignored():
    basic_scene()
    cam = bpy.context.scene.camera
    before = export().scene.camera.transforms[0].copy()
    cam.scale = (2.0, 3.0, 0.5)
    after = export().scene.camera.transforms[0]
    assert after == pytest.approx(before)


# ---- animation ------------------------------------------------------------------------------------------


def test_motion_of_objects_lights_and_camera():
    sc = basic_scene()
    box = scenes.box("Mover", (1, 1, 1), location=(0, 0, 0.5))
    lamp = scenes.light("POINT", "Blink", (0, 0, 3), energy=10.0)
    cam = sc.camera
    for f, x in ((1, 0.0), (3, 2.0)):
        box.location.x = x
        box.keyframe_insert("location", frame=f)
        cam.location.z = 4.0 + x
        cam.keyframe_insert("location", frame=f)
        lamp.data.energy = 10.0 if f == 1 else 0.0
        lamp.data.keyframe_insert("energy", frame=f)
    sc.frame_set(1)
    exp = export(frames=[1, 2, 3])
    s = exp.scene.validate()
    assert s.frames == 3 and exp.frames == [1, 2, 3]
    mover = mesh_by_name(s, "Mover")[0]
    assert mover.transforms.shape == (3, 4, 4)
    xs = [restircl.Scene.at(mover.transforms, i)[0, 3] for i in range(3)]
    assert xs[0] == pytest.approx(0.0) and xs[2] == pytest.approx(2.0) and 0.0 < xs[1] < 2.0
    assert s.camera.transforms.shape == (3, 4, 4)
    assert s.camera.transforms[2][2, 3] == pytest.approx(6.0)
    floor = mesh_by_name(s, "Floor")[0]
    assert floor.transforms.shape == (1, 4, 4)  # static objects keep one matrix
    blink = next(lt for lt in s.lights if lt.name == "Blink")
    assert blink.power == pytest.approx(10.0)
    assert blink.power_at(0) == pytest.approx(10.0) and blink.power_at(2) == pytest.approx(0.0)
    assert s.has_moving_objects and s.has_moving_lights
    assert sc.frame_current == 1  # the exporter puts the frame back


def test_geometry_read_at_current_frame_and_camera_cuts():
    sc = basic_scene()
    cam_a = sc.camera
    cam_b = scenes.camera((5, 0, 2), (0, 0, 0), name="CamB", make_active=False)
    sc.timeline_markers.new("A", frame=1).camera = cam_a
    sc.timeline_markers.new("B", frame=3).camera = cam_b
    sc.frame_set(2)
    exp = export(frames=[1, 2, 3, 4])
    c = exp.scene.camera
    assert c.cuts == (2,)  # index of frame 3, where the camera switches
    assert c.transforms[3][:3, 3] == pytest.approx((5, 0, 2))
    assert c.transforms[0][:3, 3] == pytest.approx(tuple(cam_a.location))
    assert exp.index_of(3) == 2
    assert sc.frame_current == 2


def test_deforming_mesh_is_detected():
    sc = basic_scene()
    ob = scenes.box("Blob", (1, 1, 1))
    ob.shape_key_add(name="Basis")
    key = ob.shape_key_add(name="Grow")
    for v in key.data:
        v.co *= 2.0
    key.value = 0.0
    key.keyframe_insert("value", frame=1)
    key.value = 1.0
    key.keyframe_insert("value", frame=3)
    sc.frame_set(1)
    exp = export(frames=[1, 2, 3])
    assert exp.deforming == ["Blob"]
    assert any("deform" in w for w in exp.warnings)
    exp2 = export(frames=[1])
    assert exp2.deforming == []


# ---- bad scenes -----------------------------------------------------------------------------------------


def test_nan_transform_fails_validation():
    basic_scene()
    ob = scenes.box("Bad", (1, 1, 1))
    ob.location = (float("nan"), 0.0, 0.0)
    exp = export()
    with pytest.raises(restircl.SceneError, match="Bad"):
        exp.scene.validate()


def test_negative_light_power_is_left_out_with_a_warning():
    basic_scene()
    lamp = scenes.light("POINT", "Negative", (0, 0, 2))
    lamp.data.energy = -5.0
    if lamp.data.energy >= 0:
        pytest.skip("this Blender clamps light power at 0")
    exp = export()
    exp.scene.validate()
    assert [lt.name for lt in exp.scene.lights] == ["Sun"]
    assert any("Negative" in w and "negative strength" in w for w in exp.warnings)


def test_empty_scene_warns():
    scenes.new_scene(16, 16)
    scenes.camera()
    exp = export()
    exp.scene.validate()
    assert not exp.scene.meshes and not exp.scene.lights
    assert any("empty" in w for w in exp.warnings)


def test_world_lighting_is_exported():
    sc = basic_scene()
    sc.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    sc.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    exp = export()
    # the rest: tests/blender/test_blender_world.py
    assert exp.scene.environment.color == pytest.approx((0.5, 0.5, 0.5))
    assert not any("world" in w for w in exp.warnings)


# ---- the fingerprint the engine compares to reuse a renderer --------------------------------------------


def test_fingerprint_tracks_changes():
    basic_scene()
    a = export().fingerprint()
    assert export().fingerprint() == a
    bpy.data.objects["Sun"].data.energy = 5.0
    assert export().fingerprint() != a


def test_fingerprint_tracks_soft_falloff():
    basic_scene()
    lamp = scenes.light("POINT", "Soft", (0, 0, 1), energy=50.0, shadow_soft_size=0.3, use_soft_falloff=True)
    a = export().fingerprint()
    lamp.data.use_soft_falloff = False
    assert export().fingerprint() != a


def _every_field_scene():
    """A Scene with one of each part and no field left at None, so that every field can be changed."""
    mesh = restircl.Mesh(name="m", vertices=np.eye(3), triangles=np.array([[0, 1, 2]]),
                         material_ids=np.array([0]), transforms=np.eye(4), uvs=np.zeros((1, 3, 2)),
                         normals=np.ones((1, 3, 3)), attributes={"Col": np.ones((1, 3, 4))},
                         deform=np.stack([np.eye(3), 2 * np.eye(3)]), deform_times=np.array([0.0, 1.0]),
                         deform_normals=np.ones((2, 1, 3, 3)))
    material = restircl.Material(name="a", normal=restircl.materials.textures.NormalMap(), mix=0.5)
    light = restircl.Light(name="l", type="point", transforms=np.eye(4), radius=0.2,
                           power_per_frame=np.array([1.0, 0.5]))
    cam = restircl.Camera(transforms=np.eye(4), cuts=(1,), focus_per_frame=np.array([2.0, 3.0]))
    world = restircl.Environment(image=np.ones((2, 4, 3), np.float32), path="sky.exr", rotation=np.eye(3),
                                 strength_per_frame=np.array([1.0, 2.0]))
    return restircl.Scene(meshes=[mesh], materials=[material], lights=[light], camera=cam,
                          frame_count=2, environment=world)


def _changed(value):
    """Some other value of the same kind."""
    if isinstance(value, bool):
        return not value
    if isinstance(value, int | float):
        return value + 1
    if isinstance(value, str):
        return value + "x"
    if isinstance(value, np.ndarray):
        return value + 1
    if isinstance(value, list | tuple):
        return type(value)(value[:-1]) if value else type(value)((1,))
    if isinstance(value, dict):
        return {k: _changed(v) for k, v in value.items()}
    return None  # a nested part (the camera) or None: changed to None / from None


def test_fingerprint_covers_every_field():
    from restircl_blender.export import Export

    sc = _every_field_scene()
    base = Export(scene=sc, frames=[1, 2]).fingerprint()
    assert Export(scene=_every_field_scene(), frames=[1, 2]).fingerprint() == base
    assert Export(scene=sc, frames=[1, 3]).fingerprint() != base
    parts = [sc, sc.meshes[0], sc.materials[0], sc.lights[0], sc.camera, sc.environment]
    assert {type(p) for p in parts} == {restircl.Scene, restircl.Mesh, restircl.Material, restircl.Light,
                                        restircl.Camera, restircl.Environment}
    checked = []
    for part in parts:
        for f in dataclasses.fields(part):
            if not f.compare:
                continue
            old = getattr(part, f.name)
            setattr(part, f.name, _changed(old))
            try:
                assert Export(scene=sc, frames=[1, 2]).fingerprint() != base, f"{type(part).__name__}.{f.name}"
            finally:
                setattr(part, f.name, old)
            checked.append(f"{type(part).__name__}.{f.name}")
    assert "Light.soft_falloff" in checked
    assert Export(scene=sc, frames=[1, 2]).fingerprint() == base


def test_fingerprint_refuses_values_without_a_stable_hash():
    from restircl_blender.export import Export

    sc = _every_field_scene()
    sc.lights[0].name = object()  # its repr holds an address: equal scenes would never match
    with pytest.raises(TypeError, match=r"lights\[0\]\.name"):
        Export(scene=sc, frames=[1]).fingerprint()


@needs_renderer
def test_soft_falloff_toggle_between_renders_rebuilds_the_renderer(tmp_path):
    from restircl_blender import engine

    sc = scenes.new_scene(24, 16, engine="RESTIRCL")
    scenes.quad("Floor", 6.0, 6.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    lamp = scenes.light("POINT", "Near", (0, 0, 0.4), energy=40.0, shadow_soft_size=0.3, use_soft_falloff=True)
    scenes.camera((0, -3, 2), (0, 0, 0))
    sc.restircl.method = "reference"
    sc.restircl.samples = 1
    key = (sc.name, sc.view_layers[0].name)
    render_to(sc, tmp_path / "soft.exr")
    first = engine._SESSIONS[key].renderer
    lamp.data.use_soft_falloff = False
    render_to(sc, tmp_path / "hard.exr")
    assert engine._SESSIONS[key].renderer is not first
    soft = read_exr_passes(tmp_path / "soft.exr")["Combined"][..., :3]
    hard = read_exr_passes(tmp_path / "hard.exr")["Combined"][..., :3]
    assert not np.allclose(soft, hard, rtol=1e-3)
