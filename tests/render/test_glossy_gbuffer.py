"""The G-buffer extension of glossy scenes (GlossySample, written by primary when HAS_GLOSSY): it holds the true
view direction and one lobe per closure with a specular part; diffuse-only scenes build without HAS_GLOSSY and
keep only a placeholder; the specialised glossy build gives the images of the general build; and
surface_material_similar tells lobes of different roughness or metallic share apart."""

import numpy as np
import pyopencl as cl
import pytest
from restircl.core import layouts as L
from restircl.core.program import build_program
from restircl.render.features import general_flags
from restircl.scenes.builtin import cornell_box, material_balls

from ..helpers import Renderer, Settings
from .test_features import OUTPUTS, render_sequence


def test_diffuse_scene_has_no_extension(device):
    r = Renderer(cornell_box(16, 16), Settings(method="ris"), device)
    assert not r.flags["HAS_GLOSSY"] and "glossy" not in r.features
    assert r.history.glossy_bytes == 16 and r.device_scene.ggx_tables_buf is None


def test_extension_holds_view_direction_and_lobes(device):
    w, h = 48, 27
    scene = material_balls(w, h)
    r = Renderer(scene, Settings(method="ris", jitter=False), device)
    assert r.flags["HAS_GLOSSY"] and r.history.glossy_bytes == w * h * L.GLOSSY_SAMPLE.itemsize
    r.render_frame(0)
    slot = r.history.prev  # the frame just rendered
    q = r.device.queue
    g = np.empty(w * h, L.GSAMPLE)
    x = np.empty(w * h, L.GLOSSY_SAMPLE)
    cl.enqueue_copy(q, g, r.history.gbuf(slot))
    cl.enqueue_copy(q, x, r.history.glossy(slot))
    hit = L.float_bits_to_int(g["normal"][:, 3]) >= 0
    eye = scene.camera.transforms[0][:3, 3]
    want = eye - g["pos"][hit, :3]
    want /= np.linalg.norm(want, axis=1, keepdims=True)
    np.testing.assert_allclose(x["wo"][hit, :3], want, atol=1e-4)
    obj = L.float_bits_to_int(g["albedo"][:, 3])
    lobes = L.float_bits_to_int(x["wo"][:, 3])
    assert np.all(lobes[hit & (obj == 0)] == 0)  # the diffuse floor
    assert np.all(lobes[hit & (obj > 0)] == 1)  # every sphere, the Mix of diffuse and glossy too
    assert np.all(np.isfinite(x["lobe0"]["c"][hit]))  # the weights of the metallic part


@pytest.mark.parametrize("method", ["ris", "restir", "reference"])
def test_specialised_and_general_glossy_builds_give_identical_images(device, method):
    s = dict(method=method, seed=17, taa=method == "restir")
    spec = render_sequence(material_balls(24, 14), Settings(**s), device)
    gen = render_sequence(material_balls(24, 14), Settings(**s, specialise=False), device)
    for k, (a, b) in enumerate(zip(spec, gen, strict=True)):
        for out in OUTPUTS:
            x, y = getattr(a, out), getattr(b, out)
            assert np.array_equal(x, y), (method, k, out)


SIMILAR_SRC = """
#include "types.h"
#include "numerics.h"
#include "sampling/rng.h"
#include "lights/lights.h"
#include "surface/surface.h"

/* lobes: (roughness, metal weight, dielectric weight) per surface; out: surface_material_similar(0, k) */
__kernel void similar(const __global float4* lobes, __global int* out)
{
    int k = get_global_id(0);
    Surface s[2];
    for (int j = 0; j < 2; ++j) {
        float4 p = lobes[j == 0 ? 0 : k];
        s[j].mat.albedo = (float3)(0.2f);
        s[j].mat.lobes = p.w > 0.0f ? 1 : 0;
        MicrofacetReflection m = {(float3)(1.0f), p.x * p.x, (float3)(0.0f), 1.5f, (float3)(p.y), 0.04f,
                                  (float3)(0.04f), (float3)(p.z)};
        Lobe l = microfacet_reflection_lobe(&m, 1.0f);
        s[j].mat.lobe[0] = l;
        s[j].mat.lobe[1] = l;
    }
    out[k] = surface_material_similar(&s[0], &s[1]) ? 1 : 0;
}
"""


def test_material_similarity_rejects_other_roughness_and_metallic(device):
    cases = [((0.3, 0.0, 1.0, 1.0), 1),  # itself
             ((0.35, 0.0, 1.0, 1.0), 1),  # roughness within 0.15
             ((0.6, 0.0, 1.0, 1.0), 0),  # rougher
             ((0.3, 1.0, 0.0, 1.0), 0),  # a metal
             ((0.3, 0.0, 1.0, 0.0), 0)]  # no lobe: diffuse
    lobes = np.array([c for c, _ in cases], np.float32)
    prog = build_program(device, general_flags(), source=SIMILAR_SRC)
    mf = cl.mem_flags
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=lobes)
    out = np.empty(len(cases), np.int32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "similar")(device.queue, (len(cases),), None, lb, ob)
    cl.enqueue_copy(device.queue, out, ob)
    assert out.tolist() == [w for _, w in cases]


def test_diffuse_build_shades_a_mix_of_diffuse_closures_with_its_weights(device):
    from restircl import Material

    scene = cornell_box(16, 16)
    a, b = Material("a", (0.9, 0.1, 0.1), kind="diffuse"), Material("b", (0.1, 0.1, 0.9), kind="diffuse")
    scene.materials[0] = Material.mixed(a, b, 0.25, name="mix")
    r = Renderer(scene, Settings(method="ris", jitter=False), device)
    assert not r.flags["HAS_GLOSSY"]
    albedo = r.render_frame(0).albedo
    want = np.array([0.75 * 0.9 + 0.25 * 0.1, 0.1, 0.75 * 0.1 + 0.25 * 0.9], np.float32)
    floor = np.all(np.abs(albedo - want) < 1e-6, axis=-1)
    assert floor.sum() > 10  # the white walls and floor now show the mix
