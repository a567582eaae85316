"""One place per light type: each device type's code is defined once, in its host module (restircl/lights/<type>.py;
opencl/codes.h is generated from it, tests/upload/test_codes.py checks the device reads it); every scene light has
exactly one type; the dispatch headers compile each type behind its own feature flag; the types read their record
through named fields. And every fact of a type, checked per registered type by name, so that a new type that forgets
one fails here: its tree bounds hold its lights' points (or it is DISTANT, and its points are at infinity), its host and
device say alike which of its lights rays meet (the camera's rule), its header defines each function the dispatches
call and each dispatch reaches it, a BSDF ray that meets one of its sampled points finds that point and its density
again, its area-sampling rule answers for its records, and its closed form (the stress suite's reference) matches the
device's estimate or says there is none."""

import re

import numpy as np
import pyopencl as cl
import pytest
from restircl import Environment, Light, Scene, look_at
from restircl.core.program import build_program, opencl_dir
from restircl.lights.bounds import DISTANT, Bounds
from restircl.lights.device_lights import DeviceLights, scene_lights
from restircl.lights.light_type import LightType, NoClosedForm, NotAnalytic, SceneLightType
from restircl.lights.registry import SCENE_LIGHT_TYPES, TYPES, type_of
from restircl.render.features import ALL_FLAGS, general_flags
from restircl.scene.light import AREA_SHAPES, LIGHT_TYPES
from restircl.upload.codes import families

from ..helpers import mixed_lights_scene


def test_each_type_has_its_header_code_and_flag():
    light_codes = next(f for f in families() if f.title == "light types").codes
    assert sorted(t.code for t in TYPES) == list(range(len(TYPES)))
    for t in TYPES:
        assert (opencl_dir() / "lights" / f"{t.name}.h").is_file(), t.name
        assert (f"LIGHT_{t.name.upper()}", t.code) in dict(light_codes).items(), t.name  # opencl/codes.h
        # the world is one light, not a kind of lights: its flag is HAS_ENVIRONMENT
        flag = "HAS_ENVIRONMENT" if t.name == "environment" else f"HAS_{t.name.upper()}_LIGHTS"
        assert t.flag == flag and t.flag in ALL_FLAGS
        assert f"#ifdef {t.flag}" in (opencl_dir() / "lights/lights.h").read_text()


@pytest.mark.parametrize("kind", LIGHT_TYPES)
def test_every_scene_light_has_exactly_one_type(kind):
    for shape in AREA_SHAPES if kind == "area" else ("SQUARE",):
        lt = Light("l", kind, shape=shape)
        takers = [t.name for t in SCENE_LIGHT_TYPES if t.accepts(lt)]
        assert len(takers) == 1 and type_of(lt).name == takers[0], (kind, shape, takers)


def test_type_code_reads_its_lanes_only_in_its_decode_step():
    """Outside lights/record.h (the lanes every type shares), a record's lanes are read only in brace initialisers of
    the decode steps (e.g. `SunLight s = {l->a.xyz, l->b.x, l->b.y};`), so the code after them uses named fields."""
    lane = re.compile(r"->\s*[pabL]\.")
    decode = re.compile(r"^\s*\w+ \w+ = \{.*\};$")
    for path in sorted((opencl_dir() / "lights").glob("*.h")):
        if path.name == "record.h":
            continue
        for no, line in enumerate(path.read_text().splitlines(), 1):
            assert not lane.search(line) or decode.match(line), f"{path.name}:{no}: {line.strip()}"


EVAL_SRC = """
#include "lights/lights.h"
__kernel void eval_all(const __global Light* lights, int n, const __global float4* pts, __global float4* out)
{
    int i = get_global_id(0);
    float3 x = pts[i].xyz, nrm = (float3)(0.0f, 0.0f, 1.0f);
    float u = 0.1f + 0.8f * (float)(i % 7) / 7.0f, v = 0.05f + 0.9f * (float)(i % 11) / 11.0f;
    for (int l = 0; l < n; ++l) {
        float pdf;
        float2 uv = light_sample(&lights[l], x, u, v, &pdf);
        LightEval e;
        bool ok = light_eval(&lights[l], uv.x, uv.y, x, nrm, &e);
        __global float4* o = &out[(i * n + l) * 3];
        o[0] = (float4)(uv, pdf, ok ? 1.0f : 0.0f);
        o[1] = ok ? (float4)(e.contrib, e.dist) : (float4)(0.0f);
        o[2] = ok ? (float4)(e.pos, e.eps) : (float4)(0.0f);
    }
}
"""


