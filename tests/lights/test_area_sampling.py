"""Solid-angle sampling of area lights (setting area_sampling; opencl/lights/spherical_rect.h, spherical_tri.h,
solid_angle.h): the sampled points follow the density cos_l / (d^2 S) that the device reports (chi-square against
bin probabilities integrated in numpy, overhead, close-up and grazing), the density integrates to one over the
light's visible part, light_point_pdf (MIS with BSDF candidates) gives the same density, no NaN where the shading
point lies on the light's plane, behind it, 1e-4 or 1e4 away; RIS and the unbiased ReSTIR modes agree with the
exhaustive reference with it; the weight of a sample stays bounded however close the shading point is, in every
mode, since `area` too samples by solid angle next to a light; and it cuts the per-frame variance of RIS where lights
are large and close."""

import dataclasses
import math

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
import pytest
from restircl import Light, Material, Mesh, Scene, Settings, translation
from restircl.core.program import build_program
from restircl.lights.device_lights import scene_lights
from restircl.render.features import general_flags

from ..bias_controls import wrong_pdf
from ..helpers import batch_stats, collect, luminance, mean_and_se, run_means
from ..render.test_bsdf_candidates import BATCHES, SIZES, H, W, assert_unbiased, large_lights_scene
from ..stats import pooled_chi2

