"""The BSDF seam (opencl/bsdf/bsdf.h), Lambert: f = albedo / pi computed as the renderer always has (bit for bit), the
pdf integrates to 1 over the sphere and is 0 below the surface, a cosine sample's f cos / pdf is the albedo, and the
samples follow the pdf (chi-square over cos^2 and azimuth)."""

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
import pytest
from restircl.core.program import build_program
from restircl.render.features import general_flags

from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "numerics.h"
#include "sampling/rng.h"
#include "lights/lights.h"
#include "surface/surface.h"
#include "bsdf/bsdf.h"

inline Surface test_surface(float4 n4, float4 albedo4)
{
    Surface s;
    s.x = (float3)(0.0f);
    surface_set_normal(&s, n4.xyz);
    s.wo = n4.xyz;
    s.mat.albedo = albedo4.xyz;
#ifdef HAS_GLOSSY
    s.mat.lobes = 0;
#endif
    s.depth = 1.0f;
    s.valid = 1;
    s.prim = 0;
    return s;
}

/* per direction: (f, pdf) */
__kernel void eval_dirs(float4 n4, float4 albedo4, float4 wo4, const __global float4* dirs, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = test_surface(n4, albedo4);
    float3 wi = dirs[i].xyz;
    out[i] = (float4)(bsdf_eval(&s, wo4.xyz, wi), bsdf_pdf(&s, wo4.xyz, wi));
}

/* per sample: (wi, pdf), (f, bsdf_pdf at wi) */
__kernel void sample_dirs(float4 n4, float4 albedo4, float4 wo4, uint seed, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = test_surface(n4, albedo4);
    uint rng = rng_seed((uint)i, 0u, seed, 0u);
    float u0 = rng_next(&rng), u1 = rng_next(&rng);
    float3 wi;
    float pdf;
    float3 f = bsdf_sample(&s, wo4.xyz, u0, u1, &wi, &pdf);
    out[2 * i] = (float4)(wi, pdf);
    out[2 * i + 1] = (float4)(f, bsdf_pdf(&s, wo4.xyz, wi));
}
"""

ALBEDO = (0.8, 0.45, 0.05)
NORMALS = [(0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (0.48, -0.6, 0.64), (1.0, 0.0, 0.0)]


def _f4(v) -> np.ndarray:
    return clt.make_float4(*v, 0.0)


def _unit(v) -> np.ndarray:
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v)


def eval_dirs(device, n, dirs: np.ndarray, wo=None) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    d4 = np.zeros((len(dirs), 4), np.float32)
    d4[:, :3] = dirs
    db = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=d4)
    out = np.empty((len(dirs), 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "eval_dirs")(device.queue, (len(dirs),), None, _f4(n), _f4(ALBEDO), _f4(wo if wo else n), db, ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def sample_dirs(device, n, count: int, seed: int = 3) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    out = np.empty((count, 2, 4), np.float32)
    ob = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "sample_dirs")(device.queue, (count,), None, _f4(n), _f4(ALBEDO), _f4(n), np.uint32(seed), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def sphere_grid(res: int) -> np.ndarray:
    """Midpoints of a res x res grid uniform in (z, azimuth): cells of equal solid angle 4 pi / res^2."""
    z = -1.0 + (np.arange(res) + 0.5) * (2.0 / res)
    phi = (np.arange(res) + 0.5) * (2.0 * np.pi / res)
    zz, pp = np.meshgrid(z, phi, indexing="ij")
    r = np.sqrt(1.0 - zz * zz)
    return np.stack([r * np.cos(pp), r * np.sin(pp), zz], axis=-1).reshape(-1, 3)


def test_lambert_eval_is_albedo_over_pi_bit_for_bit(device):
    rng = np.random.default_rng(1)
    dirs = rng.normal(size=(256, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    out = eval_dirs(device, NORMALS[2], dirs, wo=(0.0, 1.0, 0.0))
    want = np.asarray(ALBEDO, np.float32) * np.float32(0.318309886183791)
    # the general build has refracting lobes (HAS_TRANSMISSION): there the Lambert part is 0 below the surface
    above = dirs @ _unit(NORMALS[2]) > 0
    np.testing.assert_array_equal(out[above, :3], np.broadcast_to(want, (int(above.sum()), 3)))
    np.testing.assert_array_equal(out[~above, :3], 0.0)


@pytest.mark.parametrize("n", NORMALS)
def test_pdf_integrates_to_one_and_is_zero_below(device, n):
    dirs = sphere_grid(400)
    pdf = eval_dirs(device, _unit(n), dirs)[:, 3].astype(np.float64)
    assert abs(pdf.sum() * 4.0 * np.pi / len(dirs) - 1.0) < 1e-3
    cos = dirs @ _unit(n)
    assert np.all(pdf[cos < -1e-6] == 0.0) and np.all(pdf >= 0.0)
    np.testing.assert_allclose(pdf[cos > 0], cos[cos > 0] / np.pi, rtol=1e-5, atol=1e-7)


@pytest.mark.parametrize("n", NORMALS)
def test_cosine_sample_weight_is_the_albedo(device, n):
    n = _unit(n)
    out = sample_dirs(device, n, 50_000)
    wi, pdf, f, pdf_at = out[:, 0, :3], out[:, 0, 3], out[:, 1, :3], out[:, 1, 3]
    np.testing.assert_allclose(np.linalg.norm(wi, axis=1), 1.0, rtol=1e-5)
    cos = wi.astype(np.float64) @ n
    assert np.all(cos >= -1e-6)
    np.testing.assert_array_equal(pdf, pdf_at)
    ok = pdf > 0
    assert ok.mean() > 0.999
    weight = f[ok] * (cos[ok] / pdf[ok])[:, None]
    np.testing.assert_allclose(weight, np.broadcast_to(ALBEDO, weight.shape), rtol=1e-4)


@pytest.mark.parametrize("n", NORMALS[1:3])
def test_samples_follow_the_cosine_pdf(device, n):
    # with density cos / pi, cos^2 is uniform in [0, 1) and the azimuth uniform about n
    n = _unit(n)
    wi = sample_dirs(device, n, 200_000, seed=11)[:, 0, :3].astype(np.float64)
    t = _unit(np.cross(n, (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)))
    b = np.cross(n, t)
    c2 = np.clip((wi @ n) ** 2, 0.0, 1.0 - 1e-12)
    phi = np.arctan2(wi @ b, wi @ t) % (2.0 * np.pi)
    bins_c, bins_p = 16, 12
    hist, _, _ = np.histogram2d(c2, phi, bins=(bins_c, bins_p), range=((0.0, 1.0), (0.0, 2.0 * np.pi)))
    _, p, _ = pooled_chi2(hist, np.full(hist.shape, 1.0 / hist.size))
    assert p > 1e-3
