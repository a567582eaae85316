"""The camera vertex's Sobol group (opencl/sampling/qmc.h QMC_CAMERA, camera/jitter.h): the pixel jitter and the first
light candidate of a Sobol still are one 6D Sobol point. Its tables are Joe and Kuo's Sobol dimensions (scipy's) and
current; the 4D projection (jitter, point on the light) is a (t, 4)-net with t = 3 over aligned blocks, which the
former pairing (a Halton jitter per frame beside the light group, or a pair of its own) is not; every coordinate is
uniform over pixels; a still render stays unbiased against independent renders of the random sampler; and the still
switches the pixel's jitter on only with Settings.jitter."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pytest
from restircl import Renderer, Settings
from restircl.core.program import build_program
from restircl.eval.nets import net_holds
from restircl.render.camera import halton
from restircl.render.qmc import ON, PIXEL_JITTER, still_flags
from restircl.upload import sobol_table

from ..bias_controls import wrong_pdf
from ..helpers import mixed_lights_scene
from .test_qmc import assert_uniform_and_uncorrelated, run_means, sobol_problems

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "sampling/qmc.h"
/* points index0 .. index0 + n - 1 of the camera group of `pixel` under `key`: jitter x, y, light point u, v, pick,
 * resampling choice */
__kernel void camera_points(uint pixel, uint key, uint index0, __global uint* out)
{
    uint k = get_global_id(0);
    Qmc q = qmc_stream(QMC_ON | QMC_PIXEL_JITTER, index0 + k, key, pixel);
    uint2 j = qmc_camera_jitter_bits(&q);
    uint4 a = qmc_camera_light_bits(&q);
    __global uint* o = out + 6u * k;
    o[0] = j.x; o[1] = j.y; o[2] = a.y; o[3] = a.z; o[4] = a.x; o[5] = a.w;
}
/* the former layout's numbers of the same samples: the first candidate's 4D group (u, v) and a pair of its own */
__kernel void former_points(uint pixel, uint key, uint index0, __global uint* out)
{
    uint k = get_global_id(0);
    Qmc q = qmc_stream(QMC_ON, index0 + k, key, pixel);
    uint4 a = qmc_quad_bits(&q, QMC_LIGHT(0));
    uint2 p = qmc_pair_bits(&q, 0x70000u);
    __global uint* o = out + 4u * k;
    o[0] = p.x; o[1] = p.y; o[2] = a.y; o[3] = a.z;
}
/* point `index` of the camera group for pixels 0 .. n - 1 */
__kernel void camera_across_pixels(uint key, uint index, __global uint* out)
{
    uint i = get_global_id(0);
    Qmc q = qmc_stream(QMC_ON | QMC_PIXEL_JITTER, index, key, i);
    uint2 j = qmc_camera_jitter_bits(&q);
    uint4 a = qmc_camera_light_bits(&q);
    __global uint* o = out + 6u * i;
    o[0] = j.x; o[1] = j.y; o[2] = a.y; o[3] = a.z; o[4] = a.x; o[5] = a.w;
}
/* unscrambled Sobol dimensions 2 .. 5 at the given indices (the tables hold them bit-reversed) */
__kernel void sobol2345(const __global uint* index, __global uint4* out)
{
    uint k = get_global_id(0), i = index[k];
    out[k] = (uint4)(qmc_reverse_bits(sobol_reversed(i, SOBOL_DIM2)), qmc_reverse_bits(sobol_reversed(i, SOBOL_DIM3)),
                     qmc_reverse_bits(sobol_reversed(i, SOBOL_DIM4)), qmc_reverse_bits(sobol_reversed(i, SOBOL_DIM5)));
}
"""
JITTER, POINT, PICK, CHOICE = (0, 1), (2, 3), 4, 5


@pytest.fixture(scope="module")
def prog(device):
    return build_program(device, {}, source=SRC)


def _run(device, prog, kernel: str, width: int, n: int, *args: int) -> np.ndarray:
    out = np.empty((n, width), np.uint32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, kernel)(device.queue, (n,), None, *(np.uint32(a) for a in args), buf)
    cl.enqueue_copy(device.queue, out, buf)
    return out


def camera_points(device, prog, pixel: int, key: int, n: int, index0: int = 0) -> np.ndarray:
    return _run(device, prog, "camera_points", 6, n, pixel, key, index0)


def test_tables_are_current_and_scipys_sobol(device, prog):
    # the header is what the generator writes, and its dimensions 2 .. 5 are scipy's (Joe and Kuo's), whose
    # unscrambled point k is the matrix product at gray(k); 4096 points and 8 from 2^31 - 3 on read every nibble table
    from scipy.stats import qmc

    assert sobol_table.main(["--check"]) == 0
    for start, n in ((0, 1 << 12), ((1 << 31) - 3, 8)):
        sob = qmc.Sobol(d=6, scramble=False, bits=32)
        if start:
            sob.fast_forward(start)
        ref = np.floor(sob.random(n)[:, 2:] * 2.0**32).astype(np.uint64)
        k = np.arange(start, start + n, dtype=np.uint64)
        gray = (k ^ (k >> np.uint64(1))).astype(np.uint32)
        idx = cl.Buffer(device.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=gray)
        out = np.empty((n, 4), np.uint32)
        buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
        cl.Kernel(prog, "sobol2345")(device.queue, (n,), None, idx, buf)
        cl.enqueue_copy(device.queue, out, buf)
        assert np.array_equal(out.astype(np.uint64), ref), start


