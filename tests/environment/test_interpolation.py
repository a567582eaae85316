"""A world read with Linear interpolation (Environment.interpolation, Blender's default for an Environment Texture):
the device blends the four texel centres around a direction as Cycles does (wrapping across the seam and over the
poles); its tables draw the dual cells between texel centres by their patches' means and the sample inside a cell
follows the patch (environment/interpolation.py): the device's density integrates to 1, the samples' histogram
matches it (chi-square), the sampler reports the density that the MIS evaluation gives, and the estimate integrates
to the irradiance of the blended map by quadrature. Negative controls: the density uniform within a dual cell
(what the tables alone give) fails the histogram and the irradiance tests; a blend that clamps at the poles instead
of wrapping fails the lookup test."""

import math

import numpy as np
import pyopencl as cl
import pytest
from restircl import Environment, Scene
from restircl.core.program import build_program
from restircl.environment.interpolation import DualLuminance, dual_row_extent
from restircl.environment.table import row_solid_angles, table_texel_probabilities
from restircl.environment.world import WorldError
from restircl.lights import environment
from restircl.lights.device_lights import scene_lights
from restircl.render.features import general_flags
from restircl.scenes.hdri_sky import texel_directions

from ..stats import pooled_chi2
from .test_environment import sample

SRC = """
#include "types.h"
#include "lights/lights.h"
__kernel void lookup_env(const __global Light* lights, const __global float2* uv, __global float4* out)
{
    int i = get_global_id(0);
    EnvLight env = environment_light(&lights[0]);
    out[i] = (float4)(light_radiance(&lights[0]) * environment_lookup(&env, uv[i].x, uv[i].y), 0.0f);
}
__kernel void pdf_env(const __global Light* lights, const __global float2* uv, __global float4* out)
{
    int i = get_global_id(0);
    EnvLight env = environment_light(&lights[0]);
    LightEval e;
    e.wi = environment_dir(&env, uv[i].x, uv[i].y);
    out[i] = (float4)(light_point_pdf(&lights[0], LIGHT_ENVIRONMENT, (float3)(0.0f), &e), 0.0f, 0.0f, 0.0f);
}
"""


def checker_map(h: int = 8, w: int = 16) -> np.ndarray:
    """Every other texel black, the others coloured: the blend lights the black ones, their own luminance is 0."""
    rng = np.random.default_rng(7)
    img = rng.uniform(0.3, 1.0, (h, w, 3))
    img[(np.arange(h)[:, None] + np.arange(w)[None, :]) % 2 == 1] = 0.0
    return img.astype(np.float32)


def bilinear(img: np.ndarray, u: np.ndarray, v: np.ndarray, wrap_rows: bool = True) -> np.ndarray:
    """Cycles' Linear lookup of an (H, W, 3) map, row 0 at the zenith, at image coordinates (u, v), in float64;
    wrap_rows=False clamps at the poles (the control)."""
    h, w = img.shape[:2]
    x, y = u * w - 0.5, v * h - 0.5
    fx, fy = np.floor(x), np.floor(y)
    tx, ty = (x - fx)[:, None], (y - fy)[:, None]
    c0, r0 = fx.astype(int) % w, fy.astype(int)
    c1, r1 = (c0 + 1) % w, r0 + 1
    r0, r1 = (r0 % h, r1 % h) if wrap_rows else (np.clip(r0, 0, h - 1), np.clip(r1, 0, h - 1))
    t = img.astype(np.float64)
    return (1 - ty) * ((1 - tx) * t[r0, c0] + tx * t[r0, c1]) + ty * ((1 - tx) * t[r1, c0] + tx * t[r1, c1])


