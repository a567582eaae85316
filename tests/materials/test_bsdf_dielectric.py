"""The dielectric lobe (opencl/bsdf/microfacet_dielectric.h) as the Glass, Refraction and Principled BSDFs make it,
seen from outside (a front face: eta = IOR) and from inside (a back face: eta = 1 / IOR, total internal
reflection beyond the critical angle): its samples over the whole sphere follow its pdf (chi-square), a smooth
interface's throughput is the Fresnel split of 1 written out here (no energy lost or made), and an IOR of 1
passes rays straight on."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
import pytest
from restircl.materials.material import Material
from restircl.upload.materials import pack_materials

from ..stats import pooled_chi2
from .bsdf_kernels import HEADERS, view
from .direction_bins import Bins
from .lobe_kernels import LobeKernels

SRC = HEADERS + """
inline Surface glass_surface(const __global Closure* cl, int count, int back, const __global float* tab, float3 wo)
{
    ClosureInputs in[MAX_LAYERS];
    for (int k = 0; k < count; ++k) {
        in[k] = closure_constants(&cl[k]);
        in[k].backfacing = back;
    }
    return resolved_surface(in, count, tab, wo);
}

/* per sample of u[i]: (wi, pdf) and (f |cos| / pdf, 0) of the mixture's bsdf_sample, 0 where it drew none */
__kernel void glass_samples(const __global Closure* cl, int count, int back, const __global float* tab, float4 wo4,
                            const __global float2* u, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = glass_surface(cl, count, back, tab, wo4.xyz);
    float3 wi;
    float pdf;
    float3 f = bsdf_sample(&s, wo4.xyz, u[i].x, u[i].y, &wi, &pdf);
    bool ok = pdf > 0.0f;
    out[2 * i] = ok ? (float4)(wi, pdf) : (float4)(0.0f);
    out[2 * i + 1] = ok ? (float4)(f * (abs_f(dot3(s.n, wi)) / pdf), 0.0f) : (float4)(0.0f);
}

