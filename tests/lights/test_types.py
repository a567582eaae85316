"""One place per light type: each device type's code and flags are defined once on each side of the host/device line
(opencl/lights/<type>.h, restircl/lights/<type>.py) and agree on the device; every scene light has exactly one type;
the dispatch header compiles each type behind its own feature flag; the types read their record through named
fields."""

import re

import numpy as np
import pyopencl as cl
import pytest
from restircl import Environment, Light
from restircl.core.program import build_program, opencl_dir
from restircl.lights.device_lights import scene_lights
from restircl.lights.record import FLAG_TWO_SIDED
from restircl.lights.registry import SCENE_LIGHT_TYPES, TYPES, type_of
from restircl.lights.sphere import FLAG_SOFT_FALLOFF
from restircl.render.features import ALL_FLAGS, general_flags
from restircl.scene.light import AREA_SHAPES, LIGHT_TYPES

from ..helpers import device_ints, mixed_lights_scene

DEVICE_CONSTANTS = {**{f"LIGHT_{t.name.upper()}": t.code for t in TYPES},
                    "LIGHT_FLAG_TWO_SIDED": FLAG_TWO_SIDED, "LIGHT_FLAG_SOFT_FALLOFF": FLAG_SOFT_FALLOFF}


def test_codes_and_flags_agree_on_the_device(device):
    out = device_ints(device, "lights/lights.h", list(DEVICE_CONSTANTS))
    assert dict(zip(DEVICE_CONSTANTS, out, strict=True)) == DEVICE_CONSTANTS


def test_each_type_has_its_header_code_and_flag():
    assert sorted(t.code for t in TYPES) == list(range(len(TYPES)))
    for t in TYPES:
        header = (opencl_dir() / "lights" / f"{t.name}.h").read_text()
        assert f"#define LIGHT_{t.name.upper()} {t.code}" in header, t.name
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
    """A type's header is all a kernel needs to use that type (what a new type's author starts from)."""
    src = f"""
#include "lights/{name}.h"
__kernel void one(const __global Light* l, __global float4* out)
{{
    float pdf;
    float2 uv = {name}_sample(l, (float3)(0.0f), 0.5f, 0.5f, &pdf);
    LightEval e;
    out[0] = (float4)(uv, pdf, {name}_eval(l, uv.x, uv.y, (float3)(0.0f), (float3)(0.0f, 0.0f, 1.0f), &e));
}}
"""
    assert build_program(device, {}, source=src).one is not None
