"""The environment light (opencl/lights/environment.h): both sampling tables draw texels with probability
luminance x solid angle (exactly on the host, chi-square on the device), directions are uniform in solid angle within
a texel, the pdf the device reports is the density it draws with, and contrib / pdf integrates to the irradiance
computed in numpy by quadrature over the map (within 4 standard errors)."""

import math

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
import pytest
from restircl import Environment, Scene
from restircl.core.program import build_program
from restircl.environment.table import (
    TABLE_KINDS,
    alias_rows,
    build_table,
    row_solid_angles,
    table_texel_probabilities,
    texel_weights,
)
from restircl.lights import environment
from restircl.lights.device_lights import scene_lights
from restircl.lights.record import LUMINANCE
from restircl.render.features import general_flags
from restircl.scenes.hdri_sky import sky_map, texel_directions

from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
__kernel void sample_env(const __global Light* lights, float4 n4, uint seed, __global float4* out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, seed, 0u);
    float r0 = rng_next(&rng), r1 = rng_next(&rng);
    float pdf;
    float3 x = (float3)(0.0f);
    float2 uv = light_sample(&lights[0], x, r0, r1, &pdf);
    LightEval e;
    bool ok = pdf > 0.0f && light_eval(&lights[0], uv.x, uv.y, x, n4.xyz, &e);
    EnvLight env = environment_light(&lights[0]);
    float3 wi = environment_dir(&env, uv.x, uv.y);
    LightEval back;
    back.wi = wi;
    out[3 * i + 0] = (float4)(uv, pdf, light_point_pdf(&lights[0], LIGHT_ENVIRONMENT, x, &back));
    out[3 * i + 1] = (float4)(ok ? e.contrib : (float3)(0.0f), ok ? 1.0f : 0.0f);
    out[3 * i + 2] = (float4)(wi, 0.0f);
}
"""

N = 200_000
UP = np.array([0.0, 0.0, 1.0])


def env_buffer(env: Environment, kind: str, fmt: str = "auto") -> np.ndarray:
    old = environment.TABLE_KIND, environment.TEXEL_FORMAT
    environment.TABLE_KIND, environment.TEXEL_FORMAT = kind, fmt
    try:
        lights = scene_lights(Scene(environment=env), 0)
        assert lights.environment is not None and lights.environment.stored.fmt == ("half" if fmt == "auto" else fmt)
        return lights.device_array()
    finally:
        environment.TABLE_KIND, environment.TEXEL_FORMAT = old


def sample(device, env: Environment, kind: str, n=UP, seed: int = 1, count: int = N, fmt: str = "auto"):
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    data = env_buffer(env, kind, fmt)
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=data)
    out = np.empty((count, 3, 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "sample_env")(device.queue, (count,), None, lb, clt.make_float4(*n, 0.0), np.uint32(seed), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out.astype(np.float64)


def spiky_map(h: int = 16, w: int = 32) -> np.ndarray:
    """Smooth sky, a black band, and one texel 1e3 above the rest."""
    rng = np.random.default_rng(4)
    img = rng.uniform(0.2, 1.0, (h, w, 3))
    img[h // 2 + 2] = 0.0
    img[3, 5] = 1e3
    return img.astype(np.float32)


# ---- the tables on the host ------------------------------------------------------------------------------------


def test_alias_rows_draw_exactly_the_weights():
    rng = np.random.default_rng(2)
    w = rng.uniform(0, 1, (7, 33)) ** 4
    w[2] = 0.0  # a row of zeros: uniform, never drawn
    w[3, :5] = 0.0
    w[4, 7] = 1e5
    prob, alias = alias_rows(w)
    from restircl.environment.table import alias_probabilities

    got = alias_probabilities(prob, alias)
    want = w / np.where(w.sum(1, keepdims=True) > 0, w.sum(1, keepdims=True), 1)
    want[2] = 1.0 / w.shape[1]
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-15)
    assert np.all(got[3, :5] == 0.0)


@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_table_probabilities_are_luminance_times_solid_angle(kind):
    img = spiky_map()
    lum = img.astype(np.float64) @ LUMINANCE
    table = build_table(lum, kind)
    got = table_texel_probabilities(table, *lum.shape, kind)
    want = texel_weights(lum) / texel_weights(lum).sum()
    # alias: probabilities stored to float32's relative precision; cdf: steps of float32 sums (absolute precision)
    np.testing.assert_allclose(got, want, rtol=2e-5, atol=1e-9 if kind == "alias" else 1.5e-7)
    assert np.all(got[lum == 0] == 0.0)


def test_texel_solid_angles_cover_the_sphere():
    for h, w in ((1, 1), (3, 5), (64, 128)):
        assert row_solid_angles(h, w).sum() * w == pytest.approx(4 * math.pi, rel=1e-12)


# ---- sampling on the device ------------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_sampled_texels_follow_the_table(device, kind):
    img = spiky_map()
    env = Environment(color=(1, 1, 1), image=img)
    out = sample(device, env, kind)
    uv, pdf, pdf_back = out[:, 0, :2], out[:, 0, 2], out[:, 0, 3]
    h, w = img.shape[:2]
    col = np.minimum((uv[:, 0] * w).astype(int), w - 1)
    row = np.minimum((uv[:, 1] * h).astype(int), h - 1)
    counts = np.bincount(row * w + col, minlength=h * w)
    lum = img.astype(np.float64) @ LUMINANCE
    want = texel_weights(lum) / texel_weights(lum).sum()
    stat, p, dof = pooled_chi2(counts, want)
    assert dof > 100 and p > 1e-4, (stat, p, dof)
    # the reported density is the texel's probability over its solid angle, also when recomputed from the direction
    dens = want.reshape(-1)[row * w + col] / row_solid_angles(h, w)[row]
    np.testing.assert_allclose(pdf, dens, rtol=1e-3)
    np.testing.assert_allclose(pdf_back, dens, rtol=1e-3)


@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_constant_world_directions_are_uniform_on_the_sphere(device, kind):
    out = sample(device, Environment(color=(0.3, 0.4, 0.5)), kind)
    wi = out[:, 2, :3]
    np.testing.assert_allclose(out[:, 0, 2], 1.0 / (4 * math.pi), rtol=1e-5)
    z = wi[:, 2]
    phi = (np.arctan2(wi[:, 1], wi[:, 0]) + np.pi) / (2 * np.pi)
    hist, _, _ = np.histogram2d((z + 1) / 2, phi, bins=[12, 12], range=[[0, 1], [0, 1]])
    stat, p, dof = pooled_chi2(hist, np.full(hist.shape, 1.0 / hist.size))
    assert p > 1e-4, (stat, p, dof)


@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_directions_are_uniform_in_solid_angle_within_a_texel(device, kind):
    """A 2x4 map: within each texel, cos(theta) and the azimuth are uniform."""
    img = np.ones((2, 4, 3), np.float32)
    img[0, 1] = 5.0
    out = sample(device, Environment(color=(1, 1, 1), image=img), kind)
    wi = out[:, 2, :3]
    uv = out[:, 0, :2]
    sel = (uv[:, 1] < 0.5) & (np.floor(uv[:, 0] * 4) == 1)
    z = wi[sel, 2]  # row 0: cos(theta) in [0, 1]
    hist, _ = np.histogram(z, bins=20, range=(0, 1))
    stat, p, dof = pooled_chi2(hist, np.full(20, 0.05))
    assert p > 1e-4, (stat, p, dof)


def quadrature_irradiance(img: np.ndarray, n: np.ndarray, sub: int = 16) -> np.ndarray:
    """sum over texels of L_i x the integral of max(0, n . w) over the texel, by sub x sub midpoints per texel."""
    h, w = img.shape[:2]
    d = texel_directions(h * sub, w * sub)
    cos = np.maximum(d @ n, 0.0)
    omega = row_solid_angles(h * sub, w * sub)[:, None]
    weight = (cos * omega).reshape(h, sub, w, sub).sum(axis=(1, 3))
    return np.einsum("hw,hwc->c", weight, img.astype(np.float64))


@pytest.mark.parametrize("fmt", ["half", "float"])
@pytest.mark.parametrize("kind", TABLE_KINDS)
@pytest.mark.parametrize("normal", [(0, 0, 1), (0.6, -0.3, 0.74), (0, 1, 0)])
def test_estimate_integrates_to_the_irradiance(device, kind, normal, fmt):
    """Both texel formats (half floats scaled by a power of two, float32) against the float64 quadrature: half's
    rounding (2^-11 of a texel at most) is inside the 1e-3 allowance."""
    img = sky_map(16, 32, sun_scale=0.05)
    rot = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # a quarter turn about Z
    env = Environment(color=(1, 1, 1), strength=2.0, image=img, rotation=rot)
    n = np.asarray(normal, np.float64)
    n /= np.linalg.norm(n)
    out = sample(device, env, kind, n=n, fmt=fmt)
    contrib, ok, pdf = out[:, 1, :3], out[:, 1, 3] > 0, out[:, 0, 2]
    est = np.where(ok[:, None], contrib / np.where(pdf > 0, pdf, 1.0)[:, None], 0.0)
    mean, se = est.mean(axis=0), est.std(axis=0, ddof=1) / math.sqrt(len(est))
    want = 2.0 * quadrature_irradiance(img, rot @ n)  # the map is looked up at R d: n . d = (R n) . (R d)
    assert np.all(np.abs(mean - want) <= 4 * se + 1e-3 * want), (mean, want, se)
