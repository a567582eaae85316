"""The thin-film Fresnel (opencl/bsdf/thin_film.h) against a brute-force spectral evaluation written here: at each
wavelength (360-830 nm, every 0.25 nm) the exact Airy reflectance of the film, the closed form of all its bounces
r = (r12 + r23 e^(i delta)) / (1 + r12 r23 e^(i delta)) with complex amplitudes per polarisation, integrated against
the linear Rec.709 matching functions (upload/thin_film_table.py's CIE fit, normalised to a flat spectrum = 1). The
device sums the series to its third order through the table of the matching functions' Fourier transforms instead.
Also: a film of thickness 0 is the plain Fresnel curve, the table is what its module gives, and the host and device
agree on which closures have a film."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pytest
from restircl.core.program import build_program
from restircl.materials.material import Material
from restircl.upload import thin_film_table
from restircl.upload.materials import pack_materials

from .bsdf_kernels import HEADERS

SRC = """
#include "types.h"
#include "numerics.h"
#include "bsdf/thin_film.h"

/* per row (cos, eta or 0 for a metal, thickness, film IOR) and (f0 rgb, g) of a metal: the film's reflectance */
__kernel void film(const __global float4* p, const __global float4* metal, __global float4* out)
{
    int i = get_global_id(0);
    float4 a = p[i], m = metal[i];
    float3 r = a.y > 0.0f ? thin_film_specular(a.x, a.y, (float3)(m.x, m.y, m.z), a.z, a.w)
                          : thin_film_metal(a.x, m.xyz, (float3)(m.w), a.z, a.w);
    out[i] = (float4)(r, 0.0f);
}
"""
GLASS_SRC = HEADERS + """
/* per row (cos, IOR, thickness, film IOR) and back face (0/1): a rough Glass BSDF closure with that film resolved
 * as the renderer does, then its Fresnel at a microfacet met at cos: what it reflects and what it transmits */