def device_lookup(device, env: Environment, uv: np.ndarray, kernel: str = "lookup_env") -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    data = scene_lights(Scene(environment=env), 0).device_array()
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=data)
    ub = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(uv, np.float32))
    out = np.empty((len(uv), 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, kernel)(device.queue, (len(uv),), None, lb, ub, ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out[:, :3].astype(np.float64)


# ---- the host: the tables' weights ------------------------------------------------------------------------------


def test_dual_cells_are_the_blend_integrated_over_each_patch():
    """By midpoints: 64 x 64 per half texel of the wrapped bilinear blend of a random luminance map, summed over the
    dual cells (offset by half a texel; the first and last dual rows are half rows at the poles)."""
    rng = np.random.default_rng(3)
    lum = rng.uniform(0, 1, (5, 7))
    sub = 64
    h, w = lum.shape
    uu, vv = np.meshgrid((np.arange(2 * w * sub) + 0.5) / (2 * w * sub), (np.arange(2 * h * sub) + 0.5) / (2 * h * sub))
    blend = bilinear(np.repeat(lum[..., None], 3, -1), uu.ravel(), vv.ravel())[:, 0].reshape(2 * h, sub, 2 * w, sub)
    halves = blend.mean(axis=(1, 3))  # (2H, 2W) half-texel means
    halves = np.roll(halves, -1, axis=1)  # dual column j: half columns 2j + 1 and 2j + 2
    across = 0.5 * (halves[:, 0::2] + halves[:, 1::2])
    want = np.concatenate([across[:1], 0.5 * (across[1:-1:2] + across[2::2]), across[-1:]])
    got = DualLuminance(lum)[0 : h + 1]
    np.testing.assert_allclose(got, want, rtol=1e-12)


def test_bands_of_rows_equal_the_whole_map():
    lum = np.random.default_rng(5).uniform(0, 1, (9, 6))
    whole = DualLuminance(lum)[0:10]
    parts = np.concatenate([DualLuminance(lum)[a : min(a + 2, 10)] for a in range(0, 10, 2)])
    np.testing.assert_array_equal(whole, parts)
    assert whole.shape == (10, 6) and np.all(whole > 0)
    assert DualLuminance(lum).row_solid.sum() * 6 == pytest.approx(4 * np.pi, rel=1e-12)


def test_a_linear_map_draws_every_dual_cell_of_a_checker():
    packed = environment.packed_map(Environment(image=checker_map(), interpolation="Linear"))
    assert packed.linear and packed.kind == "cdf"
    h, w = packed.shape
    marg, cond = packed.table[: h + 2], packed.table[h + 2 :].reshape(h + 1, w + 1)
    assert np.all(np.diff(marg) > 0) and np.all(np.diff(cond, axis=1) > 0)


def test_unknown_interpolation_is_refused_naming_the_world():
    with pytest.raises(WorldError, match="'sky'.*interpolation"):
        Environment("sky", image=checker_map(), interpolation="Cubic").validate()


# ---- the device -------------------------------------------------------------------------------------------------


def test_lookup_blends_as_cycles_across_the_seam_and_the_poles(device):
    img = checker_map()
    rng = np.random.default_rng(11)
    uv = rng.uniform(0, 1, (4000, 2))
    uv[:500, 1] *= 0.06  # within half a texel of the zenith (1/16 of v), where the blend wraps over the pole
    uv[500:1000, 0] = rng.choice([0.01, 0.99], 500)  # beside the seam
    env = Environment(color=(1, 1, 1), strength=1.5, image=img, interpolation="Linear")
    got = device_lookup(device, env, uv)
    want = 1.5 * bilinear(img, uv[:, 0], uv[:, 1])
    np.testing.assert_allclose(got, want, rtol=2e-3, atol=1e-4)  # half-float texels
    clamped = 1.5 * bilinear(img, uv[:, 0], uv[:, 1], wrap_rows=False)
    assert not np.allclose(got[:500], clamped[:500], rtol=2e-3, atol=1e-4)  # the control: the poles differ
    closest = device_lookup(device, Environment(color=(1, 1, 1), strength=1.5, image=img), uv)
    h, w = img.shape[:2]
    texel = img[np.minimum((uv[:, 1] * h).astype(int), h - 1), np.minimum((uv[:, 0] * w).astype(int), w - 1)]
    np.testing.assert_allclose(closest, 1.5 * texel, rtol=2e-3, atol=1e-4)  # Closest as before


def blended_quadrature(img: np.ndarray, n: np.ndarray, sub: int = 16) -> np.ndarray:
    """The irradiance of the blended map: sum over sub x sub midpoints per texel of L(d) max(0, n . d) d omega."""
    h, w = img.shape[:2]
    d = texel_directions(h * sub, w * sub)
    cos = np.maximum(d @ n, 0.0)
    omega = row_solid_angles(h * sub, w * sub)[:, None]
    uu, vv = np.meshgrid((np.arange(w * sub) + 0.5) / (w * sub), (np.arange(h * sub) + 0.5) / (h * sub))
    radiance = bilinear(img, uu.ravel(), vv.ravel()).reshape(h * sub, w * sub, 3)
    return np.einsum("hw,hwc->c", cos * omega, radiance)


def irradiance_error(device, n: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    img = checker_map()
    env = Environment(color=(1, 1, 1), strength=2.0, image=img, interpolation="Linear")
    out = sample(device, env, "cdf", n=n)
    contrib, ok, pdf = out[:, 1, :3], out[:, 1, 3] > 0, out[:, 0, 2]
    est = np.where(ok[:, None], contrib / np.where(pdf > 0, pdf, 1.0)[:, None], 0.0)
    mean, se = est.mean(axis=0), est.std(axis=0, ddof=1) / math.sqrt(len(est))
    want = 2.0 * blended_quadrature(img, n)
    return mean, want, se


@pytest.mark.parametrize("normal", [(0, 0, 1), (0.6, -0.3, 0.74), (0, 1, 0)])
def test_estimate_integrates_to_the_blended_irradiance(device, normal):
    n = np.asarray(normal, np.float64) / np.linalg.norm(normal)
    mean, want, se = irradiance_error(device, n)
    assert np.all(np.abs(mean - want) <= 4 * se + 2e-3 * want), (mean, want, se)


def uniform_cell_pdf(env: Environment, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The control: the density in solid angle if (u, v) were uniform within the dual cell the tables draw."""
    packed = environment.packed_map(env)
    h, w = packed.shape
    probs = table_texel_probabilities(packed.table, h + 1, w, "cdf")
    t0, t1 = dual_row_extent(h)
    j = np.floor(u * w - 0.5).astype(int) % w
    k = np.clip(np.floor(v * h - 0.5).astype(int) + 1, 0, h)
    area = (t1 - t0)[k] / (h * w)
    return probs[k, j] / area / (2 * np.pi**2 * np.maximum(np.sin(np.pi * v), 1e-7))


def linear_env() -> Environment:
    return Environment(color=(1, 1, 1), strength=2.0, image=checker_map(), interpolation="Linear")


def quarter_grid(h: int, w: int, sub: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """Midpoints of sub x sub bins per texel (the dual cells' edges are bin edges: the density in (u, v) is
    bilinear over each bin, so its midpoint is its mean)."""
    uu, vv = np.meshgrid((np.arange(w * sub) + 0.5) / (w * sub), (np.arange(h * sub) + 0.5) / (h * sub))
    return uu.ravel(), vv.ravel()


def test_device_density_integrates_to_one(device):
    env = linear_env()
    h, w = checker_map().shape[:2]
    u, v = quarter_grid(h, w)
    pdf = device_lookup(device, env, np.stack([u, v], 1), "pdf_env")[:, 0]
    total = np.sum(pdf * 2 * np.pi**2 * np.sin(np.pi * v)) / u.size
    assert abs(total - 1.0) < 2e-4, total


def test_samples_follow_the_reported_density(device):
    """Chi-square of the samples' (u, v) in 4 x 4 bins per texel against the device's density; the control (the
    density uniform within a dual cell) fails. The sampler's density is the MIS evaluation's."""
    env = linear_env()
    h, w = checker_map().shape[:2]
    sub = 4
    u, v = quarter_grid(h, w, sub)
    jac = 2 * np.pi**2 * np.sin(np.pi * v) / u.size
    want = device_lookup(device, env, np.stack([u, v], 1), "pdf_env")[:, 0] * jac
    out = sample(device, env, "cdf", count=400_000, seed=3)
    su, sv, pdf, pdf_back = out[:, 0, 0], out[:, 0, 1], out[:, 0, 2], out[:, 0, 3]
    col = np.minimum((su * w * sub).astype(int), w * sub - 1)
    row = np.minimum((sv * h * sub).astype(int), h * sub - 1)
    counts = np.bincount(row * w * sub + col, minlength=u.size)
    stat, p, dof = pooled_chi2(counts, want)
    assert dof > 1000 and p > 1e-4, (stat, p, dof)
    control = uniform_cell_pdf(env, u, v) * jac
    stat, p, dof = pooled_chi2(counts, control)
    assert p < 1e-12, (stat, p, dof)
    np.testing.assert_allclose(pdf_back, pdf, rtol=2e-3)  # up to the direction's round trip through (u, v)


def test_density_uniform_within_a_dual_cell_is_biased(device):
    """The control of the irradiance test: the same samples weighed by the density the tables alone would give."""
    n = np.array([0.0, 0.0, 1.0])
    env = linear_env()
    out = sample(device, env, "cdf", n=n)
    contrib, ok = out[:, 1, :3], out[:, 1, 3] > 0
    q = uniform_cell_pdf(env, out[:, 0, 0], out[:, 0, 1])
    est = np.where(ok[:, None], contrib / q[:, None], 0.0)
    mean, se = est.mean(axis=0), est.std(axis=0, ddof=1) / math.sqrt(len(est))
    want = 2.0 * blended_quadrature(checker_map(), n)
    assert np.all(np.abs(mean - want) > 10 * se), (mean, want, se)
