"""The GGX energy tables (python/restircl/upload/ggx_tables.py): entries against an independent Monte Carlo integral of
the GGX BRDF over the hemisphere (uniform directions, the BRDF's formula rather than visible normals), within the
estimate's noise; and the error of their linear interpolation between grid points, which bounds the energy
compensation's systematic error (TABLE_ERROR in tests/materials/test_bsdf_principled.py)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.upload import ggx_tables as T

from ..materials.principled_model import _lerp_table, smith_lambda
from ..materials.test_bsdf_principled import TABLE_ERROR


def _uniform_hemisphere(rng, n: int) -> np.ndarray:
    z = rng.random(n)
    phi = 2.0 * np.pi * rng.random(n)
    r = np.sqrt(1.0 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def _mc(alpha: float, mu: float, eta: float | None, n: int = 400_000, seed: int = 3) -> tuple[float, float]:
    """With eta None: E = int f cos dw of GGX without Fresnel; else s = int (VNDF density of wi) * remapped
    Fresnel dw. Mean and standard error."""
    rng = np.random.default_rng(seed)
    wi = _uniform_hemisphere(rng, n)
    wo = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    a2 = alpha * alpha
    c2 = h[:, 2] ** 2
    d = a2 / (np.pi * ((1.0 - c2) + a2 * c2) ** 2)
    lo, li = smith_lambda(a2, np.array(mu)), smith_lambda(a2, wi[:, 2])
    if eta is None:
        val = d / (4.0 * mu * (1.0 + lo + li))  # f cos
    else:
        f0 = ((eta - 1.0) / (eta + 1.0)) ** 2
        s = np.clip((T.fresnel_dielectric(h @ wo, eta) - f0) / (1.0 - f0), 0.0, 1.0)
        val = s * d / (4.0 * mu * (1.0 + lo))
    val = val * 2.0 * np.pi  # / uniform pdf
    return float(val.mean()), float(val.std() / np.sqrt(n))


QUAD_ERROR = 3e-3  # the tables' own quadrature (64 x 64 midpoints, a discontinuity at the horizon)


@pytest.mark.parametrize("i,j", [(31, 31), (10, 20), (20, 5), (31, 2), (25, 15)])
def test_albedo_entries_match_monte_carlo(i, j):
    rough, mu = max(i / 31, 1e-4), max(j / 31, 1e-4)
    tab = T.ggx_tables()
    got = float(tab[T.E_OFFSET + j * T.E_SIZE + i])
    mean, se = _mc(rough * rough, mu, None)
    assert abs(got - mean) < 4.0 * se + QUAD_ERROR, (got, mean, se)


@pytest.mark.parametrize("i,j,k", [(15, 15, 5), (8, 10, 3), (12, 4, 10), (15, 2, 7)])
def test_fresnel_blend_entries_match_monte_carlo(i, j, k):
    rough, mu, z = max(i / 15, 1e-4), max(j / 15, 1e-4), min(max(k / 15, 1e-4), 0.99)
    eta = float(T.ior_from_f0(z ** 4))
    tab = T.ggx_tables()
    got = float(tab[T.S_OFFSET + (k * T.S_SIZE + j) * T.S_SIZE + i])
    mean, se = _mc(rough * rough, mu, eta)
    assert abs(got - mean) < 4.0 * se + QUAD_ERROR, (got, mean, se)


def test_tables_are_finite_and_bounded():
    tab = T.ggx_tables()
    assert tab.shape == (T.TABLE_FLOATS,) and np.all(np.isfinite(tab))
    assert np.all((tab >= 0.0) & (tab <= 1.0))
    # a smooth surface reflects everything it sees: E = 1 at roughness 0 (away from the horizon)
    e = tab[T.E_OFFSET:T.E_AVG_OFFSET].reshape(T.E_SIZE, T.E_SIZE)
    np.testing.assert_allclose(e[2:, 0], 1.0, atol=QUAD_ERROR)


def test_interpolation_error_is_below_the_allowance():
    """E between grid points (cell centres, mu >= 0.1 where shading happens at all but grazing) against E computed
    there directly: the multiscatter compensation's error 1 / E_interp - 1 / E stays below TABLE_ERROR."""
    tab = T.ggx_tables()[T.E_OFFSET:T.E_AVG_OFFSET].astype(np.float64)
    rough = (np.arange(T.E_SIZE - 1) + 0.5) / (T.E_SIZE - 1)
    worst = 0.0
    for mu in (np.arange(3, T.E_SIZE - 1) + 0.5) / (T.E_SIZE - 1):
        direct = T.directional_albedo(rough * rough, float(mu))
        interp = np.array([_lerp_table(tab, T.E_SIZE, [r, float(mu)]) for r in rough])
        worst = max(worst, float(np.max(np.abs(1.0 / interp - 1.0 / direct) * direct)))
    assert worst < TABLE_ERROR, worst


def test_the_shipped_tables_are_a_fresh_computation():
    """ggx_tables() reads the file shipped with the package (tools/ship_tables.py writes it); it must be what the
    quadrature gives now, to float32 rounding of the same float64 sums on another machine's numpy."""
    with np.load(T.SHIPPED) as z:
        assert np.array_equal(z["key"], T.KEY)
        shipped = z["tables"]
    fresh = T.compute_ggx_tables()
    assert shipped.dtype == np.float32 and shipped.shape == fresh.shape
    np.testing.assert_allclose(shipped, fresh, rtol=2e-7, atol=1e-8)
    assert np.array_equal(T.ggx_tables(), shipped)


def test_tables_of_other_sizes_are_computed_again(tmp_path, monkeypatch):
    path = tmp_path / "ggx_tables.npz"
    np.savez_compressed(path, key=T.KEY + 1, tables=np.zeros(T.TABLE_FLOATS, np.float32))
    monkeypatch.setattr(T, "SHIPPED", path)
    T.ggx_tables.cache_clear()
    try:
        with pytest.warns(RuntimeWarning, match="other table sizes"):
            tables = T.ggx_tables()
        assert tables.max() > 0.9
    finally:
        T.ggx_tables.cache_clear()