__kernel void glass_film(const __global float4* p, const __global int* back, const __global float* tab,
                         __global float4* out)
{
    int i = get_global_id(0);
    float4 a = p[i];
    ClosureInputs in;
    in.base = (float3)(1.0f);
    in.tint = (float3)(1.0f);
    in.metallic = 0.0f;
    in.roughness = 0.3f;
    in.ior = a.y;
    in.specular = 0.5f;
    in.weight = 1.0f;
    in.kind = CLOSURE_GLASS;
    in.multiscatter = 0;
    in.normal = (float3)(0.0f);
    in.transmission = 0.0f;
    in.backfacing = back[i];
    in.film_thickness = a.z;
    in.film_ior = a.w;
    Lobe l[1];
    int count;
    glass_resolve(&in, 1.0f, in.base, 1.0f, tab, l, &count);
    MicrofacetDielectric m = microfacet_dielectric(&l[0]);
    float3 t;
    float3 r = dielectric_fresnel(&m, a.x, &t);
    out[2 * i] = (float4)(r, 0.0f);
    out[2 * i + 1] = (float4)(t, 0.0f);
}
"""
# the device's error: the series stops at m = 3, the table is linear between 512 points, float32
TOLERANCE = 3e-3
# on a metal the series' remainder grows with R12 R23: 5.4e-3 measured at cos 0.25 on f0 0.9 (1e-3 elsewhere)
METAL_TOLERANCE = 8e-3


def _rgb(lam: np.ndarray, reflectance: np.ndarray) -> np.ndarray:
    cmf = thin_film_table.rgb_cmf(lam)
    return reflectance @ cmf / cmf.sum(axis=0)


def _amplitudes(n1: complex, n2: complex, c1: complex) -> tuple[complex, complex, complex]:
    """s and p amplitudes from medium n1 into n2 at cosine c1, and the cosine in n2 (complex where absorbing)."""
    c2 = np.sqrt(1 - (n1 / n2) ** 2 * (1 - c1 * c1) + 0j)
    rs = (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2)
    rp = (n2 * c1 - n1 * c2) / (n2 * c1 + n1 * c2)
    return rs, rp, c2


def spectral_film(ci: float, d: float, n_f: float, substrate: complex, r23_magnitude: float | None = None,
                  step: float = 0.25, turn: int = 1, ambient: float = 1.0) -> np.ndarray:
    """Linear Rec.709 reflectance of a film (thickness d nm, IOR n_f) on a substrate of complex IOR `substrate` seen
    from IOR `ambient` at cosine ci (1 where total internal reflection keeps it all); r23_magnitude replaces |r23|
    (s and p alike: Cycles' F82 metal keeps the F82 curve's magnitude and the complex IOR's phase). turn -1: the
    film's phase turning the wrong way (a negative control)."""
    lam = np.arange(360.0, 830.0 + step / 2, step)
    rs12, rp12, c2 = _amplitudes(ambient, n_f, ci)
    if c2.real == 0 or (substrate.imag == 0 and _amplitudes(n_f, substrate, c2)[2].real == 0):
        return np.ones(3)  # total internal reflection in the film or under it
    rs23, rp23, _ = _amplitudes(n_f, substrate, c2)
    if r23_magnitude is not None:
        rs23 = r23_magnitude * rs23 / abs(rs23)
        rp23 = r23_magnitude * rp23 / abs(rp23)
    e = np.exp(turn * 2j * np.pi * 2 * n_f * d * c2.real / lam)
    total = np.zeros_like(lam)
    for r12, r23 in ((rs12, rs23), (rp12, rp23)):
        total += 0.5 * np.abs((r12 + r23 * e) / (1 + r12 * r23 * e)) ** 2
    return np.clip(_rgb(lam, total), 0.0, 1.0)


def fresnel(ci: float, eta: float) -> float:
    rs, rp, _ = _amplitudes(1.0, eta, ci)
    return float(0.5 * (abs(rs) ** 2 + abs(rp) ** 2))


def f82(ci: float, f0: float, g: float) -> float:
    m = 6 / 7
    b = (f0 + (1 - f0) * m**5 - g) * 7 / m**6
    s = 1 - ci
    return float(np.clip(f0 + (1 - f0) * s**5 - b * ci * s**6, 0, 1))


def metal_reference(ci: float, f0: float, g: float, d: float, n_f: float, turn: int = 1) -> float:
    """One channel of a film on Cycles' F82 metal: n + ik from (f0, g) by Gulbrandsen's mapping, the magnitude of
    the metal's reflection the F82 curve of the f0 of n + ik relative to the film."""
    r = min(f0, 0.999)
    n = g * (1 - r) / (1 + r) + (1 - g) * (1 + np.sqrt(r)) / (1 - np.sqrt(r))
    k = np.sqrt(max((r * (n + 1) ** 2 - (n - 1) ** 2) / (1 - r), 0.0))
    c2 = np.sqrt(1 - (1 - ci * ci) / n_f**2)
    nr, kr = n / n_f, k / n_f
    f0r = ((nr - 1) ** 2 + kr**2) / ((nr + 1) ** 2 + kr**2)
    return spectral_film(ci, d, n_f, complex(n, k), r23_magnitude=np.sqrt(f82(c2, f0r, g)), turn=turn)


def _f0(eta: float) -> tuple[float, float, float, float]:
    """the specular's f0 that leaves the film's curve unscaled: F0 of eta"""
    f = ((eta - 1) / (eta + 1)) ** 2
    return (f, f, f, 0.0)


def run(device, rows: list[tuple[float, float, float, float]], metal: list[tuple[float, float, float, float]]):
    prog = build_program(device, {"HAS_THIN_FILM": True}, source=SRC)
    p = np.asarray(rows, np.float32)
    m = np.asarray(metal, np.float32)
    out = np.zeros((len(rows), 4), np.float32)
    mf = cl.mem_flags
    bp = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=p)
    bm = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=m)
    bo = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "film")(device.queue, (len(rows),), None, bp, bm, bo)
    cl.enqueue_copy(device.queue, out, bo)
    return out[:, :3]


DIELECTRIC = [(c, eta, d, nf) for c in (1.0, 0.7, 0.3) for eta, d, nf in
              ((1.5, 250.0, 1.33), (1.5, 500.0, 1.33), (1.45, 120.0, 1.8), (1.2, 800.0, 1.6), (1.5, 30.0, 1.33))]


def test_film_on_a_dielectric_matches_the_spectral_integral(device):
    got = run(device, DIELECTRIC, [_f0(eta) for _, eta, _, _ in DIELECTRIC])
    want = np.array([spectral_film(c, d, nf, eta) for c, eta, d, nf in DIELECTRIC])
    assert np.max(np.abs(got - want)) < TOLERANCE, np.max(np.abs(got - want))
    # the films colour the reflection: the channels differ by far more than the tolerance
    assert np.max(np.ptp(want, axis=1)) > 0.02


def test_film_on_a_metal_matches_the_spectral_integral(device):
    cases = [(c, f0, g, d, nf) for c in (1.0, 0.6, 0.25) for f0, g, d, nf in
             ((0.9, 0.95, 250.0, 1.33), (0.6, 0.7, 500.0, 1.33), (0.3, 0.5, 180.0, 1.5))]
    got = run(device, [(c, 0.0, d, nf) for c, _, _, d, nf in cases], [(f0,) * 3 + (g,) for _, f0, g, _, _ in cases])
    want = np.array([metal_reference(c, f0, g, d, nf) for c, f0, g, d, nf in cases])
    assert np.max(np.abs(got - want)) < METAL_TOLERANCE, np.max(np.abs(got - want))
    assert np.max(np.ptp(want, axis=1)) > 0.02