# the quick sizes of test_bsdf_candidates (its full ones are slow-marked there); bounds from the measured errors
FRAMES, RUNS, RUN_FRAMES, REFERENCE_FRAMES = (SIZES["quick"][k] for k in ("frames", "runs", "run_frames", "reference"))

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
__kernel void sample_light(const __global Light* lights, float4 x4, float4 n4, uint seed, __global float4* out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, seed, 0u);
    float r0 = rng_next(&rng), r1 = rng_next(&rng);
    const __global Light* l = &lights[0];
    float pdf;
    float2 uv = light_sample(l, x4.xyz, r0, r1, &pdf);
    LightEval e;
    bool ok = pdf > 0.0f && light_eval(l, uv.x, uv.y, x4.xyz, n4.xyz, &e);
    out[3 * i + 0] = (float4)(ok ? e.pos : (float3)(0.0f), pdf);
    out[3 * i + 1] = (float4)(uv, ok ? light_point_pdf(l, light_type(l), x4.xyz, &e) : -1.0f, ok ? 1.0f : 0.0f);
    out[3 * i + 2] = (float4)(ok ? e.contrib : (float3)(0.0f), 0.0f);
}
"""

N = 200_000
UP = np.array([0.0, 0.0, 1.0])
SA = "solid_angle"


def sample(device, recs, x, n=UP, count=N, seed=1) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=recs)
    out = np.empty((count, 3, 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "sample_light")(device.queue, (count,), None, lb, clt.make_float4(*x, 0.0),
                                    clt.make_float4(*n, 0.0), np.uint32(seed), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def area_light(shape: str, z: float = 1.0, size: float = 1.0, size_y: float = 1.0) -> Light:
    """An area light at height z over the origin, facing down (-Z)."""
    return Light("a", "area", (1, 1, 1), 50.0, translation(0.2, -0.1, z), shape=shape, size=size, size_y=size_y)


TRI = np.array([[-0.4, -0.5, 0.0], [0.7, -0.3, 0.0], [0.1, 0.6, 0.0]])


def triangle_scene(z: float) -> Scene:
    return Scene([Mesh("tri", TRI + (0, 0, z), [[0, 1, 2]], 0)], [Material("lamp", (0, 0, 0), (1, 1, 1), 3.0)])


def records(kind: str, z: float, mode: str = SA) -> np.ndarray:
    if kind == "triangle":
        return scene_lights(triangle_scene(z), 0, area_sampling=mode).records
    shape = {"quad": "RECTANGLE", "disk": "ELLIPSE"}[kind]
    return scene_lights(Scene(lights=[area_light(shape, z, 1.2, 0.7)]), 0, area_sampling=mode).records


def shape_grid(kind: str, res: int):
    """Midpoints of a res x res grid over the shape's parameter square, in the record's (s, t): quad and triangle
    [0, 1]^2 along (a, b), disk [-1, 1]^2 in semi-axes; the mask of those inside the shape."""
    lo, hi = (-1.0, 1.0) if kind == "disk" else (0.0, 1.0)
    c = lo + (np.arange(res) + 0.5) / res * (hi - lo)
    s, t = np.meshgrid(c, c, indexing="ij")
    inside = {"quad": np.ones_like(s, bool), "disk": s * s + t * t <= 1.0, "triangle": s + t <= 1.0}[kind]
    return s, t, inside, (lo, hi)


def solid_angle_density(rec, kind: str, x: np.ndarray, res: int = 1200):
    """cos_l / d^2 on the grid (area measure of uniform solid angle, up to 1/S) and the solid angle S that the
    device samples: the shape's, or for the disk its bounding rectangle's (the points outside it are no sample)."""
    s, t, inside, (lo, hi) = shape_grid(kind, res)
    p, a, b = (rec[k][:3].astype(np.float64) for k in ("p", "a", "b"))
    pts = p + s[..., None] * a + t[..., None] * b
    nl = np.cross(a, b)
    nl /= np.linalg.norm(nl)
    d = pts - x
    d2 = (d**2).sum(-1)
    f = np.abs(d @ nl) / d2**1.5
    cell = np.linalg.norm(np.cross(a, b)) * ((hi - lo) / res) ** 2
    S = float((f if kind == "disk" else f * inside).sum() * cell)
    return f * inside, S


def plane_st(pos, rec):
    p, a, b = (rec[k][:3].astype(np.float64) for k in ("p", "a", "b"))
    coef, *_ = np.linalg.lstsq(np.stack([a, b], 1), (pos - p).T, rcond=None)
    return coef.T


# shading points: under the light's middle, close under it, grazing (just below its plane, 3 m away)
CONFIGS = {"overhead": (np.zeros(3), 1.0), "close": (np.array([0.25, -0.05, 0.0]), 0.06),
           "grazing": (np.array([3.0, 0.2, 0.0]), 0.05)}


@pytest.mark.parametrize("kind", ["quad", "disk", "triangle"])
@pytest.mark.parametrize("config", list(CONFIGS))
def test_solid_angle_points_follow_their_pdf(device, kind, config):
    x, z = CONFIGS[config]
    rec = records(kind, z)
    out = sample(device, rec, x)
    ok = out[:, 2, :3].any(axis=1) | (out[:, 0, 3] > 0)
    pdf, pos = out[:, 0, 3].astype(np.float64), out[:, 0, :3].astype(np.float64)
    f, S = solid_angle_density(rec[0], kind, x)
    bins = 10
    res = f.shape[0]
    prob = f.reshape(bins, res // bins, bins, res // bins).sum(axis=(1, 3))
    st = plane_st(pos[pdf > 0], rec[0])
    lo, hi = (-1.0, 1.0) if kind == "disk" else (0.0, 1.0)
    h, _, _ = np.histogram2d(st[:, 0], st[:, 1], bins=bins, range=[[lo, hi], [lo, hi]])
    stat, p, dof = pooled_chi2(h, prob / prob.sum(), min_expected=20)
    assert dof > 25 and p > 1e-4, (kind, config, stat, p, dof)
    # the reported density is cos_l / (d^2 S) with the solid angle integrated here
    d = pos[pdf > 0] - x
    nl = np.cross(rec[0]["a"][:3].astype(np.float64), rec[0]["b"][:3].astype(np.float64))
    nl /= np.linalg.norm(nl)
    expect = np.abs(d @ nl) / (d**2).sum(1) ** 1.5 / S
    rel = np.abs(pdf[pdf > 0] / expect - 1)
    assert np.quantile(rel, 0.99) < 2e-3, (kind, config, np.quantile(rel, 0.99))
    # light_point_pdf (MIS) gives the sampling density of the evaluated point
    mis = out[pdf > 0, 1, 2].astype(np.float64)
    assert np.quantile(np.abs(mis / pdf[pdf > 0] - 1), 0.999) < 1e-3, (kind, config)
    # it integrates to one over the light: E[1 / pdf] is the light's area (disk: the misses of its bounding
    # rectangle count as zero)
    area = float(rec[0]["b"][3])
    inv = np.where(pdf > 0, 1.0 / np.where(pdf > 0, pdf, 1.0), 0.0)
    assert abs(inv.mean() - area) <= 4 * inv.std() / math.sqrt(len(inv)) + 1e-4 * area, (inv.mean(), area)
    assert ok.sum() > 0.7 * N


@pytest.mark.parametrize("dist", [0.45, 3.0])
def test_soft_point_light_disk_is_sampled_uniformly_in_its_cone(device, dist):
    """The soft-falloff disk (radius r facing the shading point) subtends a cone of tan = r / dist: its points'
    directions are uniform in that cone, with the area density cos^3 / (dist^2 2 pi (1 - cos_max))."""
    r = 0.4
    light = Light("s", "point", (1, 1, 1), 50.0, translation(0.1, 0.0, dist), radius=r)
    rec = scene_lights(Scene(lights=[light]), 0, area_sampling=SA).records
    x = np.zeros(3)
    out = sample(device, rec, x)
    pdf, pos = out[:, 0, 3].astype(np.float64), out[:, 0, :3].astype(np.float64)
    assert np.all(pdf > 0)
    c = np.array([0.1, 0.0, dist])
    dc = np.linalg.norm(c)
    w = c / dc
    d = pos - x
    dn = np.linalg.norm(d, axis=1)
    wi = d / dn[:, None]
    omc = 1 - dc / math.hypot(dc, r)
    cos_t = wi @ w
    s = np.cross(w, [0.0, 1.0, 0.0])
    s /= np.linalg.norm(s)
    t = np.cross(w, s)
    h, _, _ = np.histogram2d((1 - cos_t) / omc, np.arctan2(wi @ t, wi @ s), bins=(10, 8),
                             range=[[0, 1], [-math.pi, math.pi]])
    stat, p, dof = pooled_chi2(h, np.ones_like(h) / h.size)
    assert p > 1e-4, (stat, p)
    expect = cos_t**3 / (dc * dc * 2 * math.pi * omc)
    assert np.quantile(np.abs(pdf / expect - 1), 0.99) < 2e-3
    assert np.quantile(np.abs(out[:, 1, 2] / pdf - 1), 0.999) < 1e-3  # light_point_pdf


ODD_POINTS = {"on_plane": np.array([0.5, 0.1, 1.0]), "behind": np.array([0.2, -0.1, 1.5]),
              "touching": np.array([0.2, -0.1, 1.0 - 1e-4]), "on_edge": np.array([0.8, -0.1, 1.0]),
              "far": np.array([1e4, 3e3, -2e3]), "far_above": np.array([0.0, 0.0, -1e4])}


@pytest.mark.parametrize("kind", ["quad", "disk", "triangle", "soft"])
@pytest.mark.parametrize("mode", [SA, "auto"])
def test_no_nan_at_odd_shading_points(device, kind, mode):
    if kind == "soft":
        recs = scene_lights(Scene(lights=[Light("s", "point", (1, 1, 1), 50.0, translation(0.2, -0.1, 1.0),
                                                radius=0.3)]), 0, area_sampling=mode).records
    else:
        recs = records(kind, 1.0, mode)
    for name, x in ODD_POINTS.items():
        out = sample(device, recs, x, n=-UP if name == "far_above" else UP, count=4096)
        assert np.all(np.isfinite(out)), (kind, name)
        pdf, uv = out[:, 0, 3], out[:, 1, :2]
        assert np.all(pdf >= 0) and np.all((uv >= 0) & (uv < 1)), (kind, name)
        lit = out[:, 2, :3].any(axis=1)
        assert np.all(pdf[lit] > 0), (kind, name)


# shading points closing in on a light at (0.2, -0.1, 1) (the quad, disk and soft point light; the triangle's plane is
# z = 1 too): face to face under it, beside its edge (a receiver it stands on), and, for the spheres, at its surface
def _closing_in(kind: str, d: float) -> list[tuple[np.ndarray, np.ndarray]]:
    centre = np.array([0.2, -0.1, 1.0])
    up = np.array([0.0, 0.0, 1.0])
    if kind in ("soft", "sphere"):
        out = np.array([0.6, 0.0, -0.8])  # from the centre, radius 0.3 (+ d) out
        side = np.array([0.0, 1.0, 0.0])
        return [(centre + (0.3 + d) * out, -out), (centre + (0.3 + d) * side, -side)]
    edge = {"quad": np.array([0.8, -0.1, 1.0]), "disk": np.array([0.8, -0.1, 1.0]),
            "triangle": np.array([0.7, -0.3, 1.0])}[kind]
    side = np.array([1.0, 0.0, 0.0]) if kind != "triangle" else np.array([0.96, -0.28, 0.0])
    return [(centre - d * up, up), (np.array([0.1, 0.0, 1.0]) - d * up, up), (edge + d * side - d * up, -side)]


@pytest.mark.parametrize("kind", ["quad", "disk", "triangle", "soft", "sphere"])
@pytest.mark.parametrize("mode", ["area", SA, "auto"])
def test_weights_stay_bounded_next_to_the_light(device, kind, mode):
    """The weight of a light sample, contribution / density = Le cos_x G / pdf, stays below 2 pi Le in every mode
    however close the shading point is (1 cm .. 10 um): drawn uniformly in area next to the light it grows as 1 / d^2
    (pi Le A / d^2), and a receiver touching an emitter got fireflies that never averaged out (issue 37). Solid angle
    bounds it by Le S <= 2 pi Le (lights/solid_angle.h); beyond twice the light's radius, area sampling by pi Le."""
    if kind == "soft":
        light = Light("s", "point", (1, 1, 1), 50.0, translation(0.2, -0.1, 1.0), radius=0.3)
        recs = scene_lights(Scene(lights=[light]), 0, area_sampling=mode).records
    elif kind == "sphere":
        light = Light("s", "point", (1, 1, 1), 50.0, translation(0.2, -0.1, 1.0), radius=0.3, soft_falloff=False)
        recs = scene_lights(Scene(lights=[light]), 0, area_sampling=mode).records
    else:
        recs = records(kind, 1.0, mode)
    le = float(recs[0]["L"][:3].max())
    for d in (1e-2, 1e-3, 1e-4, 1e-5):
        for x, n in _closing_in(kind, d):
            out = sample(device, recs, x, n=n, count=20_000, seed=3)
            pdf, contrib = out[:, 0, 3].astype(np.float64), out[:, 2, :3].astype(np.float64)
            lit = contrib.any(axis=1)
            assert lit.mean() > 0.5, (kind, mode, d, x)
            w = contrib[lit].max(axis=1) / pdf[lit]
            assert w.max() <= 2 * math.pi * le * 1.001, (kind, mode, d, x, w.max() / le)


