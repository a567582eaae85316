"""GGX energy tables for the Principled BSDF's energy preservation (opencl/bsdf/tables.h reads them).

Cycles keeps its multiscatter GGX and the diffuse under the specular layer energy-conserving with three tables of
the single-scattering GGX reflection (isotropic, alpha = roughness^2), which we compute here ourselves, by a
deterministic quadrature over the distribution of visible normals (VNDF) of the view direction:

- E(roughness, mu): directional albedo of GGX without Fresnel at view cosine mu, 32 x 32; the VNDF-sampled
  estimate of a reflected direction is G2 / G1 (0 when it points below the surface);
- E_avg(roughness) = integral of 2 mu E(mu) dmu, 32 entries;
- s(roughness, mu, z): the mean, over visible normals h, of the real dielectric Fresnel at dot(h, wo) remapped to
  [0, 1] between its F0 and 1 (and 0 for a reflection below the surface), 16 x 16 x 16, for the IOR
  eta = ior_from_F0(z^4) (most entries at common IORs). The layering estimate of a dielectric specular's albedo is
  then mix(f0, 1, s).

Grid point i of n stands for the parameter i / (n - 1) (roughness and mu clamped to >= 1e-4, z to [1e-4, 0.99]);
the device interpolates linearly between them. The quadrature: QUAD x QUAD midpoints of the unit square mapped to
the projected hemisphere by polar coordinates (r = sqrt(u), phi = 2 pi v): any measure-preserving map gives the
same integral, and a fixed grid makes the tables reproducible bit for bit.

The quadrature takes seconds of numpy; the tables depend on nothing but the constants below, so they ship with the
package (ggx_tables.npz beside this module, written by `python tools/ship_tables.py`) and `ggx_tables()`
reads them, keyed by those constants: a file of other constants (or none) is computed again, with a warning.
tests/upload/test_ggx_tables.py checks the shipped file equals a fresh computation.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

E_SIZE = 32  # roughness x mu
S_SIZE = 16  # roughness x mu x z
QUAD = 64  # midpoints per axis of the quadrature
MU_AVG = 64  # mu midpoints of E_avg's integral

# offsets of the tables in the one device buffer (opencl/bsdf/tables.h has the same numbers)
E_OFFSET = 0
E_AVG_OFFSET = E_SIZE * E_SIZE
S_OFFSET = E_AVG_OFFSET + E_SIZE
TABLE_FLOATS = S_OFFSET + S_SIZE ** 3


def ior_from_f0(f0: np.ndarray | float) -> np.ndarray:
    r = np.sqrt(np.clip(f0, 0.0, 0.99))
    return (1.0 + r) / (1.0 - r)


def fresnel_dielectric(cos_i: np.ndarray, eta: float) -> np.ndarray:
    """Unpolarised Fresnel reflectance from outside into a medium of relative IOR eta > 1."""
    c = np.abs(cos_i)
    g2 = eta * eta - 1.0 + c * c
    g = np.sqrt(np.maximum(g2, 0.0))
    a = (g - c) / (g + c)
    b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return np.where(g2 > 0, 0.5 * a * a * (1.0 + b * b), 1.0)


def _quadrature() -> tuple[np.ndarray, np.ndarray]:
    u = (np.arange(QUAD) + 0.5) / QUAD
    uu, vv = np.meshgrid(u, u, indexing="ij")
    return uu.ravel(), vv.ravel()


def visible_normals(alpha: np.ndarray, mu: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The quadrature's visible normals h (R x N x 3) of each alpha (R) for the view wo = (sqrt(1 - mu^2), 0, mu),
    the reflected directions wi (R x N x 3), and wo."""
    alpha = np.atleast_1d(np.asarray(alpha, np.float64))[:, None]
    wo = np.array([np.sqrt(max(1.0 - mu * mu, 0.0)), 0.0, mu])
    vx, vz = alpha * wo[0], np.full_like(alpha, wo[2])
    vl = np.sqrt(vx * vx + vz * vz)
    vx, vz = vx / vl, vz / vl  # the view in the stretched configuration; its y is 0, so t1 = (0, 1, 0)
    u1, u2 = _quadrature()
    r = np.sqrt(u1)
    phi = 2.0 * np.pi * u2
    p1, p2 = r * np.cos(phi), r * np.sin(phi)
    s = 0.5 * (1.0 + vz)
    p2 = (1.0 - s) * np.sqrt(np.maximum(1.0 - p1 * p1, 0.0)) + s * p2
    p3 = np.sqrt(np.maximum(1.0 - p1 * p1 - p2 * p2, 0.0))
    # t2 = v x t1 = (-vz, 0, vx)
    hx = -p2 * vz + p3 * vx
    hy = np.broadcast_to(p1, hx.shape)
    hz = p2 * vx + p3 * vz
    h = np.stack([alpha * hx, alpha * hy, np.maximum(hz, 0.0)], axis=-1)
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    wi = 2.0 * (h @ wo)[..., None] * h - wo
    return h, wi, wo