def test_a_film_of_thickness_0_is_the_plain_fresnel_curve(device):
    rows = [(c, eta, 0.0, 1.33) for c in (1.0, 0.5, 0.1) for eta in (1.5, 1.2)]
    got = run(device, rows, [_f0(eta) for _, eta, _, _ in rows])
    want = np.array([[fresnel(c, eta)] * 3 for c, eta, _, _ in rows])
    assert np.max(np.abs(got - want)) < 1e-5
    metal = [(c, 0.0, 0.0, 1.33) for c in (1.0, 0.5, 0.1)]
    got = run(device, metal, [(0.8, 0.8, 0.8, 0.85)] * len(metal))
    want = np.array([[f82(c, 0.8, 0.85)] * 3 for c, _, _, _ in metal])
    assert np.max(np.abs(got - want)) < 1e-4


def test_glass_with_a_film_reflects_the_film_and_transmits_the_rest(device):
    """The Glass BSDF's lobe with a film, from outside and from inside, where Cycles (and the device) rescales the
    film's IOR by the glass's: the stack glass | film | air seen as air | film / IOR | 1 / IOR, whose interfaces
    reflect as the physical stack's but whose optical path is that of a film 1 / IOR as thick (Cycles' choice, kept
    for agreement with it): its reflectance is the spectral integral of the physical stack with that thickness, and
    it transmits 1 - the reflectance."""
    rows = [(c, 1.5, d, nf, back) for c in (1.0, 0.8, 0.5) for d, nf in ((250.0, 1.33), (500.0, 1.33), (300.0, 1.8))
            for back in (0, 1)]
    prog = build_program(device, {"HAS_THIN_FILM": True, "HAS_TRANSMISSION": True, "HAS_GLOSSY": True},
                         source=GLASS_SRC)
    p = np.asarray([r[:4] for r in rows], np.float32)
    back = np.asarray([r[4] for r in rows], np.int32)
    out = np.zeros((2 * len(rows), 4), np.float32)
    mf = cl.mem_flags
    bufs = [cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=x)
            for x in (p, back, np.zeros(4, np.float32))]
    bo = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "glass_film")(device.queue, (len(rows),), None, *bufs, bo)
    cl.enqueue_copy(device.queue, out, bo)
    refl, trans = out[0::2, :3], out[1::2, :3]
    want = np.array([spectral_film(c, d / ior, nf, 1.0, ambient=ior) if b else spectral_film(c, d, nf, ior)
                     for c, ior, d, nf, b in rows])
    err = np.abs(refl - want).max(axis=1)
    assert np.max(err) < TOLERANCE, [(r, e) for r, e in zip(rows, err, strict=True) if e >= TOLERANCE]
    assert np.max(np.abs(refl + trans - 1.0)) < 1e-6
    assert np.max(np.ptp(want, axis=1)) > 0.02


def test_the_wrong_phase_convention_is_caught(device):
    """Negative control: the reference with the film's phase turning the other way (e^(-i delta)), which a film on
    a metal (whose reflection's phase is neither 0 nor pi) tells apart, differs from the device by far more than the
    bound."""
    c, f0, g, d, nf = 1.0, 0.6, 0.7, 300.0, 1.33
    got = run(device, [(c, 0.0, d, nf)], [(f0, f0, f0, g)])[0]
    assert np.max(np.abs(got - metal_reference(c, f0, g, d, nf))) < METAL_TOLERANCE
    assert np.max(np.abs(got - metal_reference(c, f0, g, d, nf, turn=-1))) > 5 * METAL_TOLERANCE


def test_the_table_header_is_current():
    assert thin_film_table.main(["--check"]) == 0
    s = thin_film_table.sensitivity(np.array([0.0]))[0]
    assert np.allclose(s, 1.0)


@pytest.mark.parametrize(("kind", "thickness", "film"), [("principled", 250.0, True), ("glass", 500.0, True),
                                                         ("principled", 0.1, False), ("glossy", 0.0, False)])
def test_a_film_thicker_than_the_cutoff_turns_the_flag_on(kind, thickness, film):
    m = Material("m", kind=kind, thin_film_thickness=thickness, specular=0.5)
    packed = pack_materials([m])
    assert packed.thin_film is film
    assert float(packed.closures["glass"][0, 1]) == np.float32(thickness)  # packed whatever the flag
