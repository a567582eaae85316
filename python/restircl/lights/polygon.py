"""The closed form of the direct light of a polygonal emitter of uniform radiance (the quad and triangle types'
LightType.analytic): its projected solid angle by Lambert's formula, in float64."""

from __future__ import annotations

import numpy as np

from .light_type import NotAnalytic
from .record import FLAG_TWO_SIDED


def polygon_psa(x: np.ndarray, n: np.ndarray, verts: np.ndarray, one_sided: np.ndarray) -> np.ndarray:
    """Projected solid angle (integral of cos over the solid angle) of polygons verts (T, V, 3) seen from points
    x (P, 3) with normals n (P, 3), by Lambert's formula: 1/2 |sum_i theta_i n . unit(g_i x g_i+1)|, (P, T). Each
    polygon must lie on one side of each point's horizon. A one-sided polygon emits along its winding's normal."""
    nv = verts.shape[1]
    nx, ny, nz = (n[:, k : k + 1] for k in range(3))
    g, above, below = [], None, None
    for i in range(nv):  # unit vectors from the points to vertex i, as three (P, T) arrays
        gx, gy, gz = (verts[None, :, i, k] - x[:, k : k + 1] for k in range(3))
        dist = np.sqrt(gx * gx + gy * gy + gz * gz)
        height = gx * nx + gy * ny + gz * nz
        tol = 1e-5 * dist  # float32 positions: a vertex on the horizon may land this far on either side
        a, b = height >= -tol, height <= tol
        above = a if above is None else above & a
        below = b if below is None else below & b
        g.append((gx / dist, gy / dist, gz / dist))
    if np.any(~above & ~below):
        raise NotAnalytic("a polygon light crosses the horizon of a shading point")
    total = np.zeros(above.shape)
    for i in range(nv):
        (ax, ay, az), (bx, by, bz) = g[i], g[(i + 1) % nv]
        cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
        sn = np.sqrt(cx * cx + cy * cy + cz * cz)
        theta = np.arctan2(sn, ax * bx + ay * by + az * bz)
        ok = sn > 0
        total += np.where(ok, theta * (cx * nx + cy * ny + cz * nz) / np.where(ok, sn, 1.0), 0.0)
    psa = 0.5 * np.abs(total)
    psa[~above] = 0.0
    # one-sided emitters: nothing reaches a point behind the emitting side
    nl = np.cross(verts[:, 1] - verts[:, 0], verts[:, 2] - verts[:, 0])  # (T, 3)
    side = sum((x[:, k : k + 1] - verts[None, :, 0, k]) * nl[None, :, k] for k in range(3))
    psa[one_sided[None, :] & ~(side > 0)] = 0.0
    return psa


def polygon_direct(x: np.ndarray, n: np.ndarray, verts: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """LightType.analytic of planar records whose shapes are the polygons verts (S, V, 3), wound so that their
    normal is the emitting side's."""
    return polygon_psa(x, n, verts, (flags & FLAG_TWO_SIDED) == 0)