def smith_lambda(alpha: np.ndarray, cos: np.ndarray) -> np.ndarray:
    c2 = np.maximum(cos * cos, 1e-30)
    return 0.5 * (np.sqrt(1.0 + alpha * alpha * np.maximum(1.0 / c2 - 1.0, 0.0)) - 1.0)


def directional_albedo(alpha: np.ndarray, mu: float) -> np.ndarray:
    """E at view cosine mu for each alpha."""
    _, wi, _ = visible_normals(alpha, mu)
    a = np.atleast_1d(np.asarray(alpha, np.float64))[:, None]
    lo = smith_lambda(a, np.array(mu))
    weight = np.where(wi[..., 2] > 0, (1.0 + lo) / (1.0 + lo + smith_lambda(a, wi[..., 2])), 0.0)
    return weight.mean(axis=1)


def fresnel_blend(alpha: np.ndarray, mu: float, eta: float) -> np.ndarray:
    """s at view cosine mu and IOR eta for each alpha."""
    h, wi, wo = visible_normals(alpha, mu)
    f0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    s = np.clip((fresnel_dielectric(h @ wo, eta) - f0) / (1.0 - f0), 0.0, 1.0)
    return np.where(wi[..., 2] > 0, s, 0.0).mean(axis=1)


def _grid(n: int, lo: float = 1e-4, hi: float = 1.0) -> np.ndarray:
    return np.clip(np.arange(n) / (n - 1), lo, hi)


#: what the tables depend on: a shipped file made with other values is not used
KEY = np.array([E_SIZE, S_SIZE, QUAD, MU_AVG], np.int64)
SHIPPED = Path(__file__).with_name("ggx_tables.npz")


def read_shipped(path: Path, key: np.ndarray, floats: int, compute: Callable[[], np.ndarray], what: str) -> np.ndarray:
    """The tables in the shipped file `path` where it was made with `key` and holds `floats` values, else compute()
    with a warning naming `what`."""
    try:
        with np.load(path) as z:
            if np.array_equal(z["key"], key) and z["tables"].shape == (floats,):
                return z["tables"].astype(np.float32)
        reason = "it was made with other table sizes"
    except (OSError, KeyError, ValueError) as exc:
        reason = f"it cannot be read ({type(exc).__name__}: {exc})"
    warnings.warn(f"{what}: {path} is not used ({reason}); computing them", RuntimeWarning, stacklevel=3)
    return compute()


@functools.lru_cache(maxsize=1)
def ggx_tables() -> np.ndarray:
    """The tables (compute_ggx_tables), read from the file shipped with the package where it matches KEY."""
    return read_shipped(SHIPPED, KEY, TABLE_FLOATS, compute_ggx_tables, "GGX tables")


def write_shipped(path: Path = SHIPPED) -> None:
    """Compute the tables and write them where ggx_tables() reads them."""
    np.savez_compressed(path, key=KEY, tables=compute_ggx_tables())


def compute_ggx_tables() -> np.ndarray:
    """All three tables in one float32 array: E[rough][mu] (row-major, mu fastest ... see the offsets), E_avg,
    s[z][mu][rough]. Layout: index = E_OFFSET + mu_i * E_SIZE + rough_i; E_AVG_OFFSET + rough_i;
    S_OFFSET + (z_i * S_SIZE + mu_i) * S_SIZE + rough_i."""
    out = np.zeros(TABLE_FLOATS, np.float64)
    alpha = _grid(E_SIZE) ** 2
    for j, m in enumerate(_grid(E_SIZE)):
        out[E_OFFSET + j * E_SIZE:E_OFFSET + (j + 1) * E_SIZE] = directional_albedo(alpha, m)
    mu_mid = (np.arange(MU_AVG) + 0.5) / MU_AVG
    avg = sum(2.0 * m * directional_albedo(alpha, m) for m in mu_mid) / MU_AVG
    out[E_AVG_OFFSET:E_AVG_OFFSET + E_SIZE] = avg
    alpha_s = _grid(S_SIZE) ** 2
    for k, z in enumerate(_grid(S_SIZE, 1e-4, 0.99)):
        eta = float(ior_from_f0(z ** 4))
        for j, m in enumerate(_grid(S_SIZE)):
            o = S_OFFSET + (k * S_SIZE + j) * S_SIZE
            out[o:o + S_SIZE] = fresnel_blend(alpha_s, m, eta)
    return np.clip(out, 0.0, 1.0).astype(np.float32)