def test_modes_flag_only_the_lights_they_sample_by_solid_angle():
    from restircl.lights.area_sampling import FLAG_SA_AUTO, FLAG_SA_NEAR, FLAG_SOLID_ANGLE, sampling_flags

    lights = [area_light("RECTANGLE"), area_light("ELLIPSE"),
              Light("p", "point", (1, 1, 1), 5.0, translation(0, 0, 1), radius=0.2),
              Light("hard", "point", (1, 1, 1), 5.0, translation(0, 0, 1), radius=0.2, soft_falloff=False),
              Light("sun", "sun", (1, 1, 1), 1.0, translation(0, 0, 1), angle=0.1)]
    scene = Scene([Mesh("tri", TRI, [[0, 1, 2]], 0)], [Material("lamp", (0, 0, 0), (1, 1, 1), 3.0)], lights)
    dl = scene_lights(scene, 0)
    # area: by solid angle only near the light (never uniformly in area right next to it)
    assert sampling_flags(dl.records, dl.types, "area").tolist() == [FLAG_SOLID_ANGLE | FLAG_SA_NEAR] * 3 + [
        0, 0, FLAG_SOLID_ANGLE | FLAG_SA_NEAR]
    assert sampling_flags(dl.records, dl.types, SA).tolist() == [FLAG_SOLID_ANGLE] * 3 + [0, 0, FLAG_SOLID_ANGLE]
    assert sampling_flags(dl.records, dl.types, "auto").tolist() == [FLAG_SOLID_ANGLE | FLAG_SA_AUTO] * 3 + [
        0, 0, FLAG_SOLID_ANGLE | FLAG_SA_AUTO]
    sheared = dl.records.copy()
    sheared[0]["a"][:3] += 0.3 * sheared[0]["b"][:3]  # a parallelogram: area sampling
    assert sampling_flags(sheared, dl.types, SA)[0] == 0
    with pytest.raises(ValueError, match="area_sampling"):
        sampling_flags(dl.records, dl.types, "cosine")