def _eval_all(device, flags, lights, pts) -> np.ndarray:
    prog = build_program(device, flags, source=EVAL_SRC)
    mf = cl.mem_flags
    recs = lights.records
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=lights.device_array())
    pb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=pts)
    out = np.zeros((len(pts), len(recs), 3, 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    prog.eval_all(device.queue, (len(pts),), None, lb, np.int32(len(recs)), pb, ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def test_dispatch_compiles_each_type_behind_its_flag(device):
    """A build with one type's flag evaluates that type bit for bit as the general build does, and samples nothing
    of the types it leaves out."""
    scene = mixed_lights_scene()
    scene.environment = Environment("sky", color=(1, 1, 1), image=np.linspace(0.1, 1, 96).reshape(4, 8, 3))
    lights = scene_lights(scene, 0)
    assert lights.type_set == {t.code for t in TYPES}
    rng = np.random.default_rng(2)
    pts = np.zeros((64, 4), np.float32)
    pts[:, :3] = rng.uniform((-1.5, -1.5, 0.0), (1.5, 1.5, 0.3), (64, 3))
    general = _eval_all(device, general_flags(), lights, pts)
    for t in TYPES:
        flags = dict.fromkeys(ALL_FLAGS, False) | {t.flag: True}
        one = _eval_all(device, flags, lights, pts)
        mine = lights.types == t.code
        assert general[:, mine, 0, 3].any(), t.name  # the type lights some point
        assert np.array_equal(one[:, mine].view(np.uint32), general[:, mine].view(np.uint32)), t.name
        assert not one[:, ~mine, 0, 2:].any(), t.name  # pdf 0, no contribution


@pytest.mark.parametrize("name", [t.name for t in TYPES])
def test_each_type_header_builds_alone(device, name):
    """A type's header is all a kernel needs to use that type (what a new type's author starts from), every function
    the dispatches call included."""
    src = f"""
#include "lights/{name}.h"
__kernel void one(const __global Light* l, __global float4* out)
{{
    float pdf;
    float3 x = (float3)(0.0f), n = (float3)(0.0f, 0.0f, 1.0f);
    float2 uv = {name}_sample(l, x, 0.5f, 0.5f, &pdf);
    LightEval e;
    bool ok = {name}_eval(l, uv.x, uv.y, x, n, &e);
    float2 hit_uv;
    bool hit = {name}_hittable(l) && {name}_hit(l, x, n, &hit_uv);
    out[0] = (float4)(uv, pdf, ok);
    out[1] = (float4)({name}_point_pdf(l, x, &e), hit, hit_uv);
    out[2] = (float4)({name}_hit_radiance(l, x, uv), 0.0f);
}}
"""
    assert build_program(device, {}, source=src).one is not None


# ---- every fact of every type, by name ------------------------------------------------------------------------------

#: each dispatch function (lights/lights.h) and the function of each type it calls: <name>_<suffix>
DISPATCH = {"lights.h": {"light_eval": "eval", "light_sample_typed": "sample", "light_hit": "hit",
                         "light_point_pdf": "point_pdf", "light_type_hittable": "hittable",
                         "light_hit_radiance": "hit_radiance"}}


def _function_body(text: str, name: str) -> str:
    start = text.index(f" {name}(")
    open_brace = text.index("{", start)
    depth, k = 0, open_brace
    while True:
        depth += {"{": 1, "}": -1}.get(text[k], 0)
        if depth == 0:
            return text[open_brace:k + 1]
        k += 1


@pytest.mark.parametrize("name", [t.name for t in TYPES])
def test_type_defines_each_device_function_and_each_dispatch_reaches_it(name):
    t = next(t for t in TYPES if t.name == name)
    header = (opencl_dir() / "lights" / f"{name}.h").read_text()
    assert f'#include "lights/{name}.h"' in (opencl_dir() / "lights/lights.h").read_text()
    for file, calls in DISPATCH.items():
        text = (opencl_dir() / "lights" / file).read_text()
        for dispatch, suffix in calls.items():
            fn = f"{name}_{suffix}"
            assert re.search(rf"^inline \w+ {fn}\(", header, re.M), f"lights/{name}.h defines no {fn}"
            case = rf"#ifdef {t.flag}\s+case LIGHT_{name.upper()}: return {fn}\("
            assert re.search(case, _function_body(text, dispatch)), f"{file} {dispatch} does not call {fn}"


def _records_of(t: LightType, lights: DeviceLights) -> tuple[np.ndarray, np.ndarray]:
    mine = lights.types == t.code
    assert mine.any(), f"the test scene has no {t.name} light"
    rec = lights.records[mine]
    return rec.view(np.float32).reshape(-1, 16).astype(np.float64), rec.view(np.int32).reshape(-1, 16)[:, 15]


def _all_types_scene() -> Scene:
    """mixed_lights_scene (every type, shapes and deltas) with a world, a delta sun and a spot with a radius."""
    scene = mixed_lights_scene()
    scene.environment = Environment("sky", color=(1, 1, 1), image=np.linspace(0.1, 1, 96).reshape(4, 8, 3))
    scene.lights += [Light("delta_sun", "sun", (1, 1, 1), 0.5, look_at((0.3, -1.0, 2.0), (0, 0, 0))),
                     Light("round_spot", "spot", (1, 0.8, 0.6), 200.0, look_at((-1.0, 1.0, 1.2), (-0.5, 0.5, 0)),
                           radius=0.1, spot_size=1.2)]
    return scene


def _all_types_lights() -> DeviceLights:
    lights = scene_lights(_all_types_scene(), 0)
    assert lights.type_set == {t.code for t in TYPES}
    return lights


@pytest.mark.parametrize("name", [t.name for t in TYPES])
def test_type_states_its_host_facts(name):
    """Bounds (or DISTANT), the area-sampling rule and the closed form answer for the type's records; a scene type
    also says which scene lights it takes and whether they have a shape."""
    t = next(t for t in TYPES if t.name == name)
    lanes, flags = _records_of(t, _all_types_lights())
    k = len(lanes)
    if t.bounds != DISTANT:
        b = t.bounds(lanes, flags)
        assert isinstance(b, Bounds)
        for v, shape in ((b.lo, (k, 3)), (b.hi, (k, 3)), (b.axis, (k, 3)), (b.theta_o, (k,)), (b.theta_e, (k,)),
                         (b.two_sided, (k,))):
            assert np.shape(v) == shape, name
        assert np.all(b.lo <= b.hi), name
    wants = t.solid_angle(lanes, flags)
    assert wants.dtype == bool and wants.shape == (k,), name
    assert callable(t.analytic)
    if isinstance(t, SceneLightType):
        assert t in SCENE_LIGHT_TYPES
        for f in (t.accepts, t.record, t.power, t.has_shape):
            assert callable(f), name


PROBE_SRC = """
#include "lights/lights.h"
/* per (point i, light l, sample k): sample, evaluate, and what a ray towards the evaluated point finds again */
__kernel void probe(const __global Light* lights, int n, int side, const __global float4* pts,
                    const __global float4* normals, __global float4* out)
{
    int g = get_global_id(0), per = side * side;
    int k = g % per, l = (g / per) % n, i = g / (per * n);
    float3 x = pts[i].xyz, nrm = normals[i].xyz;
    float u = ((float)(k % side) + 0.5f) / (float)side, v = ((float)(k / side) + 0.5f) / (float)side;
    const __global Light* rec = &lights[l];
    int type = light_type(rec);
    float pdf;
    float2 uv = light_sample(rec, x, u, v, &pdf);
    LightEval e, h;
    bool ok = pdf > 0.0f && light_eval(rec, uv.x, uv.y, x, nrm, &e);
    bool hittable = light_hittable(rec, type, l, n, 1);  /* as BSDF candidates testing every light see them */
    float2 huv = (float2)(0.0f);
    bool hit = ok && hittable && type != LIGHT_TRIANGLE && light_hit(rec, type, x, e.wi, &huv);
    bool hok = hit && light_eval(rec, huv.x, huv.y, x, nrm, &h);
    __global float4* o = out + 5 * g;
    o[0] = (float4)(uv, pdf, ok ? 1.0f : 0.0f);
    o[1] = ok ? (float4)(e.contrib, e.dist) : (float4)(0.0f);
    o[2] = ok ? (float4)(e.pos, light_point_pdf(rec, type, x, &e)) : (float4)(0.0f);
    o[3] = (float4)(hittable ? 1.0f : 0.0f, hit ? 1.0f : 0.0f, hok ? 1.0f : 0.0f, hok ? h.dist : 0.0f);
    o[4] = hok ? (float4)(h.pos, 0.0f) : (float4)(0.0f);
}
"""


def _probe(device, lights: DeviceLights, pts: np.ndarray, normals: np.ndarray, side: int) -> dict[str, np.ndarray]:
    """(points, lights, side^2) arrays of what PROBE_SRC gives."""
    prog = build_program(device, general_flags(), source=PROBE_SRC)
    mf = cl.mem_flags
    p4 = np.zeros((len(pts), 4), np.float32)
    n4 = np.zeros((len(pts), 4), np.float32)
    p4[:, :3], n4[:, :3] = pts, normals
    n = len(lights)
    out = np.zeros((len(pts) * n * side * side, 5, 4), np.float32)
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=lights.device_array())
    pb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=p4)
    nb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=n4)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "probe")(device.queue, (len(out),), None, lb, np.int32(n), np.int32(side), pb, nb, ob)
    cl.enqueue_copy(device.queue, out, ob)
    o = out.reshape(len(pts), n, side * side, 5, 4).astype(np.float64)
    return {"pdf": o[..., 0, 2], "ok": o[..., 0, 3] > 0, "contrib": o[..., 1, :3], "dist": o[..., 1, 3],
            "pos": o[..., 2, :3], "point_pdf": o[..., 2, 3], "hittable": o[..., 3, 0] > 0, "hit": o[..., 3, 1] > 0,
            "hit_ok": o[..., 3, 2] > 0, "hit_dist": o[..., 3, 3], "hit_pos": o[..., 4, :3]}


