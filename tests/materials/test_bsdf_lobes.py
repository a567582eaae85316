"""Each lobe kind of the BSDF (opencl/bsdf/<kind>.h, registered in bsdf/lobes.h) by itself: it has every piece the
dispatch calls, its code reaches the device, its samples follow its own pdf, and the mixture (bsdf/bsdf.h) is the
sum of its parts' f with a pdf that is their pdfs averaged by the parts' sampling weights. A lobe is made the way the
renderer makes it: a closure of a kind that declares it (materials/closures/), packed and resolved on the device."""

from __future__ import annotations

import re

import numpy as np
import pytest
from restircl.core.program import opencl_dir
from restircl.materials.closures.registry import CLOSURE_KINDS
from restircl.materials.material import Material

from ..stats import pooled_chi2
from .bsdf_kernels import view
from .direction_bins import Bins
from .lobe_kernels import LobeKernels, device_lobe_kinds, mid_material

LOBES = device_lobe_kinds()
PIECES = ("eval", "pdf", "sample", "albedo", "weights")


@pytest.fixture(scope="module")
def kernels(device):
    return LobeKernels(device)


def _code(name: str) -> int:
    header = (opencl_dir() / "bsdf" / f"{name}.h").read_text()
    found = re.search(rf"#define {LOBES[name]} (\d+)\b", header)
    assert found, f"bsdf/{name}.h does not define {LOBES[name]}"
    return int(found.group(1))


def _material(name: str) -> Material:
    """A closure whose kind declares lobe `name`, one that makes it first where there is one (with a thin film for
    the lobe that only a film makes)."""
    kinds = sorted((k for k in CLOSURE_KINDS if name in k.lobes), key=lambda k: (k.lobes[0] != name, k.code))
    assert kinds, f"no closure kind makes lobe {name!r} (ClosureKind.lobes)"
    m = mid_material(kinds[0].name)
    if name == "thin_dielectric":  # the Principled's transmission on a thin wall
        m.transmission, m.thin_wall = 0.6, True
    elif name == "thin_film_reflection":
        m.thin_film_thickness = 300.0
    return m


def _transmits(name: str) -> bool:
    """Whether the material that makes lobe `name` refracts: its samples then cover the whole sphere."""
    m = _material(name)
    return bool([k for k in CLOSURE_KINDS if k.name == m.kind][0].transmits(m))


def _slot(kernels: LobeKernels, m: Material, wo: np.ndarray, name: str) -> int:
    _, lobes = kernels.surface(m, wo)
    slots = [k for k, lb in enumerate(lobes) if lb["kind"] == _code(name)]
    assert slots, f"{m.kind} resolved no {name} lobe"
    return slots[0]


def test_there_are_lobe_kinds_and_their_codes_differ():
    assert "microfacet_reflection" in LOBES
    codes = [_code(n) for n in LOBES]
    assert len(set(codes)) == len(codes), codes


@pytest.mark.parametrize("name", sorted(LOBES))
def test_each_lobe_kind_has_its_pieces(name):
    path = opencl_dir() / "bsdf" / f"{name}.h"
    assert path.exists(), f"lobe {name}: no opencl/bsdf/{name}.h"
    header = path.read_text()
    assert LOBES[name] == f"LOBE_{name.upper()}", f"lobe {name}: its code is named {LOBES[name]}"
    for piece in PIECES:
        assert re.search(rf"^inline \w+ {name}_{piece}\(", header, re.M), f"lobe {name}: no {name}_{piece}"
    assert f'#include "bsdf/{name}.h"' in (opencl_dir() / "bsdf" / "lobes.h").read_text(), name


def test_lobe_codes_agree_on_the_device(kernels):
    assert kernels.lobe_codes() == [_code(n) for n in LOBES]


@pytest.mark.parametrize("name", sorted(LOBES))
@pytest.mark.parametrize("theta", [20.0, 65.0])
def test_lobe_samples_follow_its_pdf(kernels, name, theta):
    """The lobe's own samples binned about the normal against its pdf integrated over each bin (over the sphere for a
    lobe that refracts); the directions it cannot produce (pdf 0: below a reflecting surface) are left out, and
    their share must be what the pdf leaves of 1."""
    m, wo = _material(name), view(theta)
    slot = _slot(kernels, m, wo, name)
    _, lobes = kernels.surface(m, wo)
    assert lobes[slot]["weight"] > 0 and np.all(np.isfinite(lobes[slot]["albedo"]))
    assert np.all(lobes[slot]["albedo"] >= 0)
    bins = Bins(wo, "n", sphere=_transmits(name))
    prob = bins.probabilities(lambda d: kernels.directions(m, wo, d)[:, 2 + slot, 3])
    total = prob.sum()
    assert 0.5 < total <= 1.0 + 1e-3
    s = kernels.lobe_samples(m, wo, slot, 200_000)
    drawn = s[:, 3] > 0
    pdf_at = np.zeros(len(s))
    pdf_at[drawn] = kernels.directions(m, wo, s[drawn, :3])[:, 2 + slot, 3]
    ok = pdf_at > 0
    assert abs((1.0 - ok.mean()) - (1.0 - total)) < 0.01
    _, p, dof = pooled_chi2(bins.histogram(s[ok, :3]).ravel(), prob.ravel())
    assert dof > 20
    assert p > 1e-4, (name, theta, p)


@pytest.mark.parametrize("name", sorted(LOBES))
def test_mixture_is_the_sum_of_its_parts(kernels, name):
    """f is Lambert's plus each lobe's; the pdf is the parts' pdfs averaged with their sampling weights."""
    other = Material("other", albedo=(0.3, 0.6, 0.2), metallic=0.3, roughness=0.7, specular=0.5)
    m = Material.mixed(_material(name), other, 0.4)
    rng = np.random.default_rng(3)
    for theta in (0.0, 50.0, 85.0):
        wo = view(theta)
        w_lambert, lobes = kernels.surface(m, wo)
        assert len(lobes) == 2 and w_lambert > 0
        dirs = rng.normal(size=(512, 3))
        dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
        out = kernels.directions(m, wo, dirs)
        weights = np.array([w_lambert, lobes[0]["weight"], lobes[1]["weight"]])
        parts = out[:, 1:4]
        np.testing.assert_allclose(out[:, 0, :3], parts[:, :, :3].sum(axis=1), rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(out[:, 0, 3], parts[:, :, 3] @ weights / weights.sum(), rtol=1e-5, atol=1e-9)
