"""BSDF-sampled RIS candidates with MIS (opencl/direct/bsdf_candidates.h, lights/lights.h): a ray aimed at a light
sample finds that sample again, with the density light sampling gave it; RIS and every unbiased ReSTIR mode with BSDF
candidates agree with the exhaustive reference on large lights of every type (where the BSDF strategy matters),
occluded ones and ones behind the surface; and the candidates cut the variance where lights are large and close."""

import math

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
import pytest
from restircl import Camera, Light, Material, Mesh, Scene, Settings, look_at, scenes, translation
from restircl.core.program import build_program
from restircl.lights.device_lights import scene_lights
from restircl.render.features import general_flags

from ..bias_controls import built_with
from ..helpers import (
    allowed_outliers,
    batch_stats,
    below_only_scene,
    collect,
    constant,
    luminance,
    mean_and_se,
    print_power,
    run_means,
)
from ..materials.bsdf_kernels import SRC as BSDF_SRC
from ..materials.bsdf_kernels import BsdfKernels, Closure, view
from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
/* per work-item: sample the light from x, aim a ray at the sampled point, and find it again by light_hit */
__kernel void hit_again(const __global Light* lights, float4 x4, float4 n4, __global float4* out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, 9u, 0u);
    float r0 = rng_next(&rng), r1 = rng_next(&rng);
    const __global Light* l = &lights[0];
    int type = light_type(l);
    float pdf;
    float2 uv = light_sample(l, x4.xyz, r0, r1, &pdf);
    LightEval e, e2;
    bool ok = pdf > 0.0f && light_eval(l, uv.x, uv.y, x4.xyz, n4.xyz, &e);
    float2 uv2 = (float2)(-1.0f);
    bool hit = ok && light_hit(l, type, x4.xyz, e.wi, &uv2);
    bool ok2 = hit && light_eval(l, uv2.x, uv2.y, x4.xyz, n4.xyz, &e2);
    out[3 * i + 0] = (float4)(ok ? e.pos : (float3)(0.0f), ok ? pdf : 0.0f);
    out[3 * i + 1] = (float4)(ok2 ? e2.pos : (float3)(0.0f), ok2 ? light_point_pdf(l, type, x4.xyz, &e2) : -1.0f);
    out[3 * i + 2] = (float4)(ok ? e.wi : (float3)(0.0f), ok2 ? dot3(e.wi, e2.wi) : -2.0f);
}
/* triangle_uv inverts triangle_eval's map of (u, v) to barycentrics */
__kernel void triangle_inverse(__global float2* uv)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, 3u, 0u);
    float u = rng_next(&rng), v = rng_next(&rng);
    float su = sqrt(u);
    uv[2 * i] = (float2)(u, v);
    uv[2 * i + 1] = triangle_uv(su * (1.0f - v), su * v);
}
"""

N = 4096
X, NRM = (0.1, -0.2, 0.0), (0.0, 0.0, 1.0)

HIT_LIGHTS = {
    "quad": Light("q", "area", power=50.0, transforms=translation(0.3, 0.2, 1.0), shape="RECTANGLE", size=1.2,
                  size_y=0.7),
    "disk": Light("d", "area", power=50.0, transforms=translation(-0.4, 0.1, 0.8), shape="ELLIPSE", size=1.0,
                  size_y=0.6),
    "sphere": Light("s", "point", power=50.0, transforms=translation(0.5, 0.5, 1.2), radius=0.4, soft_falloff=False),
    "soft_sphere": Light("ss", "point", power=50.0, transforms=translation(-0.5, 0.3, 0.9), radius=0.3),
    # sphere_hit's early rejection by the ray's distance from the centre must keep the disk's rim: a small far disk
    # (many_lights' kind) and one far from the origin, where the margin's float32 terms are large
    "soft_sphere_far": Light("sf", "point", power=50.0, transforms=translation(9.0, -7.0, 4.0), radius=0.05),
    "soft_sphere_offset": Light("so", "point", power=50.0, transforms=translation(3e3, 1e3, 2e3), radius=2.0),
    "spot": Light("sp", "spot", power=50.0, transforms=look_at((0.0, 0.0, 1.5), (0.1, -0.2, 0.0)), radius=0.25,
                  spot_size=1.2),
    "sun": Light("sun", "sun", power=2.0, transforms=look_at((1, -1, 3), (0, 0, 0)), angle=0.3),
    "tiny_sun": Light("ts", "sun", power=2.0, transforms=look_at((1, -1, 3), (0, 0, 0)), angle=1e-3),
}


@pytest.mark.parametrize("name", list(HIT_LIGHTS))
def test_a_ray_at_a_light_sample_finds_it_again_with_its_pdf(device, name):
    recs = scene_lights(Scene(lights=[HIT_LIGHTS[name]]), 0).records
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=recs)
    out = np.empty((N, 3, 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "hit_again")(device.queue, (N,), None, lb, clt.make_float4(*X, 0.0), clt.make_float4(*NRM, 0.0),
                                 ob)
    cl.enqueue_copy(device.queue, out, ob)
    ok = out[:, 0, 3] > 0
    assert ok.sum() > N // 2, name
    found = out[ok, 1, 3] >= 0
    assert found.all(), (name, int((~found).sum()))
    if name.endswith("sun"):  # a direction: the two evaluations' directions agree
        assert np.all(out[ok, 2, 3] > 1.0 - 1e-6), (name, out[ok, 2, 3].min())
    else:
        scale = np.linalg.norm(out[ok, 0, :3] - np.array(X), axis=1)
        err = np.linalg.norm(out[ok, 0, :3] - out[ok, 1, :3], axis=1) / scale
        assert err.max() < 1e-4, (name, err.max())
    rel = np.abs(out[ok, 1, 3] / out[ok, 0, 3] - 1.0)
    assert np.quantile(rel, 0.999) < 1e-3 and rel.max() < 1e-2, (name, rel.max())


def test_triangle_uv_inverts_the_barycentric_map(device):
    prog = build_program(device, general_flags(), source=SRC)
    out = np.empty((N, 2, 2), np.float32)
    ob = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "triangle_inverse")(device.queue, (N,), None, ob)
    cl.enqueue_copy(device.queue, out, ob)
    assert np.abs(out[:, 0] - out[:, 1]).max() < 1e-4


def large_lights_scene(width: int = 16, height: int = 12, glossy: bool = False) -> Scene:
    """Large, close lights of every type that a ray can hit, where BSDF sampling matters: an area quad and an
    ellipse, a sphere and a soft-falloff sphere, a spot with a radius, a wide sun, an emissive panel (two
    triangles) partly behind a block, plus a point light (a delta: light sampling only) and lights below the
    floor (no contribution). glossy: a polished dielectric floor (roughness 0.2) and a metal block (0.3)."""
    fv, ft = scenes.quad(4, 4)
    bv, bt = scenes.box((0.5, 0.5, 0.8))
    pv, pt = scenes.quad(1.0, 0.6)
    panel = pv @ np.array([[1, 0, 0], [0, 0, 1], [0, 1, 0]]).T + (0.9, 0.9, 0.7)  # vertical, facing -y and +y
    below_v = pv + (-0.5, 0.5, -0.2)
    materials = [Material("floor", (0.7, 0.7, 0.7)), Material("panel", (0, 0, 0), (1.0, 0.9, 0.7), 8.0)]
    if glossy:
        materials[0] = Material("floor", (0.5, 0.5, 0.5), roughness=0.2, specular=0.5)
        materials.append(Material("metal", (0.9, 0.7, 0.5), metallic=1.0, roughness=0.3))
    meshes = [Mesh("floor", fv, ft, 0), Mesh("block", bv + (0.5, 0.2, 0.4), bt, 2 if glossy else 0),
              Mesh("panel", panel, pt, 1),
              Mesh("below", below_v, pt, 1)]
    lights = [
        Light("quad", "area", (1.0, 0.9, 0.8), 40.0, translation(-0.8, -0.6, 0.5), shape="RECTANGLE", size=1.2,
              size_y=0.8),
        Light("ellipse", "area", (0.8, 0.9, 1.0), 30.0, translation(0.9, -0.8, 0.6), shape="ELLIPSE", size=0.9,
              size_y=0.6),
        Light("sphere", "point", (1.0, 0.8, 0.6), 60.0, translation(-1.0, 1.0, 0.6), radius=0.35,
              soft_falloff=False),
        Light("soft", "point", (0.6, 0.8, 1.0), 40.0, translation(0.0, 0.0, 1.2), radius=0.4),
        Light("spot", "spot", (1, 1, 1), 200.0, look_at((-1.4, 0.0, 1.0), (-1.0, 0.0, 0.0)), radius=0.3,
              spot_size=1.4, spot_blend=0.3),
        Light("sun", "sun", (1.0, 1.0, 0.9), 1.5, look_at((1, -2, 2), (0, 0, 0)), angle=0.25),
        Light("point", "point", (1.0, 1.0, 1.0), 20.0, translation(0.5, -1.2, 0.8)),
        Light("below", "area", (1, 1, 1), 300.0, translation(0.3, -0.2, -0.4), size=1.5),
    ]
    cam = Camera(look_at((0.0, -3.0, 2.6), (0.0, 0.1, 0.2)), width, height, lens=26.0)
    return Scene(meshes, materials, lights, cam, name="glossy_large_lights" if glossy else "large_lights")


W, H = 16, 12
BATCHES = 64
# Frame counts: the default suite runs "quick", a quarter of the frames of "full" (slow-marked, the figures in the
# docstrings); both judge by the measured standard errors, so quick only has half the resolution for a bias.
SIZES = {
    "quick": dict(frames=1024, runs=24, run_frames=32, reference=2048, glossy_reference=1024),
    "full": dict(frames=4096, runs=48, run_frames=64, reference=8192, glossy_reference=4096),
}
SIZE_PARAMS = [pytest.param("full", marks=pytest.mark.slow), "quick"]


@pytest.fixture(scope="module")
def references(reference_samples):
    """reference(glossy, size): batch statistics of the exhaustive sampler (the glossy twin's is noisier on the
    glossy floor: half the frames), rendered once per session (lights/test_area_sampling.py shares the quick one)."""
    cache: dict[tuple[bool, str], tuple[np.ndarray, np.ndarray]] = {}

    def get(glossy: bool, size: str) -> tuple[np.ndarray, np.ndarray]:
        if (glossy, size) not in cache:
            frames = SIZES[size]["glossy_reference" if glossy else "reference"]
            s = Settings(method="reference", seed=19 if glossy else 17, jitter=False)
            cache[glossy, size] = batch_stats(luminance(reference_samples(large_lights_scene(W, H, glossy), s,
                                                                          frames)), BATCHES)
        return cache[glossy, size]

    return get


def assert_unbiased(mean: np.ndarray, se: np.ndarray, ref: tuple[np.ndarray, np.ndarray], n_stats: int,
                    label: str, image_se: float | None = None) -> None:
    """Per pixel within 4 standard errors (outliers as the t-distribution allows) and the image mean too. image_se:
    the standard error of the image mean measured from independent runs (spatial reuse correlates neighbouring
    pixels, so their standard errors do not add up as independent ones); None: from the pixels' own."""
    mr, sr = ref
    sigma = np.sqrt(se**2 + sr**2)
    live = ~constant(sigma, mr)
    assert np.all(np.abs(mean - mr)[~live] <= 1e-5 * np.abs(mr[~live]) + 1e-12), label
    z = np.abs(mean - mr)[live] / sigma[live]
    se_img = math.sqrt(float((se**2).sum())) / se.size if image_se is None else image_se
    sr_img = math.sqrt(float((sr**2).sum())) / sr.size
    print_power(label, mean.mean() / mr.mean() - 1.0, math.hypot(se_img, sr_img) / mr.mean())
    assert (z > 4).sum() <= allowed_outliers(int(live.sum()), n_stats), (label, "outliers", np.sort(z)[-5:])
    assert abs(mean.mean() - mr.mean()) <= 4 * math.hypot(se_img, sr_img) + 1e-6 * mr.mean(), (
        label, "image means", mean.mean(), mr.mean())