def spread_powers(scene: Scene) -> Scene:
    """The same scene with its lights' powers spread over 1e-6..1e6 (and the emissive panel's strength 1e3)."""
    powers = np.logspace(-6, 6, len(scene.lights))
    lights = [dataclasses.replace(lt, power=float(p) * lt.power) for lt, p in zip(scene.lights, powers, strict=True)]
    mats = [dataclasses.replace(m, emission_strength=m.emission_strength * 1e3) if m.emission_strength else m
            for m in scene.materials]
    return dataclasses.replace(scene, lights=lights, materials=mats)


SCENES = {"large": large_lights_scene, "powers": lambda w, h: spread_powers(large_lights_scene(w, h))}


@pytest.fixture(scope="module")
def references(reference_samples):
    """Rendered once per session: render/test_bsdf_candidates.py's quick reference is the same render of "large"."""
    return {name: batch_stats(luminance(reference_samples(make(W, H), Settings(method="reference", seed=17,
                                                                                jitter=False), REFERENCE_FRAMES)),
                              BATCHES) for name, make in SCENES.items()}


UNBIASED_CASES = {
    "ris": ("large", dict(method="ris", candidates=4)),
    "ris_auto": ("large", dict(method="ris", candidates=4, area_sampling="auto")),
    "ris_bsdf": ("large", dict(method="ris", candidates=4, bsdf_sampling="on")),
    "ris_powers": ("powers", dict(method="ris", candidates=4, bsdf_sampling="on")),
    "restir_pairwise": ("large", dict(method="restir", bsdf_sampling="on", taa=False)),
    "restir_z_count": ("large", dict(method="restir", bias_correction="z_count", m_cap=4.0, taa=False)),
    "restir_powers": ("powers", dict(method="restir", taa=False)),
}


