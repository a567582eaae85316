"""The thin dielectric lobe (opencl/bsdf/thin_dielectric.h) as the Principled BSDF with Thin Wall makes it
(opencl/bsdf/closures/thin_wall.h): its samples over the whole sphere follow its pdf (chi-square); a smooth sheet
reflects R and passes T straight on, unbent, with R and T the slab's sums written out here from the single-face
Fresnel (white: R + T = 1, nothing lost or made); the Base Color is the sheet's transmittance at normal incidence,
stronger along a slanted path inside; the transmission's blur is roughened for the two faces; a rough white sheet
keeps the energy (multiscatter compensation)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.materials.material import Material

from ..stats import pooled_chi2
from .bsdf_kernels import view
from .direction_bins import Bins
from .test_bsdf_dielectric import GlassKernels, fresnel


@pytest.fixture(scope="module")
def kernels(device):
    return GlassKernels(device)


def sheet(roughness: float, ior: float = 1.5, colour=(1.0, 1.0, 1.0), transmission: float = 1.0) -> Material:
    return Material("thin", colour, roughness=roughness, ior=ior, specular=0.5, transmission=transmission,
                    distribution="ggx", thin_wall=True)


def slab(cos_i: float, ior: float, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """R and T of a thin slab of index ior whose normal-incidence transmittance is c, seen at cosine cos_i: a face
    reflects r (Fresnel), transmits 1 - r; a pass inside at cosine cos_t keeps c^(1 / cos_t); the light bounces
    between the faces: T = sum_k (1 - r)^2 a (r a)^(2k), R = r + sum_k (1 - r)^2 a^2 r (r a)^(2k) (a the pass)."""
    r = fresnel(cos_i, ior)
    cos_t = np.sqrt(1.0 - (1.0 - cos_i**2) / ior**2)
    a = c ** (1.0 / cos_t)
    k = np.arange(200)[:, None]
    T = ((1 - r) ** 2 * a * (r * a) ** (2 * k)).sum(axis=0)
    R = r + ((1 - r) ** 2 * a * a * r * (r * a) ** (2 * k)).sum(axis=0)
    return R, T


@pytest.mark.parametrize(("roughness", "ior", "theta"), [(0.3, 1.5, 30.0), (0.3, 1.5, 75.0), (0.6, 1.2, 45.0)])
def test_samples_follow_the_pdf_over_the_sphere(kernels, roughness, ior, theta):
    """Rough sheets: the sampled directions binned over the whole sphere against the pdf integrated over each bin;
    every sample is drawn but for those a GGX reflection sends below its side."""
    m, wo = sheet(roughness, ior), view(theta)
    bins = Bins(wo, "n", n_a=32, n_p=12, sphere=True)
    prob = bins.probabilities(lambda d: kernels.dirs(m, False, wo, d)[:, 3])
    s = kernels.samples(m, False, wo, 200_000)
    drawn = s[:, 0, 3] > 0
    assert abs(drawn.mean() - prob.sum()) < 0.01, (drawn.mean(), prob.sum())
    assert (s[drawn, 0, 2] < 0).mean() > 0.5  # most goes through
    _, p, dof = pooled_chi2(bins.histogram(s[drawn, 0, :3]).ravel(), prob.ravel())
    assert dof > 20
    assert p > 1e-4, (roughness, ior, theta, p)


@pytest.mark.parametrize("theta", [0.0, 40.0, 70.0, 85.0])
@pytest.mark.parametrize("colour", [(1.0, 1.0, 1.0), (0.9, 0.5, 0.2)])
def test_smooth_sheet_reflects_r_and_passes_t_straight_on(kernels, theta, colour):
    """Smooth (Roughness 0) sheet of IOR 1.5: the reflected throughput is the slab's R, the transmitted its T, and
    the transmitted rays leave along -wo (no refraction); white, R + T = 1."""
    wo, c = view(theta), np.array(colour)
    s = kernels.samples(sheet(0.0, colour=colour), False, wo, 50_000)
    w = s[:, 1, :3]
    up = s[:, 0, 2] > 0
    R, T = slab(np.cos(np.radians(theta)), 1.5, c)
    assert np.all(np.isfinite(w)) and np.all(s[:, 0, 3] > 0)
    np.testing.assert_allclose(w[up].sum(axis=0) / len(w), R, rtol=0.03, atol=2e-3)
    np.testing.assert_allclose(w[~up].sum(axis=0) / len(w), T, rtol=0.01, atol=2e-3)
    assert np.quantile(np.linalg.norm(s[~up, 0, :3] + wo, axis=1), 0.99) < 5e-3  # but GGX's tail at alpha 1e-4
    if colour == (1.0, 1.0, 1.0):
        assert w[:, 0].mean() == pytest.approx(1.0, abs=0.01)


def test_the_negative_control_fails_the_slab_bound(kernels):
    """The same material without Thin Wall (a solid's single interface that bends the ray) differs from the slab:
    its transmitted rays are refracted and what one face reflects is about half the slab's R."""
    wo = view(40.0)
    s = kernels.samples(Material("solid", (1.0, 1.0, 1.0), roughness=0.0, ior=1.5, specular=0.5,
                                 transmission=1.0, distribution="ggx"), False, wo, 20_000)
    up = s[:, 0, 2] > 0
    R, _ = slab(np.cos(np.radians(40.0)), 1.5, np.ones(3))
    assert np.quantile(np.linalg.norm(s[~up, 0, :3] + wo, axis=1), 0.5) > 0.1
    assert s[up, 1, 0].sum() / len(s) < 0.7 * R[0]


def test_transmission_blur_is_roughened_by_the_ior(kernels):
    """The transmission's spread about -wo grows with the IOR at one Roughness (two faces refract; IOR 1.05 hardly
    at all), while the reflection keeps alpha = Roughness^2 whatever the IOR."""
    wo = view(0.0)

    def spread(ior: float, side: int) -> float:
        s = kernels.samples(sheet(0.4, ior), False, wo, 40_000)
        pick = (s[:, 0, 2] * side > 0) & (s[:, 0, 3] > 0)
        return float(np.median(np.linalg.norm(s[pick, 0, :2], axis=1)))

    t = {ior: spread(ior, -1) for ior in (1.05, 1.5, 2.5)}
    assert t[1.05] < 0.5 * t[1.5] < 0.5 * t[2.5], t
    assert spread(1.5, 1) == pytest.approx(spread(2.5, 1), rel=0.05)


@pytest.mark.parametrize("theta", [20.0, 60.0])
def test_rough_white_sheet_keeps_the_energy(kernels, theta):
    """Rough (0.5) white sheet: reflected plus transmitted throughput is 1 within the compensation's accuracy."""
    s = kernels.samples(sheet(0.5), False, view(theta), 100_000)
    assert s[:, 1, 0].mean() == pytest.approx(1.0, abs=0.03)


def test_thin_wall_survives_a_scene_file(tmp_path):
    """The flag is saved and loaded with the scene (scene/file.py) and packed into Closure.glass.w for the device."""
    from restircl.eval.scenes.thin_wall import thin_pane
    from restircl.scene.file import load_scene, save_scene
    from restircl.scene.scene import Scene
    from restircl.upload.materials import pack_materials

    for thin in (True, False):
        save_scene(thin_pane(8, 6, 0.2, thin), tmp_path / "pane.json")
        back = load_scene(tmp_path / "pane.json", Scene)
        assert [m.thin_wall for m in back.materials] == [False, thin, False, False]
        assert pack_materials(back.materials).closures["glass"][1, 3] == (1.0 if thin else 0.0)