RIS_CASES = {
    "one": dict(bsdf_candidates=1),
    "three": dict(bsdf_candidates=3),
    "tiles": dict(light_tiles="on", light_tile_count=4, light_tile_size=32),
    "glossy": dict(),  # the glossy twin: GGX lobes sampled and weighed by the Principled BSDF
    # a BSDF sample with its own shadow ray beside the reservoir's instead of the candidates (direct/bsdf_mis.h)
    "mis_sample": dict(bsdf_mis_sample=True),
    "glossy_mis_sample": dict(bsdf_mis_sample=True),
}


@pytest.mark.parametrize("size", SIZE_PARAMS)
@pytest.mark.parametrize("case", list(RIS_CASES))
def test_ris_with_bsdf_candidates_matches_reference(device, references, case, size):
    glossy = case.startswith("glossy")
    reference = references(glossy, size)
    s = Settings(method="ris", candidates=4, bsdf_sampling="on", seed=23, jitter=False, **RIS_CASES[case])
    x = collect(large_lights_scene(W, H, glossy), s, SIZES[size]["frames"], device)
    assert np.all(np.isfinite(x))
    m, se = batch_stats(luminance(x), BATCHES)
    assert_unbiased(m, se, reference, BATCHES, case)


RESTIR_CASES = {
    "pairwise": dict(),
    "pairwise_no_visibility": dict(visibility_reuse=False),
    "z_count": dict(bias_correction="z_count", m_cap=4.0),
    "z_count_spatial": dict(bias_correction="z_count", temporal=False),
    # glossy: the target and the BSDF candidates use the Principled BSDF for each pixel's view; reuse re-evaluates
    # it at the receiving pixel and rejects neighbours of another material (bsdf_sampling "auto" turns them on)
    "glossy_pairwise": dict(bsdf_sampling="auto"),
    "glossy_z_count": dict(bsdf_sampling="auto", bias_correction="z_count", m_cap=4.0),
}


