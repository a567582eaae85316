"""How closely the light tree's pick follows each light's share of the light at points on a kind's surfaces, above
all beside its lights (issue 37: the `user` kind's first-frame fireflies are NEE samples at bounce vertices near
small point lights that the tree picks at a fraction of their share). Host only: the float64 pmf of lights/tree.py.

Points are drawn on the scene's triangles by area, each with its triangle's normal turned towards the nearest local
light; `near` points are those within --near metres of a local light's centre. At each point q_i is each local
light's share of its unshadowed direct light there (the type's closed form, lights/<type>.py `analytic`, times its
radiance's luminance; where there is none, a quadrature of the shape), p_i the tree's pick within the
local lights (lights/tree.py pmf over the tree's share); --exact 0 gives the tree before its exact pick below small
nodes (lights/tree_exact.py). The variance factor sum q_i^2 / p_i is 1 for a pick by share,
and is what one light sample's relative second moment is multiplied by against such a pick.

    python -m tools.experiments.tree_near_lights --kind user --points 3000 --near 0.6 [--exact 0]
"""

from __future__ import annotations

import argparse

import numpy as np
from restircl.eval.cycles.compare import scene_pair
from restircl.lights import tree as light_tree
from restircl.lights.device_lights import scene_lights
from restircl.lights.light_type import NotAnalytic
from restircl.lights.record import FLAG_TWO_SIDED, LUMINANCE
from restircl.lights.registry import type_with_code
from restircl.lights.spot import mask as spot_mask
from restircl.lights.tree import build_light_tree, pmf


def surface_points(scene, count: int, rng) -> tuple[np.ndarray, np.ndarray]:
    """`count` points on the scene's triangles by area, and their geometric normals."""
    wt = scene.world_triangles(0)
    cross = np.cross(wt.v1 - wt.v0, wt.v2 - wt.v0)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    tri = rng.choice(len(area), count, p=area / area.sum())
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1
    u, v = np.where(flip, 1 - u, u), np.where(flip, 1 - v, v)
    x = wt.v0[tri] + u[:, None] * (wt.v1[tri] - wt.v0[tri]) + v[:, None] * (wt.v2[tri] - wt.v0[tri])
    n = cross[tri] / np.linalg.norm(cross[tri], axis=1, keepdims=True)
    return x, n


def _area_direct(x: np.ndarray, n: np.ndarray, lane: np.ndarray, flag: int, disk: bool) -> float:
    """The projected solid angle of a quad (origin corner, edge spans) or ellipse (centre, half axes) record by a
    stratified quadrature of 32 x 32 points: cos at x x cos at the light / d^2 x area."""
    k = 32
    u, v = np.meshgrid((np.arange(k) + 0.5) / k, (np.arange(k) + 0.5) / k)
    u, v = u.ravel(), v.ravel()
    p, a, b = lane[0:3], lane[4:7], lane[8:11]
    if disk:
        r, t = np.sqrt(u), 2 * np.pi * v
        pts = p + (r * np.cos(t))[:, None] * a + (r * np.sin(t))[:, None] * b
        area = np.pi * np.linalg.norm(np.cross(a, b))
    else:
        pts = p + u[:, None] * a + v[:, None] * b
        area = np.linalg.norm(np.cross(a, b))
    nl = np.cross(a, b) / np.linalg.norm(np.cross(a, b))
    d = pts - x
    d2 = np.einsum("ij,ij->i", d, d)
    w = d / np.sqrt(d2)[:, None]
    cos_i = np.clip(w @ n, 0, None)
    cos_e = -(w @ nl)
    cos_e = np.abs(cos_e) if flag & FLAG_TWO_SIDED else np.clip(cos_e, 0, None)
    return float(np.mean(cos_i * cos_e / d2) * area)


