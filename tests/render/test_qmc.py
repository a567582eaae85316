"""The scrambled Sobol sampler of still RIS renders (opencl/sampling/qmc.h, setting sampler, render/qmc.py): every
dimension pair stratifies (one point per elementary interval), the scrambles differ by pixel, key and pair and make
each point uniform, the one-uniform resampling choice (res_update_remap) picks with the weights' probabilities, the
estimator stays unbiased against the exhaustive reference, its variance falls faster than random numbers', and the
setting switches it where it says."""

from __future__ import annotations

import math

import numpy as np
import pyopencl as cl
import pytest
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, scenes, translation
from restircl.core.program import build_program
from restircl.eval.nets import net_holds
from restircl.render.qmc import still_key, still_uses_sobol
from scipy import stats

from ..bias_controls import wrong_pdf
from ..helpers import batch_stats, collect, constant, luminance, mixed_lights_scene, print_power
from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "sampling/qmc.h"
#include "sampling/reservoir.h"
/* points index0 .. index0 + n - 1 of pair `dim` of pixel `pixel` under `key`, as 32-bit fractions */
__kernel void points(uint pixel, uint key, uint dim, uint index0, __global uint2* out)
{
    uint k = get_global_id(0);
    Qmc q = qmc_stream(1, index0 + k, key, pixel);
    out[k] = qmc_pair_bits(&q, dim);
}
/* point `index` of pair `dim` for pixels 0 .. n - 1, as floats */
__kernel void across_pixels(uint key, uint dim, uint index, __global float2* out)
{
    uint i = get_global_id(0);
    Qmc q = qmc_stream(1, index, key, i);
    out[i] = qmc_pair(&q, dim);
}
/* points index0 .. index0 + n - 1 of the 4D group `dim` of pixel `pixel` under `key` */
__kernel void quads(uint pixel, uint key, uint dim, uint index0, __global uint4* out)
{
    uint k = get_global_id(0);
    Qmc q = qmc_stream(1, index0 + k, key, pixel);
    out[k] = qmc_quad_bits(&q, dim);
}
/* point `index` of the 4D group `dim` for pixels 0 .. n - 1 */
__kernel void quads_across_pixels(uint key, uint dim, uint index, __global uint4* out)
{
    uint i = get_global_id(0);
    Qmc q = qmc_stream(1, index, key, i);
    out[i] = qmc_quad_bits(&q, dim);
}
/* streaming choice over n weights driven by one uniform: random (stratified = 0) or the item's stratum */
__kernel void remap_choice(const __global float* w, int n, int stratified, volatile __global int* counts)
{
    uint i = get_global_id(0);
    uint rng = rng_seed(i, 0u, 77u, 0u);
    float sel = stratified ? ((float)i + 0.5f) / (float)get_global_size(0) : rng_next(&rng);
    Reservoir r;
    res_init(&r);
    for (int k = 0; k < n; ++k) res_update_remap(&r, k, 0.0f, 0.0f, w[k], w[k], &sel, 1.0f);
    if (r.light >= 0) atomic_inc(&counts[r.light]);
}
"""


@pytest.fixture(scope="module")
def prog(device):
    return build_program(device, {}, source=SRC)


def _sequence(device, prog, kernel: str, width: int, pixel: int, key: int, dim: int, n: int,
              index0: int) -> np.ndarray:
    out = np.empty((n, width), np.uint32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, kernel)(device.queue, (n,), None, np.uint32(pixel), np.uint32(key), np.uint32(dim),
                            np.uint32(index0), buf)
    cl.enqueue_copy(device.queue, out, buf)
    return out


def points(device, prog, pixel: int, key: int, dim: int, n: int, index0: int = 0) -> np.ndarray:
    """Points of pair `dim` (n, 2)."""
    return _sequence(device, prog, "points", 2, pixel, key, dim, n, index0)


def quads(device, prog, pixel: int, key: int, dim: int, n: int, index0: int = 0) -> np.ndarray:
    """Points of the 4D group `dim` (n, 4)."""
    return _sequence(device, prog, "quads", 4, pixel, key, dim, n, index0)


@pytest.mark.parametrize("k", [4, 8, 10])
def test_first_points_stratify_every_elementary_interval(device, prog, k):
    for pixel, key, dim in [(0, 0, 0), (17, 5, 1), (4095, 123456, 7), (77, 1, 65536)]:
        p = points(device, prog, pixel, key, dim, 1 << k)
        assert net_holds(p, k, 0), (pixel, key, dim)


def test_aligned_blocks_after_the_first_stratify_too(device, prog):
    # a still render's half buffer continues the sequence: samples 2^k .. 2^(k+1) - 1 are a net of their own
    for index0 in (64, 192, 1 << 20):
        p = points(device, prog, 9, 3, 2, 64, index0)
        assert net_holds(p, 6, 0), index0
    p = points(device, prog, 9, 3, 2, 96)  # and any 2^k-aligned prefix of a longer run
    assert net_holds(p[:32], 5, 0) and net_holds(p[:64], 6, 0)


@pytest.mark.parametrize("k", [4, 8, 10])
def test_light_group_stratifies_the_pick_and_the_point_together(device, prog, k):
    # a light candidate's (pick, point) is one Sobol point: 2 of the first 2^k in every 3D box of volume 2^(1-k),
    # the point alone one in every elementary interval; a later aligned block too
    for pixel, key, dim, index0 in [(0, 0, 0, 0), (17, 5, 2, 0), (4095, 123456, 14, 0), (9, 3, 0, 1 << k)]:
        p = quads(device, prog, pixel, key, dim, 1 << k, index0)
        assert net_holds(p[:, :3], k, 1), (pixel, key, dim, index0)
        assert net_holds(p[:, 1:3], k, 0), (pixel, key, dim, index0)
    # the pick's and the point's pairs of the old layout were shuffled apart: two points per box fails for them
    pair = points(device, prog, 0, 0, 0, 1 << k)
    other = points(device, prog, 0, 0, 1, 1 << k)
    assert not net_holds(np.column_stack([pair[:, 0], other]), k, 1)


@pytest.mark.parametrize("index", [0, 37])
def test_light_group_coordinates_are_uniform_over_pixels(device, prog, index):
    n = 1 << 14
    out = np.empty((n, 4), np.uint32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "quads_across_pixels")(device.queue, (n,), None, np.uint32(1), np.uint32(2), np.uint32(index),
                                           buf)
    cl.enqueue_copy(device.queue, out, buf)
    assert_uniform_and_uncorrelated(out.astype(np.float64) / 2.0**32)


def assert_uniform_and_uncorrelated(u: np.ndarray) -> None:
    """Every column of the (n, s) points in [0, 1) uniform (chi-square over 32 bins) and no two correlated."""
    for c in range(u.shape[1]):
        counts = np.bincount(np.floor(u[:, c] * 32).astype(int), minlength=32)
        chi2, p, _ = pooled_chi2(counts, np.full(32, 1 / 32))
        assert p > 1e-4, (c, chi2, p)
    corr = np.corrcoef(u.T)[np.triu_indices(u.shape[1], 1)]
    assert np.all(np.abs(corr) < 4 / math.sqrt(len(u))), corr


def test_scrambles_differ_by_pixel_key_and_pair(device, prog):
    base = points(device, prog, 5, 11, 0, 64)
    for other in ((6, 11, 0), (5, 12, 0), (5, 11, 1)):
        p = points(device, prog, *other, 64)
        # the same point set (order aside) would mean the scramble ignores that argument
        assert set(map(tuple, p.tolist())) != set(map(tuple, base.tolist())), other
        # and no systematic relation: the first points are not equal in most places
        assert np.mean(p[:, 0] == base[:, 0]) < 0.1, other
    # the two half buffers' keys differ
    assert still_key(7, 0) != still_key(7, 1) and still_key(7, 0) != still_key(8, 0)


@pytest.mark.parametrize("index", [0, 1, 37])
def test_each_point_is_uniform_over_pixels(device, prog, index):
    # Owen scrambling randomises every point: across pixels point `index` is uniform on the unit square
    n = 1 << 14
    out = np.empty((n, 2), np.float32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "across_pixels")(device.queue, (n,), None, np.uint32(3), np.uint32(1), np.uint32(index), buf)
    cl.enqueue_copy(device.queue, out, buf)
    assert np.all((out >= 0) & (out < 1))
    cells = (np.floor(out[:, 0] * 8) * 8 + np.floor(out[:, 1] * 8)).astype(int)
    counts = np.bincount(cells, minlength=64)
    chi2, p, _ = pooled_chi2(counts, np.full(64, 1 / 64))
    assert p > 1e-4, (chi2, p)
    # and the two coordinates are uncorrelated
    assert abs(np.corrcoef(out[:, 0], out[:, 1])[0, 1]) < 4 / math.sqrt(n)


@pytest.mark.parametrize("stratified", [0, 1])
def test_remapped_choice_picks_with_the_weights_probabilities(device, prog, stratified):
    w = np.array([0.5, 3.0, 0.0, 1.0, 7.5, 0.25, 2.0, 1e-3], np.float32)
    items = 1 << 18
    counts = np.zeros(len(w), np.int32)
    cb = cl.Buffer(device.context, cl.mem_flags.READ_WRITE | cl.mem_flags.COPY_HOST_PTR, hostbuf=counts)
    wb = cl.Buffer(device.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=w)
    cl.Kernel(prog, "remap_choice")(device.queue, (items,), None, wb, np.int32(len(w)), np.int32(stratified), cb)
    cl.enqueue_copy(device.queue, counts, cb)
    expected = w / w.sum()
    assert counts[2] == 0 and counts.sum() == items
    if stratified:
        # one uniform per stratum: each item gets its share of the strata, to within one stratum per boundary
        assert np.all(np.abs(counts - expected * items) <= len(w) + 1), (counts, expected * items)
    else:
        chi2, p, _ = pooled_chi2(counts, expected)
        assert p > 1e-4, (chi2, p, counts)


W, H = 16, 12
# Independent runs of 32 frames against a reference of 2048 frames. The negative control (a light pdf 2 % too small)
# is rejected far beyond the bound at this size: image mean +2.03 to +2.10 % against bounds of 0.10-0.19 % and 92
# pixels beyond 4 standard errors, over two sets of 32 runs (64 runs and 4096 reference frames: +2.07 % against
# 0.08-0.12 %, 94 pixels; docs/measurements/benchmarks.md, "Test suite time")
RUNS = 32


def run_means(scene, settings: Settings, runs: int, samples: int, device) -> np.ndarray:
    """(runs, H, W, 3) still renders of `samples` frames, each with its own seed (its own scramble keys)."""
    out = []
    for k in range(runs):
        s = Settings(**{**settings.__dict__, "seed": 1000 + k})
        out.append(Renderer(scene, s, device).render_still(0, samples).color[..., :3].astype(np.float64))
    return np.stack(out)


@pytest.fixture(scope="module")
def reference(device):
    return collect(mixed_lights_scene(W, H), Settings(method="reference", seed=101, jitter=False), 2048, device)


def sobol_problems(runs: np.ndarray, reference: np.ndarray) -> list[str]:
    """Why RUNS independent run means (runs, H, W, 3) are not the exhaustive reference's mean: per pixel within 4
    standard errors (t-statistics with runs - 1 dof: the expected count beyond 4 plus four of its standard
    deviations, plus one, may exceed it), exact where neither varies, and over the image per channel."""
    lum = luminance(runs)
    m, se = lum.mean(axis=0), lum.std(axis=0, ddof=1) / math.sqrt(len(lum))
    mr, ser = batch_stats(luminance(reference), 64)
    sigma = np.sqrt(se**2 + ser**2)
    exact = constant(sigma, mr)
    problems = []
    if not np.all(np.abs(m - mr)[exact] <= 1e-5 * np.abs(mr[exact]) + 1e-12):
        problems.append("exact pixels differ")
    z = np.abs(m - mr)[~exact] / sigma[~exact]
    p = 2 * stats.t.sf(4.0, len(runs) - 1)
    if int((z > 4).sum()) > math.ceil(z.size * p + 4 * math.sqrt(z.size * p) + 1):
        problems.append(f"outliers: {int((z > 4).sum())}, largest z {np.sort(z)[-5:]}")
    img, img_r = runs.mean(axis=(1, 2)), reference.mean(axis=(1, 2))
    se_i = img.std(axis=0, ddof=1) / math.sqrt(len(img))
    _, se_r = batch_stats(img_r, 64)
    bound = 4 * np.sqrt(se_i**2 + se_r**2)
    print_power("sobol ris", img.mean(axis=0) / img_r.mean(axis=0) - 1.0, bound / 4 / img_r.mean(axis=0))
    if np.any(np.abs(img.mean(axis=0) - img_r.mean(axis=0)) > bound):
        problems.append(f"image means {img.mean(axis=0)} against {img_r.mean(axis=0)}")
    return problems


# light_proposal tree: the tree's stratified descent of a Sobol word (lights/tree.h light_tree_descend), its
# pdf the one light_pick_pdf gives the MIS weights of the BSDF candidates
@pytest.mark.parametrize("extra", [{}, {"bsdf_sampling": "on"}, {"candidates": 9}, {"bsdf_mis_sample": True},
                                   {"light_proposal": "tree"}, {"light_proposal": "tree", "bsdf_sampling": "on"}])
def test_sobol_ris_mean_equals_reference(device, reference, extra):
    # RUNS runs of 32 frames are independent (own keys); their means are compared with the exhaustive reference
    s = Settings(**{"method": "ris", "sampler": "sobol", "candidates": 4, "jitter": False, **extra})
    runs = run_means(mixed_lights_scene(W, H), s, RUNS, 32, device)
    assert np.isfinite(runs).all()
    problems = sobol_problems(runs, reference)
    assert not problems, problems


def test_the_harness_rejects_a_wrong_pdf(device, reference, monkeypatch):
    """Negative control: Sobol RIS with a light pdf 2 % too small (tests/bias_controls.py) must be rejected."""
    wrong_pdf(monkeypatch)
    s = Settings(method="ris", sampler="sobol", candidates=4, jitter=False)
    problems = sobol_problems(run_means(mixed_lights_scene(W, H), s, RUNS, 32, device), reference)
    assert any(p.startswith(("outliers", "image means")) for p in problems), problems


def total_variance(runs: np.ndarray) -> tuple[float, float]:
    """Sum over pixels of the luminance variance of the run means, and its relative standard error (pixels are
    independent estimates: no reuse; each pixel's sample variance has relative variance 2 / (runs - 1))."""
    lum = luminance(runs)
    var = lum.var(axis=0, ddof=1)
    live = var > 0
    v = var[live]
    # the relative standard error of a sum of independent sample variances with unequal sizes
    rel = math.sqrt(2 / (len(lum) - 1) * float((v**2).sum())) / float(v.sum())
    return float(v.sum()), rel


def two_area_lights_scene(width: int = 16, height: int = 12) -> Scene:
    """A floor under a square and a disk area light: soft shadows of nothing, only the light sampling's noise."""
    fv, ft = scenes.quad(4, 4)
    lights = [Light("square", "area", (1, 0.9, 0.8), 40.0, translation(-0.6, 0.0, 1.0), shape="SQUARE", size=0.8),
              Light("disk", "area", (0.7, 0.8, 1.0), 25.0, translation(0.7, 0.4, 0.7), shape="DISK", size=0.5)]
    cam = Camera(look_at((0.0, -3.0, 2.2), (0.0, 0.2, 0.0)), width, height, lens=30.0)
    return Scene([Mesh("floor", fv, ft, 0)], [Material("floor", (0.7, 0.7, 0.7))], lights, cam, name="two_lights")


def test_sobol_converges_faster_than_random(device):
    # the same still renders with random and with Sobol numbers: at 16 and at 64 frames the variance of the mean
    # must be lower with Sobol by more than four combined standard errors. (Measured 2026-12-06, 16 runs: 0.18 of
    # random's at 16 frames against the bound 0.58, 0.08 at 64 against 0.51; 24 runs: 0.19, 0.08 and 0.035 at 16, 64
    # and 128 frames.)
    scene = two_area_lights_scene()
    kw = dict(method="ris", candidates=2, jitter=False, bsdf_sampling="off")
    runs = 16
    for frames in (16, 64):
        v_rand, e_rand = total_variance(run_means(scene, Settings(sampler="random", **kw), runs, frames, device))
        v_qmc, e_qmc = total_variance(run_means(scene, Settings(sampler="sobol", **kw), runs, frames, device))
        ratio = v_qmc / v_rand
        print(f"variance of the mean of {frames} frames, sobol / random: {ratio:.3f}")
        assert ratio < 1 - 4 * math.hypot(e_rand, e_qmc), (frames, ratio, e_rand, e_qmc)


def test_no_nan_with_sobol_at_any_index(device):
    scene = mixed_lights_scene(W, H)
    r = Renderer(scene, Settings(method="ris", sampler="sobol", candidates=3, bsdf_sampling="on", jitter=False),
                 device)
    for index in (0, 1, (1 << 31) - 1, (1 << 32) - 1):
        r.qmc = (1, index, 12345)
        img = r.render_frame(0, still=True).noisy
        assert np.isfinite(img).all(), index
    r.qmc = None


def test_sampler_setting_decides_where_sobol_is_used(device):
    scene = mixed_lights_scene(8, 6)
    assert still_uses_sobol(Settings(method="ris")) and still_uses_sobol(Settings(method="ris", sampler="sobol"))
    assert not still_uses_sobol(Settings(method="ris", sampler="random"))
    assert not still_uses_sobol(Settings(method="restir"))  # ReSTIR keeps its random streams
    # animation frames: random numbers unless sampler is sobol
    for sampler, on in (("auto", 0), ("random", 0), ("sobol", 1)):
        r = Renderer(scene, Settings(method="ris", sampler=sampler), device)
        assert int(r.frame_params()["qmc"]) == on, sampler
    assert int(Renderer(scene, Settings(method="restir", sampler="sobol"), device).frame_params()["qmc"]) == 0
    # a still render switches it on for its frames and off after
    seen = []
    r = Renderer(scene, Settings(method="ris", jitter=False), device)
    r.render_still(0, 20, progress=lambda done, n: seen.append(r.qmc))
    assert r.qmc is None and len(seen) == 20
    keys = {s[2] for s in seen}
    assert all(s[0] == 1 for s in seen) and keys == {still_key(r.settings.seed, 0), still_key(r.settings.seed, 1)}
    for key in keys:  # each half buffer counts its own samples from 0
        idx = [s[1] for s in seen if s[2] == key]
        assert idx == list(range(len(idx)))
    with pytest.raises(ValueError, match="sampler"):
        Settings(sampler="halton").validate()


def test_one_light_still_draws_its_points_from_sobol(device):
    # a still of one light object: with Sobol the frames (still or animation) run RIS (their points on the light
    # from the sequence), with random numbers the plain light-array sampler; the Sobol mean's variance must be lower
    # by more than four combined standard errors, as in the test above
    full = two_area_lights_scene()
    scene = Scene(full.meshes, full.materials, full.lights[:1], full.camera, name="one_light")
    kw = dict(method="ris", candidates=1, jitter=False, bsdf_sampling="off")
    r = Renderer(scene, Settings(sampler="sobol", **kw), device)
    r.qmc = (1, 0, 1)
    r.render_frame(0, still=True, aovs=False)
    assert r.last_plan is not None and r.last_plan.method == "ris"
    r.qmc = None  # animation frames with the Sobol sampler draw from the sequence too
    r.render_frame(1 % scene.frames, aovs=False)
    assert r.last_plan.method == "ris"
    plain = Renderer(scene, Settings(sampler="random", **kw), device)
    plain.render_frame(0, aovs=False)
    assert plain.last_plan is not None and plain.last_plan.method == "light_array"
    runs = 24
    v_rand, e_rand = total_variance(run_means(scene, Settings(sampler="random", **kw), runs, 32, device))
    v_qmc, e_qmc = total_variance(run_means(scene, Settings(sampler="sobol", **kw), runs, 32, device))
    print(f"one light, variance of the mean of 32 frames, sobol / random: {v_qmc / v_rand:.3f}")
    assert v_qmc / v_rand < 1 - 4 * math.hypot(e_rand, e_qmc), (v_qmc / v_rand, e_rand, e_qmc)