@pytest.mark.parametrize("size", SIZE_PARAMS)
@pytest.mark.parametrize("case", list(RESTIR_CASES))
def test_restir_with_bsdf_candidates_matches_reference(device, references, case, size):
    glossy = case.startswith("glossy")
    reference = references(glossy, size)
    runs, run_frames = SIZES[size]["runs"], SIZES[size]["run_frames"]
    s = Settings(method="restir", **{"bsdf_sampling": "on", "jitter": False, "taa": False, "seed": 29,
                                     **RESTIR_CASES[case]})
    means = luminance(run_means(large_lights_scene(W, H, glossy), s, runs, run_frames, device))
    assert np.all(np.isfinite(means))
    m, se = mean_and_se(means)
    assert_unbiased(m, se, reference, runs, case)


@pytest.mark.parametrize("method", ["ris", "restir"])
def test_the_harness_rejects_light_candidates_without_the_mixture_pdf(device, references, method, monkeypatch):
    """Negative control at the quick size: light candidates weighed by their own pdf beside BSDF candidates (a dropped
    MIS weight, tests/bias_controls.py) must be rejected by the check above."""
    reference = references(False, "quick")
    built_with(monkeypatch, "TEST_WITHOUT_MIXTURE_PDF")
    q = SIZES["quick"]
    if method == "ris":
        s = Settings(method="ris", candidates=4, bsdf_sampling="on", seed=23, jitter=False, bsdf_candidates=1)
        m, se = batch_stats(luminance(collect(large_lights_scene(W, H), s, q["frames"], device)), BATCHES)
        n_stats = BATCHES
    else:
        s = Settings(method="restir", bsdf_sampling="on", jitter=False, taa=False, seed=29)
        m, se = mean_and_se(luminance(run_means(large_lights_scene(W, H), s, q["runs"], q["run_frames"], device)))
        n_stats = q["runs"]
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_unbiased(m, se, reference, n_stats, f"{method} without the mixture pdf")