def shares(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray, types: np.ndarray) -> np.ndarray:
    """(S,) each light's unshadowed direct light at x (normal n), luminance-weighted: the type's closed form, or,
    where it has none (disk lights, a light across the horizon), a quadrature of the shape (area lights) or the
    light's centre (spheres and spots)."""
    out = np.zeros(len(lanes))
    rest = []
    for code in np.unique(types):  # each type at once where its closed form holds for every light of it
        sel = np.flatnonzero(types == code)
        try:
            g = type_with_code(code).analytic(x[None], n[None], lanes[sel], flags[sel])[0]
            out[sel] = g * (lanes[sel, 12:15] @ LUMINANCE)
        except NotAnalytic:
            rest.extend(sel.tolist())
    for i in rest:
        t = type_with_code(types[i])
        try:
            g = t.analytic(x[None], n[None], lanes[i:i + 1], flags[i:i + 1])[0, 0]
        except NotAnalytic:
            if t.name in ("quad", "disk"):
                g = _area_direct(x, n, lanes[i], int(flags[i]), t.name == "disk")
            else:
                d = lanes[i, :3] - x
                dist = float(np.linalg.norm(d))
                g = np.pi * (lanes[i, 7] / dist) ** 2 * max(float(d @ n) / dist, 0.0)
                if t.name == "spot":
                    g *= float(spot_mask(lanes[i:i + 1], x[None])[0, 0])
        out[i] = g * float(LUMINANCE @ lanes[i, 12:15])
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", default="user")
    ap.add_argument("--points", type=int, default=3000)
    ap.add_argument("--near", type=float, default=0.6)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--show", type=int, default=0, help="print the N worst near points")
    ap.add_argument("--exact", type=int, default=None,
                    help="lights/tree_exact.py EXACT in place of its value (0: every node by its bound, as before)")
    ap.add_argument("--tree-near", type=float, default=None,
                    help="lights/tree_exact.py NEAR in place of its value (1e30: every small node picks exactly)")
    a = ap.parse_args()
    if a.exact is not None:
        light_tree.EXACT = a.exact
    if a.tree_near is not None:
        light_tree.NEAR = a.tree_near
    scene, _ = scene_pair(a.kind, 96, 54)
    dl = scene_lights(scene, 0)
    tree = build_light_tree(dl.records, dl.types, dl.power)
    local = tree.light_info[:, 0] >= 0
    lanes = dl.records.view(np.float32).reshape(-1, 16).astype(np.float64)
    flags = dl.records.view(np.int32).reshape(-1, 16)[:, 15]
    centres = lanes[local, :3]
    rng = np.random.default_rng(a.seed)
    x, n = surface_points(scene, a.points, rng)
    rows = []
    for k in range(len(x)):
        d = np.linalg.norm(centres - x[k], axis=1)
        near = int(np.argmin(d))
        nk = n[k] if (centres[near] - x[k]) @ n[k] >= 0 else -n[k]
        xk = x[k] + 1e-4 * nk
        q = np.zeros(len(lanes))
        q[local] = shares(xk, nk, lanes[local], flags[local], dl.types[local])
        if not q.sum() > 0:
            continue
        q /= q.sum()
        p = pmf(tree, xk, nk)
        p_loc = p[local] / p[local].sum()
        ql = q[local]
        lit = ql > 0
        factor = float(np.sum(ql[lit] ** 2 / p_loc[lit]))
        top = int(np.argmax(ql))
        light = int(np.flatnonzero(local)[top])
        rows.append((float(d[near]), factor, float(ql[top]), float(p_loc[top]), light, xk, nk))
    dist = np.array([r[0] for r in rows])
    fac = np.array([r[1] for r in rows])
    for name, sel in (("all", np.ones(len(rows), bool)), (f"near ({a.near} m)", dist < a.near),
                      ("near 0.3 m", dist < 0.3)):
        f = fac[sel]
        if len(f):
            print(f"{name}: {len(f)} points, factor mean {f.mean():.3f} median {np.median(f):.3f} "
                  f"p90 {np.quantile(f, 0.9):.2f} max {f.max():.1f}")
    dom = np.array([r[2] for r in rows])
    pk = np.array([r[3] for r in rows])
    sel = (dist < a.near) & (dom > 0.5)
    if sel.any():
        print(f"near points with one light above half the share: {int(sel.sum())}, its share median "
              f"{np.median(dom[sel]):.3f}, its pick median {np.median(pk[sel]):.3f}, pick/share median "
              f"{np.median(pk[sel] / dom[sel]):.3f}")
    for k in np.argsort(-np.where(dist < a.near, fac, 0))[:a.show]:
        r = rows[k]
        print(f"  d {r[0]:.3f} factor {r[1]:.2f} light {r[4]} share {r[2]:.3f} pick {r[3]:.3f} "
              f"x {np.round(r[5], 3).tolist()} n {np.round(r[6], 3).tolist()}")


if __name__ == "__main__":
    main()