@pytest.fixture(scope="module")
def around(device):
    """Probes of every light from points all around the scene and over the floor, each with the six axis normals (so
    that every point of a light faces some shading normal)."""
    lights = _all_types_lights()
    rng = np.random.default_rng(7)
    g = np.linspace(-1.6, 1.6, 9)
    floor = np.stack(np.meshgrid(g, g, [0.05]), axis=-1).reshape(-1, 3)  # where the spot's cone lands
    pts = np.vstack([rng.uniform((-2.0, -2.0, -1.0), (2.0, 2.0, 2.0), (16, 3)), floor])
    pts = np.repeat(pts, 6, axis=0)
    normals = np.tile(np.vstack([np.eye(3), -np.eye(3)]), (len(pts) // 6, 1))
    return lights, _probe(device, lights, pts, normals, side=8)


@pytest.mark.parametrize("name", [t.name for t in TYPES])
def test_tree_bounds_hold_the_type_lights(around, name):
    """Every point light sampling reaches of a light lies in its type's box; a DISTANT type's points are at
    infinity (it has no position to bound)."""
    lights, pr = around
    t = next(t for t in TYPES if t.name == name)
    mine = np.flatnonzero(lights.types == t.code)
    ok = pr["ok"][:, mine]
    assert ok.any(), name
    if t.bounds == DISTANT:
        assert np.all(np.isinf(pr["dist"][:, mine][ok])), name
        return
    lanes, flags = _records_of(t, lights)
    b = t.bounds(lanes, flags)
    pos = pr["pos"][:, mine]  # (P, lights, K, 3)
    tol = 1e-5 * (1.0 + np.abs(pos))
    inside = (pos >= b.lo[None, :, None] - tol) & (pos <= b.hi[None, :, None] + tol)
    assert np.all(inside.all(axis=-1)[ok]), name


@pytest.mark.parametrize("name", [t.name for t in TYPES])
def test_rays_find_the_type_sampled_points_again(around, name):
    """What the BSDF candidates rely on: a ray from x towards a point light sampling gave hits that point again
    and the density light_point_pdf gives the point is the one it was sampled with, for every light a ray can meet.
    Emissive triangles are found by the BVH, not by light_hit: only their density is compared."""
    lights, pr = around
    t = next(t for t in TYPES if t.name == name)
    mine = lights.types == t.code
    hittable = pr["hittable"][:, mine] & pr["ok"][:, mine]
    if not hittable.any():
        assert not any(type_of(lt).has_shape(lt) for lt in _all_types_scene().lights if type_of(lt) is t), name
        return
    # the density of the point: the sampled one, to float32 rounding of two computations
    pdf, point_pdf = pr["pdf"][:, mine][hittable], pr["point_pdf"][:, mine][hittable]
    np.testing.assert_allclose(point_pdf, pdf, rtol=2e-3, err_msg=name)
    if t.name == "triangle":  # geometry: the BVH finds them (direct/bsdf_candidates.h)
        return
    assert np.all(pr["hit_ok"][:, mine][hittable]), f"{name}: a ray towards a sampled point missed it"
    a, b = pr["pos"][:, mine][hittable], pr["hit_pos"][:, mine][hittable]
    finite = np.isfinite(pr["dist"][:, mine][hittable])
    scale = 1.0 + np.abs(a[finite]).max(axis=-1, keepdims=True)
    assert np.all(np.abs(a[finite] - b[finite]) <= 1e-3 * scale), name


@pytest.mark.parametrize("name", [t.name for t in SCENE_LIGHT_TYPES])
def test_host_and_device_agree_which_lights_rays_meet(around, name):
    """The camera's rule: the host lists the lights that have a shape (has_shape, lights/<type>.py), the device
    meets exactly those (<type>_hittable, opencl/lights/<type>.h)."""
    lights, pr = around
    scene = _all_types_scene()
    t = next(t for t in SCENE_LIGHT_TYPES if t.name == name)
    compared = 0
    for i, lt in enumerate(scene.lights):
        if type_of(lt) is not t:
            continue
        record = int(np.flatnonzero(lights.source == i)[0])
        device_says = bool(pr["hittable"][0, record, 0])
        assert t.has_shape(lt) == device_says, (name, lt.name)
        compared += 1
    assert compared, name


@pytest.mark.parametrize("name", [t.name for t in TYPES])
def test_closed_form_matches_the_device(device, name):
    """The stress suite's reference for the type (LightType.analytic): the direct light of each of its lights on
    floor points matches the device's own estimate from 64 x 64 stratified light samples, or the type says it has
    no closed form."""
    t = next(t for t in TYPES if t.name == name)
    lights = _all_types_lights()
    lanes, flags = _records_of(t, lights)
    x = np.array([[0.2, 0.3, 0.0], [-0.5, 0.8, 0.0], [1.0, -0.2, 0.0], [0.6, 0.9, 0.0]])
    n = np.tile([0.0, 0.0, 1.0], (len(x), 1))
    try:
        exact = t.analytic(x, n, lanes, flags)[..., None] * lanes[None, :, 12:15]  # (P, S, 3)
    except NotAnalytic:
        assert isinstance(t.analytic, NoClosedForm), f"{name}: the closed form refuses the probe points"
        return
    pr = _probe(device, lights, x, n, side=64)
    mine = lights.types == t.code
    with np.errstate(invalid="ignore", divide="ignore"):
        est = np.where(pr["ok"][..., None], pr["contrib"] / pr["pdf"][..., None], 0.0)[:, mine].mean(axis=2)
    assert exact.max() > 0, f"{name}: no light of the type reaches the probe points"
    np.testing.assert_allclose(est, exact, rtol=1e-2, atol=1e-4 * exact.max(), err_msg=name)
