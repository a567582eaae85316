"""A world read with Linear interpolation (Environment.interpolation, Blender's default for an Environment Texture):
the device blends the four texel centres around a direction as Cycles does (wrapping across the seam and over the
poles), its tables draw each texel by the blend's integral over it (environment/interpolation.py), and the
estimate integrates to the irradiance of the blended map by quadrature. Negative controls: tables of the texels' own
luminance (a black texel beside a bright one never drawn, its light lost) fail the irradiance test; a blend that
clamps at the poles instead of wrapping fails the lookup test."""

import math

import numpy as np
import pyopencl as cl
import pytest
from restircl import Environment, Scene
from restircl.core.program import build_program
from restircl.environment import interpolation
from restircl.environment.interpolation import LinearLuminance, cell_integrals
from restircl.environment.table import row_solid_angles
from restircl.environment.world import WorldError
from restircl.lights import environment
from restircl.lights.device_lights import scene_lights
from restircl.render.features import general_flags
from restircl.scenes.hdri_sky import texel_directions

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


def device_lookup(device, env: Environment, uv: np.ndarray) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    data = scene_lights(Scene(environment=env), 0).device_array()
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=data)
    ub = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(uv, np.float32))
    out = np.empty((len(uv), 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "lookup_env")(device.queue, (len(uv),), None, lb, ub, ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out[:, :3].astype(np.float64)


# ---- the host: the tables' weights ------------------------------------------------------------------------------


def test_cell_weights_are_the_blend_integrated_over_each_texel():
    """By midpoints: 64 x 64 per texel of the wrapped bilinear blend of a random luminance map."""
    rng = np.random.default_rng(3)
    lum = rng.uniform(0, 1, (5, 7))
    sub = 64
    h, w = lum.shape
    uu, vv = np.meshgrid((np.arange(w * sub) + 0.5) / (w * sub), (np.arange(h * sub) + 0.5) / (h * sub))
    blend = bilinear(np.repeat(lum[..., None], 3, -1), uu.ravel(), vv.ravel())[:, 0].reshape(h * sub, w * sub)
    want = blend.reshape(h, sub, w, sub).mean(axis=(1, 3))
    got = cell_integrals(lum, lum[-1], lum[0])
    np.testing.assert_allclose(got, want, rtol=1e-12)


def test_bands_of_rows_equal_the_whole_map():
    lum = np.random.default_rng(5).uniform(0, 1, (9, 6))
    whole = LinearLuminance(lum)[0:9]
    parts = np.concatenate([LinearLuminance(lum)[a : min(a + 2, 9)] for a in range(0, 9, 2)])
    np.testing.assert_array_equal(whole, parts)
    assert np.all(whole > 0)


def test_a_linear_map_draws_black_texels_beside_bright_ones():
    packed = environment.packed_map(Environment(image=checker_map(), interpolation="Linear"))
    assert packed.linear and packed.kind == "cdf"
    h, w = packed.shape
    marg, cond = packed.table[: h + 1], packed.table[h + 1 :].reshape(h, w + 1)
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


def test_tables_of_the_texels_own_luminance_lose_light(device, monkeypatch):
    """The control: the tables without the blend's weights never draw the black texels, a third of the light."""
    monkeypatch.setattr(environment, "LinearLuminance", lambda rows: rows)
    assert interpolation.LinearLuminance is not environment.LinearLuminance
    mean, want, se = irradiance_error(device, np.array([0.0, 0.0, 1.0]))
    assert np.all(mean < want - 10 * se), (mean, want, se)