@pytest.mark.parametrize("case", list(UNBIASED_CASES))
def test_estimators_with_solid_angle_sampling_match_reference(device, references, case):
    """Every area light type, an emissive panel partly behind a block, lights below the floor (large_lights_scene),
    and the same with powers over 1e-6..1e6, against the exhaustive reference (area sampling)."""
    scene_name, kw = UNBIASED_CASES[case]
    s = Settings(**{"area_sampling": SA, "seed": 41, "jitter": False, **kw})
    scene = SCENES[scene_name](W, H)
    if s.method == "ris":
        x = collect(scene, s, FRAMES, device)
        assert np.all(np.isfinite(x))
        m, se = batch_stats(luminance(x), BATCHES)
        n_stats = BATCHES
        image_se = None  # batches of independent frames: the pixels' own standard errors add up
    else:
        runs = luminance(run_means(scene, s, RUNS, RUN_FRAMES, device))
        assert np.all(np.isfinite(runs))
        m, se = mean_and_se(runs)
        n_stats = RUNS
        # ReSTIR's spatial reuse correlates neighbouring pixels: the image mean's spread is measured over the runs
        image_se = float(runs.mean(axis=(1, 2)).std(ddof=1)) / math.sqrt(RUNS)
    mr, sr = references[scene_name]
    # pixels that see an emitter directly are exact, up to the float rounding of the accumulation (1e-16 relative)
    exact = np.abs(mr) * 1e-9
    assert_unbiased(m, np.where(se < exact, 0.0, se), (mr, np.where(sr < exact, 0.0, sr)), n_stats, case,
                    image_se=image_se)


