"""The glass energy tables (python/restircl/upload/glass_tables.py): the shipped file is what the quadrature computes
(entries recomputed here), and the albedos it holds behave as a dielectric's must: a smooth interface keeps all
(reflected F plus refracted 1 - F, or all reflected beyond the critical angle from inside), a rough one loses some
and more the rougher, never above 1."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.upload import glass_tables as G
from restircl.upload.ggx_tables import TABLE_FLOATS, ggx_tables


def entry(table_offset: int, rough_i: int, mu_i: int, z_i: int) -> float:
    return float(G.glass_tables()[table_offset - G.OFFSET + (z_i * G.SIZE + mu_i) * G.SIZE + rough_i])


def test_the_tables_follow_the_ggx_tables_in_one_buffer():
    assert G.OFFSET == TABLE_FLOATS
    tab = G.device_tables()
    assert tab.shape == (TABLE_FLOATS + G.FLOATS,) and tab.dtype == np.float32
    np.testing.assert_array_equal(tab[:TABLE_FLOATS], ggx_tables())


@pytest.mark.parametrize(("rough_i", "mu_i", "z_i"), [(0, 15, 5), (5, 8, 3), (10, 2, 9), (15, 12, 15), (7, 0, 6)])
def test_shipped_entries_are_the_quadrature(rough_i, mu_i, z_i):
    grid = np.clip(np.arange(G.SIZE) / (G.SIZE - 1), 1e-4, 1.0)
    z = float(np.clip(z_i / (G.SIZE - 1), 1e-4, 0.99))
    alpha = np.array([grid[rough_i] ** 2])
    for offset, eta in ((G.E_OFFSET, G.eta_of_z(z)), (G.E_INV_OFFSET, 1.0 / G.eta_of_z(z))):
        want = float(np.clip(G.glass_albedo(alpha, float(grid[mu_i]), eta)[0], 1e-3, 1.0))
        assert entry(offset, rough_i, mu_i, z_i) == pytest.approx(want, rel=1e-6, abs=1e-7)


def test_smooth_glass_keeps_all_and_rough_glass_loses_some():
    t = G.glass_tables()
    assert np.all(t > 0) and np.all(t <= 1.0)
    for z_i in (3, 8, 12):
        # smooth (roughness grid point 0), at normal incidence, from either side: F + (1 - F)
        assert entry(G.E_OFFSET, 0, 15, z_i) == pytest.approx(1.0, abs=2e-3)
        assert entry(G.E_INV_OFFSET, 0, 15, z_i) == pytest.approx(1.0, abs=2e-3)
        # rougher loses more at normal incidence
        e = [entry(G.E_OFFSET, r, 15, z_i) for r in (2, 6, 10, 15)]
        assert all(a >= b for a, b in zip(e, e[1:], strict=False)) and e[-1] < 0.99, e
    # from inside at IOR 1.5 (z = 0.447, grid point 6.7) beyond the critical angle: a smooth interface reflects all
    assert entry(G.E_INV_OFFSET, 0, 3, 7) == pytest.approx(1.0, abs=2e-3)