@pytest.mark.parametrize("glossy", [False, True])
def test_bsdf_candidates_cut_the_variance_of_large_close_lights(device, glossy):
    """Not a timing test: per-frame variance of RIS with and without one BSDF candidate (same light candidates).
    Measured (16x12, 4096 frames): 8.1 -> 2.1 on the glossy twin."""
    scene = large_lights_scene(W, H, glossy)
    var = {}
    for mode in ("off", "on"):
        x = collect(scene, Settings(method="ris", candidates=4, bsdf_sampling=mode, seed=31, jitter=False), 512,
                    device)
        var[mode] = luminance(x).var(axis=0).mean()
    assert var["on"] < 0.8 * var["off"], var


def test_auto_adds_bsdf_candidates_only_where_a_material_is_glossy(device):
    from restircl import Renderer

    for glossy in (False, True):
        r = Renderer(large_lights_scene(W, H, glossy), Settings(method="ris"), device)
        r.render_frame(0, aovs=False)
        assert r.last_plan is not None and r.last_plan.bsdf_candidates == (1 if glossy else 0)


def test_lights_behind_the_surface_stay_exact_zero_with_bsdf_candidates(device):
    for method in ("ris", "restir"):
        samples = collect(below_only_scene(), Settings(method=method, bsdf_sampling="on", seed=3), 8, device)
        assert np.all(samples == 0.0), method


