"""Energy tables of the GGX dielectric (glass) lobe, for Multiscatter GGX glass (opencl/bsdf/closures/glass.h reads
them through opencl/bsdf/tables.h): Cycles keeps its rough glass energy-conserving by scaling the single-scattering
lobe with 1 + F_ms (1 - E) / E (Kulla and Conty), E being the lobe's directional albedo. We compute them ourselves,
by the deterministic quadrature over visible normals of upload/ggx_tables.py:

- E(roughness, mu, z): the directional albedo of a clear (untinted) GGX dielectric at view cosine mu, reflection
  weighted by the real Fresnel F at the visible normal and refraction by 1 - F, each direction's estimate G2 / G1
  (0 where a reflection points below the surface, a refraction above it, or the microfacet reflects totally and
  refracts nothing), 16 x 16 x 16, for the relative IOR eta = (1 + z^2) / (1 - z^2) (z = sqrt((eta - 1) /
  (eta + 1)), as Cycles indexes its tables); and the same for 1 / eta, seen from inside (E_inv);
- E_avg(roughness, z) = integral of 2 mu E(mu) dmu, 16 x 16, and E_inv_avg.

Grid point i of n stands for i / (n - 1) (roughness and mu clamped to >= 1e-4, z to [1e-4, 0.99]). The tables sit
after the GGX tables in the one device buffer (ggx_tables() returns both); they ship with the package
(glass_tables.npz, written by `python tools/ship_tables.py`) and are computed again, with a warning, where the file
does not match KEY."""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from .ggx_tables import TABLE_FLOATS, fresnel_dielectric, ggx_tables, read_shipped, smith_lambda, visible_normals

SIZE = 16  # roughness x mu x z
MU_AVG = 32  # mu midpoints of E_avg's integral
OFFSET = TABLE_FLOATS  # after the GGX tables in the device buffer
E_OFFSET = OFFSET
E_INV_OFFSET = E_OFFSET + SIZE**3
E_AVG_OFFSET = E_INV_OFFSET + SIZE**3
E_INV_AVG_OFFSET = E_AVG_OFFSET + SIZE**2
FLOATS = 2 * SIZE**3 + 2 * SIZE**2
KEY = np.array([SIZE, MU_AVG, 64], np.int64)
SHIPPED = Path(__file__).with_name("glass_tables.npz")


def _grid(n: int, lo: float = 1e-4, hi: float = 1.0) -> np.ndarray:
    return np.clip(np.arange(n) / (n - 1), lo, hi)


def eta_of_z(z: float) -> float:
    return (1.0 + z * z) / (1.0 - z * z)


def fresnel_any(cos_i: np.ndarray, eta: float) -> np.ndarray:
    """fresnel_dielectric for eta on either side of 1 (total internal reflection: 1)."""
    if eta >= 1.0:
        return fresnel_dielectric(cos_i, eta)
    c = np.abs(cos_i)
    sin_t2 = (1.0 - c * c) / (eta * eta)
    cos_t = np.sqrt(np.maximum(1.0 - sin_t2, 0.0))
    rs = (c - eta * cos_t) / (c + eta * cos_t)
    rp = (eta * c - cos_t) / (eta * c + cos_t)
    return np.where(sin_t2 < 1.0, 0.5 * (rs * rs + rp * rp), 1.0)


def glass_albedo(alpha: np.ndarray, mu: float, eta: float) -> np.ndarray:
    """E at view cosine mu and relative IOR eta for each alpha."""
    h, wr, wo = visible_normals(alpha, mu)
    a = np.atleast_1d(np.asarray(alpha, np.float64))[:, None]
    lo = smith_lambda(a, np.array(mu))
    c = h @ wo
    F = fresnel_any(c, eta)
    ct2 = 1.0 - (1.0 - c * c) / (eta * eta)
    ct = np.sqrt(np.maximum(ct2, 0.0))
    wt = (c / eta - ct)[..., None] * h - wo / eta
    wt /= np.maximum(np.linalg.norm(wt, axis=-1, keepdims=True), 1e-30)
    refl = np.where(wr[..., 2] > 0, F * (1.0 + lo) / (1.0 + lo + smith_lambda(a, wr[..., 2])), 0.0)
    refr = np.where((ct2 > 0) & (wt[..., 2] < 0),
                    (1.0 - F) * (1.0 + lo) / (1.0 + lo + smith_lambda(a, wt[..., 2])), 0.0)
    return (refl + refr).mean(axis=1)


def compute_glass_tables() -> np.ndarray:
    """E, E_inv (index: (z_i * SIZE + mu_i) * SIZE + rough_i), E_avg, E_inv_avg (z_i * SIZE + rough_i), float32."""
    out = np.zeros(FLOATS, np.float64)
    alpha = _grid(SIZE) ** 2
    mu_mid = (np.arange(MU_AVG) + 0.5) / MU_AVG
    for k, z in enumerate(_grid(SIZE, 1e-4, 0.99)):
        for inv, (o_e, o_avg) in enumerate(((E_OFFSET, E_AVG_OFFSET), (E_INV_OFFSET, E_INV_AVG_OFFSET))):
            eta = eta_of_z(float(z)) ** (-1 if inv else 1)
            for j, m in enumerate(_grid(SIZE)):
                o = o_e - OFFSET + (k * SIZE + j) * SIZE
                out[o:o + SIZE] = glass_albedo(alpha, float(m), eta)
            avg = sum(2.0 * m * glass_albedo(alpha, float(m), eta) for m in mu_mid) / MU_AVG
            out[o_avg - OFFSET + k * SIZE:o_avg - OFFSET + (k + 1) * SIZE] = avg
    return np.clip(out, 1e-3, 1.0).astype(np.float32)


@functools.lru_cache(maxsize=1)
def glass_tables() -> np.ndarray:
    """The tables (compute_glass_tables), read from the file shipped with the package where it matches KEY."""
    return read_shipped(SHIPPED, KEY, FLOATS, compute_glass_tables, "glass tables")


def write_shipped(path: Path = SHIPPED) -> None:
    np.savez_compressed(path, key=KEY, tables=compute_glass_tables())


def device_tables() -> np.ndarray:
    """The one table buffer of the device: the GGX tables, then the glass tables (opencl/bsdf/tables.h)."""
    return np.concatenate([ggx_tables(), glass_tables()])