def test_the_harness_rejects_a_wrong_pdf(device, references, monkeypatch):
    """Negative control: the "ris" case with a light pdf 5 % too small (tests/bias_controls.py) is rejected. This
    check's image-mean bound is 1.5-2.2 % at the quick size (printed): the large lights' bright, noisy pixels rule
    the plain image mean, and the 2 % pdf error of the other controls measured +1.4 % here (the camera sees the
    emitters), inside it; its per-pixel check did not see it either."""
    mr, sr = references["large"]
    wrong_pdf(monkeypatch, 0.95)
    s = Settings(**{"area_sampling": SA, "seed": 41, "jitter": False, **UNBIASED_CASES["ris"][1]})
    m, se = batch_stats(luminance(collect(SCENES["large"](W, H), s, FRAMES, device)), BATCHES)
    exact = np.abs(mr) * 1e-9
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_unbiased(m, np.where(se < exact, 0.0, se), (mr, np.where(sr < exact, 0.0, sr)), BATCHES, "wrong pdf")


@pytest.mark.parametrize("glossy", [False, True])
def test_area_mode_samples_large_close_lights_by_solid_angle(device, glossy):
    """Not a timing test: per-frame variance of RIS (4 candidates, no BSDF candidates) on large_lights_scene, whose
    shading points are all within twice some light's radius of it: `area` samples those lights by solid angle as
    `solid_angle` does (lights/solid_angle.h SA_NEAR_RATIO), so its variance is solid angle's (measured 0.3 % and
    0.7 % apart), not the 1.25x and more that uniform area sampling had there."""
    scene = large_lights_scene(W, H, glossy)
    var = {}
    for mode in ("area", SA):
        x = collect(scene, Settings(method="ris", candidates=4, bsdf_sampling="off", area_sampling=mode, seed=31,
                                    jitter=False), 512, device)
        var[mode] = luminance(x).var(axis=0).mean()
    assert abs(var["area"] / var[SA] - 1) < 0.05, var


def test_trig_polynomials_match_numpy(device):
    """lights/trig.h: sin, cos and atan2 within a few float32 ulps (absolute near 1, relative near 0)."""
    src = """
#include "lights/trig.h"
__kernel void trig(const __global float2* xy, __global float4* out)
{
    int i = get_global_id(0);
    float2 sc = sincos_f(xy[i].x);
    out[i] = (float4)(sc, atan2_f(xy[i].y, xy[i].x), 0.0f);
}
"""
    prog = build_program(device, {}, source=src)
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.uniform(-7, 7, 4000), rng.uniform(-1, 1, 2000) * 10.0 ** rng.uniform(-7, 0, 2000)])
    y = rng.uniform(-3, 3, len(x)) * 10.0 ** rng.uniform(-6, 0, len(x))
    xy = np.stack([x, y], 1).astype(np.float32)
    mf = cl.mem_flags
    xb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=xy)
    out = np.empty((len(x), 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    prog.trig(device.queue, (len(x),), None, xb, ob)
    cl.enqueue_copy(device.queue, out, ob)
    x64, y64 = xy[:, 0].astype(np.float64), xy[:, 1].astype(np.float64)
    for got, want in ((out[:, 0], np.sin(x64)), (out[:, 1], np.cos(x64)), (out[:, 2], np.arctan2(y64, x64))):
        err = np.abs(got - want) / np.maximum(np.abs(want), 1.0)
        rel = np.abs(got - want) / np.maximum(np.abs(want), 1e-30)
        assert err.max() < 4e-7, err.max()
        assert np.quantile(rel[np.abs(want) < 1e-2], 0.999) < 1e-6