# ---- the BSDF strategy's density of a light sample: what the MIS weights assume ------------------------------

PICK_SRC = BSDF_SRC + """
#include "bvh/traverse.h"
#include "bvh/transparent.h"
#include "sampling/reservoir.h"
#include "direct/target.h"
#include "direct/visibility.h"
#include "lights/tree.h"
#include "direct/bsdf_candidates.h"

/* density = 0, per host uniform pair in[i]: the light sample (u, v) a BSDF direction of the test surface meets on
 * lights[0], z = 1 (z = 0 where it meets nothing). density = 1, per (u, v) in[i]: in x the BSDF strategy's density
 * of that sample as the MIS weights take it (bsdf_pdf_light_measure, in the light's measure) per unit square of
 * (u, v): divided by light_point_pdf, the light measure's density of a uniform (u, v) for these lights. */
__kernel void bsdf_light(const __global float* p, int count, const __global float* tab, float4 wo4,
                         const __global Light* lights, int density, const __global float2* in, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = test_surface(p, count, tab, wo4.xyz);
    const __global Light* l = &lights[0];
    int type = light_type(l);
    if (density) {
        LightEval e;
        float d = 0.0f;
        if (light_eval(l, in[i].x, in[i].y, s.x, s.n, &e))
            d = bsdf_pdf_light_measure(&s, &e) / light_point_pdf(l, type, s.x, &e);
        out[i] = (float4)(d, 0.0f, 0.0f, 0.0f);
        return;
    }
    float3 wi;
    float pdf;
    bsdf_sample(&s, s.wo, in[i].x, in[i].y, &wi, &pdf);
    float2 uv = (float2)(0.0f);
    bool hit = pdf > 0.0f && light_hit(l, type, s.x, wi, &uv);
    out[i] = (float4)(uv, hit ? 1.0f : 0.0f, 0.0f);
}
"""