@pytest.mark.parametrize("k", [4, 8, 10])
def test_jitter_and_light_point_are_one_net(device, prog, k):
    # per pixel and key, the first 2^k samples and a later aligned block: (jitter, point) 2^3 points in every 4D
    # elementary box of volume 2^(3-k); the point alone one in every elementary interval; the jitter alone and the
    # (pick, point) at most 2^2 per box
    for pixel, key, index0 in [(0, 0, 0), (17, 5, 0), (4095, 123456, 0), (9, 3, 1 << k), (9, 3, 5 << k)]:
        p = camera_points(device, prog, pixel, key, 1 << k, index0)
        assert net_holds(p[:, [*JITTER, *POINT]], k, 3), (pixel, key, index0)
        assert net_holds(p[:, list(POINT)], k, 0), (pixel, key, index0)
        assert net_holds(p[:, list(JITTER)], k, 2), (pixel, key, index0)
        assert net_holds(p[:, [PICK, *POINT]], k, 2), (pixel, key, index0)
        assert net_holds(p[:, [CHOICE, *POINT]], k, 3), (pixel, key, index0)


@pytest.mark.parametrize("k", [8, 10])
def test_former_pairing_is_not_a_joint_net(device, prog, k):
    # negative control: the light point beside a jitter drawn apart from it, the frame's shifted Halton point
    # (render/still.py before) or a Sobol pair under its own index shuffle, fails the 4D check the group passes
    n = 1 << k
    former = _run(device, prog, "former_points", 4, n, 17, 5, 0)
    shift = (0.3, 0.6)
    frame_halton = np.array([[(halton(i + 1, 2) + shift[0]) % 1.0, (halton(i + 1, 3) + shift[1]) % 1.0]
                             for i in range(n)]) * 2.0**32
    with_halton = np.column_stack([frame_halton.astype(np.uint32), former[:, 2:]])
    for p in (former, with_halton):
        assert net_holds(p[:, 2:], k, 0)  # each part is stratified alone
        assert not net_holds(p, k, 3)


@pytest.mark.parametrize("index", [0, 37])
def test_camera_group_is_uniform_over_pixels(device, prog, index):
    n = 1 << 14
    assert_uniform_and_uncorrelated(_run(device, prog, "camera_across_pixels", 6, n, 2, index) / 2.0**32)


def test_still_takes_the_pixel_jitter_with_the_jitter_setting(device):
    assert still_flags(Settings(method="ris")) == ON | PIXEL_JITTER
    assert still_flags(Settings(method="ris", jitter=False)) == ON
    seen = []
    scene = mixed_lights_scene(8, 6)
    r = Renderer(scene, Settings(method="ris"), device)
    r.render_still(0, 4, progress=lambda done, n: seen.append(r.qmc))
    assert [s[0] for s in seen] == [ON | PIXEL_JITTER] * 4
    # the jitter moves the camera rays within their pixels: the G-buffer's positions differ from the centres'
    centre = Renderer(scene, Settings(method="ris", jitter=False), device)
    centre.render_still(0, 1)
    r.render_still(0, 1)
    a, b = r.read_gbuffer()["pos"], centre.read_gbuffer()["pos"]
    hit = np.isfinite(a[..., 3]) & np.isfinite(b[..., 3])  # pos.w: the depth, infinite where the ray missed
    moved = np.abs(a[hit][:, :3] - b[hit][:, :3]).max(axis=-1)
    assert hit.sum() > 10 and np.mean(moved > 1e-4) > 0.9


W, H = 16, 12
RUNS = 64  # the random runs are the reference here: sobol_problems takes its standard errors from 64 batches


@pytest.fixture(scope="module")
def random_runs(device):
    """RUNS independent still renders of the random sampler (each seed its own shifted Halton jitter): the
    unbiased estimate the Sobol runs are compared with."""
    s = Settings(method="ris", sampler="random", candidates=4)
    return run_means(mixed_lights_scene(W, H), s, RUNS, 32, device)


def test_sobol_still_with_pixel_jitter_is_unbiased(device, random_runs):
    s = Settings(method="ris", sampler="sobol", candidates=4, bsdf_sampling="on")
    runs = run_means(mixed_lights_scene(W, H), s, RUNS, 32, device)
    assert np.isfinite(runs).all()
    problems = sobol_problems(runs, random_runs)
    assert not problems, problems


@pytest.mark.parametrize("control", ["wrong_pdf", "no_jitter"])
def test_the_jittered_harness_rejects_what_is_not_the_pixel(device, random_runs, monkeypatch, control):
    """Negative controls: a light pdf 2 % too small (tests/bias_controls.py), and Sobol stills without jitter (every
    ray through the pixel's centre, not the pixel's mean over its area): the comparison must reject both."""
    if control == "wrong_pdf":
        wrong_pdf(monkeypatch)
    s = Settings(method="ris", sampler="sobol", candidates=4, bsdf_sampling="on", jitter=control != "no_jitter")
    problems = sobol_problems(run_means(mixed_lights_scene(W, H), s, RUNS, 32, device), random_runs)
    assert any(p.startswith(("outliers", "image means")) for p in problems), (control, problems)
