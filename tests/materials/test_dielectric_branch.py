"""The dielectric lobe's choice of branch (opencl/bsdf/microfacet_dielectric.h): sampling reflects or refracts at the
visible microfacet it drew, with that microfacet's reflected share of what it scatters. So every sample of white
glass carries G2 / G1 <= 1, also inside the glass near the critical angle, where a choice by the macroscopic normal's
Fresnel carried up to 1 / its floor (50: the fireflies of rough glass); and the samples' mean is the lobe's albedo,
the integral of f |cos| over the sphere of directions computed here from f alone by quadrature. The quadrature's
check rejects a build whose reflection pdf is 0.8 times too small (TEST_DIELECTRIC_REFLECT_PDF_SCALE)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.core.program import build_program
from restircl.render.features import general_flags

from .bsdf_kernels import view
from .direction_bins import Bins
from .test_bsdf_dielectric import SRC, GlassKernels, glass

# (inside the glass, angle of view in degrees): outside at normal, oblique and grazing views; inside below, at and
# beyond the critical angle of IOR 1.45 (43.6 degrees)
VIEWS = [(False, 0.0), (False, 60.0), (False, 85.0), (True, 30.0), (True, 42.0), (True, 44.0), (True, 50.0)]


class ControlKernels(GlassKernels):
    """The glass kernels built with the test hooks `defines`."""

    def __init__(self, device, *defines: str) -> None:
        super().__init__(device)
        self.prog = build_program(device, general_flags(), source=SRC, extra_options=tuple(f"-D{d}" for d in defines))


@pytest.fixture(scope="module")
def kernels(device):
    return GlassKernels(device)


@pytest.mark.parametrize(("back", "theta"), VIEWS)
def test_white_rough_glass_samples_carry_at_most_one(kernels, back, theta):
    """Roughness 0.3 (and a rougher 0.6): the largest weight of 200 000 samples is G2 / G1 <= 1, each branch's
    f cos / pdf being what the microfacet scatters (1 for white glass) times G2 / G1."""
    for roughness in (0.3, 0.6):
        s = kernels.samples(glass("glass", roughness), back, view(theta), 200_000)
        w = s[:, 1, :3]
        assert np.all(np.isfinite(w))
        assert w.max() <= 1.0 + 1e-4, (roughness, back, theta, w.max())
        assert (s[:, 0, 3] > 0).mean() > 0.8  # most samples draw a direction


def albedo_by_quadrature(kernels, m, back: bool, wo: np.ndarray) -> np.ndarray:
    """The integral of f |cos| over the sphere, rgb, by midpoints of fine bins about the normal (f alone, no pdf)."""
    bins = Bins(wo, "n", n_a=64, n_p=24, sphere=True)
    return np.array([bins.probabilities(lambda d, c=c: kernels.dirs(m, back, wo, d)[:, c] * np.abs(d[:, 2]),
                                        sub=24).sum() for c in range(3)])


def sample_mean(kernels, m, back: bool, wo: np.ndarray, count: int = 400_000) -> tuple[np.ndarray, np.ndarray]:
    w = kernels.samples(m, back, wo, count)[:, 1, :3]
    return w.mean(axis=0), w.std(axis=0) / np.sqrt(count)


@pytest.mark.parametrize(("kind", "back", "theta"), [("glass", False, 30.0), ("glass", True, 40.0),
                                                     ("glass", True, 50.0), ("principled", True, 42.0),
                                                     ("refraction", True, 35.0)])
def test_sample_mean_is_the_albedo(kernels, kind, back, theta):
    """Roughness 0.3, tinted: the samples' mean weight against the quadrature of f |cos|, per channel."""
    m, wo = glass(kind, 0.3, colour=(0.9, 0.6, 0.3)), view(theta)
    mean, se = sample_mean(kernels, m, back, wo)
    ref = albedo_by_quadrature(kernels, m, back, wo)
    assert np.all(np.abs(mean - ref) < 4 * se + 4e-3 * ref), (mean, se, ref)


def test_the_albedo_check_rejects_a_wrong_reflection_pdf(device):
    """Inside near the critical angle, where a good part of the light reflects, a reflection pdf 0.8 times what
    sampling draws makes the reflected samples 1.25 times too heavy: the check above sees it."""
    bad = ControlKernels(device, "TEST_DIELECTRIC_REFLECT_PDF_SCALE=0.8f")
    m, wo = glass("glass", 0.3, colour=(0.9, 0.6, 0.3)), view(40.0)
    mean, se = sample_mean(bad, m, True, wo)
    ref = albedo_by_quadrature(bad, m, True, wo)
    assert np.all(mean - ref > 4 * se + 4e-3 * ref), (mean, se, ref)