# lights whose light_sample takes (u, v) uniform (light_point_pdf is then the density of the map), around the mirror
# direction of the test view (40 degrees from the normal along +x, so reflected towards -x)
PICK_LIGHTS = {
    "quad": Light("q", "area", power=10.0, transforms=translation(-0.7, 0.1, 0.9), shape="RECTANGLE", size=0.9,
                  size_y=0.6),
    "disk": Light("d", "area", power=10.0, transforms=translation(-0.6, -0.2, 0.8), shape="ELLIPSE", size=0.8,
                  size_y=0.5),
    "sun": Light("sun", "sun", power=2.0, transforms=look_at((-0.64, 0.0, 0.77), (0, 0, 0)), angle=0.35),
}
PICK_SURFACES = {
    "glossy": [Closure(base=(0.5, 0.5, 0.5), roughness=0.3)],
    "metal": [Closure(base=(0.9, 0.7, 0.5), metallic=1.0, roughness=0.2)],
    "diffuse": [Closure(kind="diffuse", base=(0.7, 0.7, 0.7))],
}
PICK_N, PICK_CELLS, PICK_SUB = 1 << 20, 12, 6


@pytest.mark.parametrize("surface", list(PICK_SURFACES))
@pytest.mark.parametrize("name", list(PICK_LIGHTS))
def test_bsdf_light_pick_has_the_density_the_mis_weights_assume(device, name, surface):
    """Chi-square of the (u, v) that BSDF directions meet on a light, in 12 x 12 cells plus 'missed', against the
    cells' probabilities integrated (6 x 6 midpoints each) from the density the MIS weights use: a wrong inverse
    map (light_hit), a wrong measure conversion (cos_l / d^2) or a pdf that is not bsdf_sample's would fail it."""
    recs = scene_lights(Scene(lights=[PICK_LIGHTS[name]]), 0).records
    k = BsdfKernels(device, PICK_SRC)
    mf = cl.mem_flags
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=recs)
    params, count, wo = k._params(PICK_SURFACES[surface]), np.int32(len(PICK_SURFACES[surface])), view(40.0)

    def run(density: int, points: np.ndarray) -> np.ndarray:
        ib = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=points.astype(np.float32))
        out = np.empty((len(points), 4), np.float32)
        ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
        cl.Kernel(k.prog, "bsdf_light")(device.queue, (len(points),), None, params, count, k.tab,
                                        clt.make_float4(*wo, 0.0), lb, np.int32(density), ib, ob)
        cl.enqueue_copy(device.queue, out, ob)
        return out

    out = run(0, np.minimum(np.random.default_rng(41).random((PICK_N, 2)), 0.99999994))
    hit = out[:, 2] > 0
    cells = np.clip((out[hit, :2] * PICK_CELLS).astype(int), 0, PICK_CELLS - 1)
    observed = np.bincount(cells[:, 0] * PICK_CELLS + cells[:, 1], minlength=PICK_CELLS**2)
    c = (np.arange(PICK_CELLS * PICK_SUB) + 0.5) / (PICK_CELLS * PICK_SUB)
    dens = run(1, np.stack(np.meshgrid(c, c, indexing="ij"), -1).reshape(-1, 2))[:, 0]
    prob = dens.astype(np.float64).reshape(PICK_CELLS, PICK_SUB, PICK_CELLS, PICK_SUB).mean(axis=(1, 3))
    prob = prob.ravel() / PICK_CELLS**2
    assert 0.02 < prob.sum() < 0.98 and hit.mean() > 0.02, (name, surface, prob.sum(), hit.mean())
    stat, p, dof = pooled_chi2(np.append(observed, (~hit).sum()), np.append(prob, 1.0 - prob.sum()))
    print(f"{name} {surface}: hit {hit.mean():.4f} expected {prob.sum():.4f} chi2 {stat:.1f} dof {dof} p {p:.3g}")
    assert p > 1e-3, (name, surface, stat, dof)