/* per direction: (f, pdf) of the mixture */
__kernel void glass_dirs(const __global Closure* cl, int count, int back, const __global float* tab, float4 wo4,
                         const __global float4* dirs, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = glass_surface(cl, count, back, tab, wo4.xyz);
    out[i] = (float4)(bsdf_eval(&s, wo4.xyz, dirs[i].xyz), bsdf_pdf(&s, wo4.xyz, dirs[i].xyz));
}
"""

IOR = 1.45


class GlassKernels(LobeKernels):
    def __init__(self, device) -> None:
        super().__init__(device, SRC)

    def _run(self, name: str, m: Material, back: bool, wo: np.ndarray, size: int, out: np.ndarray, arg) -> np.ndarray:
        ob = cl.Buffer(self.device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
        cl.Kernel(self.prog, name)(self.device.queue, (size,), None, self._buf(pack_materials([m]).closures),
                                   np.int32(1), np.int32(back), self.tab, clt.make_float4(*wo, 0.0), arg, ob)
        cl.enqueue_copy(self.device.queue, out, ob)
        return out.astype(np.float64)

    def samples(self, m: Material, back: bool, wo: np.ndarray, count: int, seed: int = 11) -> np.ndarray:
        """(count, 2, 4): (wi, pdf), (throughput rgb, 0) per sample, 0 where none was drawn"""
        u = np.minimum(np.random.default_rng(seed).random((count, 2)), 0.99999994).astype(np.float32)
        out = np.zeros((count, 2, 4), np.float32)
        return self._run("glass_samples", m, back, wo, count, out, self._buf(u))

    def dirs(self, m: Material, back: bool, wo: np.ndarray, d: np.ndarray) -> np.ndarray:
        d4 = np.zeros((len(d), 4), np.float32)
        d4[:, :3] = d
        return self._run("glass_dirs", m, back, wo, len(d), np.zeros((len(d), 4), np.float32), self._buf(d4))


@pytest.fixture(scope="module")
def kernels(device):
    return GlassKernels(device)


def fresnel(cos_i: float, eta: float) -> float:
    """The unpolarised Fresnel reflectance (from the s and p amplitudes), 1 under total internal reflection."""
    sin_t2 = (1.0 - cos_i**2) / eta**2
    if sin_t2 >= 1.0:
        return 1.0
    cos_t = np.sqrt(1.0 - sin_t2)
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (rs * rs + rp * rp)


def glass(kind: str = "glass", roughness: float = 0.3, ior: float = IOR, colour=(1.0, 1.0, 1.0)) -> Material:
    if kind == "principled":
        return Material("p", colour, roughness=roughness, ior=ior, specular=0.5, transmission=1.0,
                        distribution="ggx")
    return Material(kind, colour, kind=kind, roughness=roughness, ior=ior, distribution="ggx")


CASES = [("glass", False, 30.0), ("glass", True, 30.0), ("glass", True, 60.0), ("glass", False, 80.0),
         ("refraction", False, 40.0), ("refraction", True, 35.0), ("principled", True, 20.0)]


@pytest.mark.parametrize(("kind", "back", "theta"), CASES)
def test_samples_follow_the_pdf_over_the_sphere(kernels, kind, back, theta):
    """Rough (0.3) dielectric lobes: the sampled directions binned over the whole sphere against the pdf integrated
    over each bin, and the share of samples drawn equals the pdf's total (what is not drawn: total internal
    reflection of a refraction, a reflection sent below the surface)."""
    m, wo = glass(kind), view(theta)
    bins = Bins(wo, "n", n_a=32, n_p=12, sphere=True)
    prob = bins.probabilities(lambda d: kernels.dirs(m, back, wo, d)[:, 3])
    s = kernels.samples(m, back, wo, 200_000)
    drawn = s[:, 0, 3] > 0
    assert abs(drawn.mean() - prob.sum()) < 0.01, (drawn.mean(), prob.sum())
    below = (s[drawn, 0, 2] < 0).mean()
    assert below > (0.3 if not back or theta < 40 else 0.0)  # rays go through (but for TIR at 60 degrees inside)
    _, p, dof = pooled_chi2(bins.histogram(s[drawn, 0, :3]).ravel(), prob.ravel())
    assert dof > 20
    assert p > 1e-4, (kind, back, theta, p)


@pytest.mark.parametrize(("back", "theta"), [(False, 0.0), (False, 50.0), (False, 85.0), (True, 20.0),
                                             (True, 40.0), (True, 50.0), (True, 75.0)])
def test_smooth_glass_splits_one_by_fresnel(kernels, back, theta):
    """Smooth white glass: every drawn sample carries 1 / (its branch's probability) of Fresnel's split, so the
    reflected share of the throughput is F(cos theta) and the transmitted 1 - F (eta = IOR outside, 1 / IOR inside,
    where beyond 43.6 degrees all reflects): nothing is lost or made."""
    wo = view(theta)
    s = kernels.samples(glass("glass", 0.0), back, wo, 100_000)
    w = s[:, 1, 0]
    up = s[:, 0, 2] > 0
    F = fresnel(np.cos(np.radians(theta)), 1.0 / IOR if back else IOR)
    assert np.all(np.isfinite(w))
    assert w[up].sum() / len(w) == pytest.approx(F, abs=0.01 + 0.1 * F)
    assert w.mean() == pytest.approx(1.0, abs=0.01)
    if F < 1:  # the refracted directions obey Snell's law (but for the far tail of GGX at alpha 1e-4)
        t = s[~up & (w > 0), 0, :3]
        eta = 1.0 / IOR if back else IOR
        dev = np.abs(np.linalg.norm(t[:, :2], axis=1) - np.sin(np.radians(theta)) / eta)
        assert np.quantile(dev, 0.999) < 2e-3


def test_ior_one_passes_rays_straight_on(kernels):
    """An interface of IOR 1 bends nothing and reflects nothing, whatever its roughness (Cycles' singular case):
    every ray goes on within 1 mrad of its direction, with its colour as the throughput."""
    wo = view(35.0)
    for rough in (0.0, 0.5):
        s = kernels.samples(glass("glass", rough, ior=1.0, colour=(0.9, 0.5, 0.2)), False, wo, 20_000)
        assert np.all(s[:, 0, 3] > 0)
        assert np.all(np.linalg.norm(s[:, 0, :3] + wo, axis=1) < 1.5e-3)
        np.testing.assert_allclose(s[:, 1, :3], np.tile([0.9, 0.5, 0.2], (len(s), 1)), rtol=1e-4)


def test_refraction_bsdf_has_no_reflection_and_no_fresnel(kernels):
    """The Refraction BSDF reflects nothing; smooth, all it does not lose to total internal reflection goes through
    with its colour."""
    wo = view(30.0)
    s = kernels.samples(glass("refraction", 0.0, colour=(0.5, 0.5, 0.5)), False, wo, 20_000)
    assert np.all(s[:, 0, 2] < 0)
    assert s[:, 1, 0].mean() == pytest.approx(0.5, rel=1e-3)
    inside = kernels.samples(glass("refraction", 0.0), True, view(60.0), 2_000)
    assert np.all(inside[:, 0, 3] == 0)  # beyond the critical angle: nothing


def test_principled_transmission_tints_by_the_square_root_of_base_color(kernels):
    """Principled Transmission 1, smooth, Base Color c: the refracted throughput is (1 - F) sqrt(c), the reflected F
    (white Specular Tint); Transmission 0 refracts nothing."""
    wo = view(0.0)
    c = np.array([0.81, 0.36, 0.04])
    s = kernels.samples(glass("principled", 0.0, colour=tuple(c)), False, wo, 50_000)
    down = s[:, 0, 2] < 0
    F = fresnel(1.0, IOR)
    np.testing.assert_allclose(s[down, 1, :3].sum(axis=0) / len(s), (1 - F) * np.sqrt(c), rtol=0.02)
    opaque = Material("p0", tuple(c), roughness=0.0, ior=IOR, specular=0.5, transmission=0.0, distribution="ggx")
    s0 = kernels.samples(opaque, False, view(30.0), 5_000)
    assert np.all(s0[:, 0, 2] >= 0)
