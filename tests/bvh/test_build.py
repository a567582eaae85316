"""BVH build (python/restircl/bvh/build.py) and traversal (opencl/bvh/traverse.h) against a brute-force intersector."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pytest
from restircl import get_device
from restircl.bvh.build import build_bvh, device_vertices, make_tris
from restircl.bvh.packets import device_arrays, leaf_max
from restircl.core import layouts
from restircl.core.program import build_program

SOURCE = r"""
#include "types.h"
#include "bvh/traverse.h"

/* rays: o.xyz origin, o.w tmax; d.xyz direction */
__kernel void closest(const __global BVHNode* nodes, const __global Tri* tris, const __global float4* ro,
                      const __global float4* rd, __global float4* out, int n)
{
    int i = get_global_id(0);
    if (i >= n) return;
    Hit h = trace_closest(nodes, tris, ro[i].xyz, rd[i].xyz, ro[i].w);
    out[i] = (float4)(h.t, as_float(h.prim), h.u, h.v);
}

__kernel void any_hit(const __global BVHNode* nodes, const __global Tri* tris, const __global float4* ro,
                      const __global float4* rd, __global int* out, int n)
{
    int i = get_global_id(0);
    if (i >= n) return;
    out[i] = trace_any(nodes, tris, ro[i].xyz, rd[i].xyz, ro[i].w) ? 1 : 0;
}

/* Trace a camera ray; at its hit point p (computed as the renderer does, v0 + u e1 + v e2), leave the surface
 * with offset_ray_origin along the normal facing the camera and trace (a) a closest-hit ray in direction
 * bounce.xyz (the caller picks it in the hemisphere of that normal) and (b) a shadow ray to the point light.
 * out: x = primary prim, y = bounce prim, z = bounce t, w = shadow occluded (1/0). */
__kernel void surface(const __global BVHNode* nodes, const __global Tri* tris, const __global float4* ro,
                      const __global float4* rd, const __global float4* bounce, float4 light,
                      __global float4* out, __global float4* normal_out, int n)
{
    int i = get_global_id(0);
    if (i >= n) return;
    float3 d = rd[i].xyz;
    Hit h = trace_closest(nodes, tris, ro[i].xyz, d, ro[i].w);
    float4 res = (float4)(as_float(h.prim), as_float(-1), INFINITY, 0.0f);
    float3 ng = (float3)(0.0f);
    if (h.prim >= 0) {
        Tri t = tris[h.prim];
        float3 p = t.v0.xyz + h.u * t.e1.xyz + h.v * t.e2.xyz;
        ng = normalize(cross(t.e1.xyz, t.e2.xyz));
        if (dot(ng, d) > 0.0f) ng = -ng;
        float3 o = offset_ray_origin(p, ng);
        Hit b = trace_closest(nodes, tris, o, bounce[i].xyz, INFINITY);
        res.y = as_float(b.prim);
        res.z = b.t;
        float3 to_light = light.xyz - o;
        res.w = trace_any(nodes, tris, o, to_light, 0.9999f) ? 1.0f : 0.0f;
    }
    out[i] = res;
    normal_out[i] = (float4)(ng, 0.0f);
}

__kernel void offset(const __global float4* p, const __global float4* ng, __global float4* out, int n)
{
    int i = get_global_id(0);
    if (i >= n) return;
    out[i] = (float4)(offset_ray_origin(p[i].xyz, ng[i].xyz), 0.0f);
}
"""


# ---- helpers ---------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def dev():
    return get_device()


@pytest.fixture(scope="module")
def prog(dev):
    return build_program(dev, flags={}, source=SOURCE)


class Scene:
    """A BVH and Tri array on the device, for tracing batches of rays."""

    def __init__(self, dev, prog, v0, v1, v2):
        self.dev, self.prog = dev, prog
        self.v0, self.v1, self.v2 = (np.asarray(v, np.float64).reshape(-1, 3) for v in (v0, v1, v2))
        n = len(self.v0)
        self.bvh = build_bvh(self.v0, self.v1, self.v2)
        self.tris = make_tris(self.v0, self.v1, self.v2, np.zeros(n, np.int64), np.arange(n), self.bvh.order)
        mf = cl.mem_flags
        ctx = dev.context
        nodes, tris = device_arrays(self.bvh.nodes, self.tris)
        tris = tris if len(tris) else np.zeros(1, layouts.TRI)
        self.nodes_buf = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=nodes)
        self.tris_buf = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=tris)
        self.k_closest = cl.Kernel(prog, "closest")
        self.k_any = cl.Kernel(prog, "any_hit")

    def _rays(self, o, d, tmax):
        n = len(o)
        ro = np.zeros((max(n, 1), 4), np.float32)
        rd = np.zeros((max(n, 1), 4), np.float32)
        ro[:n, :3] = o
        ro[:n, 3] = tmax
        rd[:n, :3] = d
        mf = cl.mem_flags
        ctx = self.dev.context
        return (cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=ro),
                cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=rd))

    def closest(self, o, d, tmax=np.inf):
        """(t, prim as original triangle index or -1, u, v) per ray."""
        n = len(o)
        ro, rd = self._rays(o, d, tmax)
        out = np.zeros((max(n, 1), 4), np.float32)
        out_buf = cl.Buffer(self.dev.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
        self.k_closest(self.dev.queue, (max(n, 1),), None, self.nodes_buf, self.tris_buf, ro, rd, out_buf,
                       np.int32(n))
        cl.enqueue_copy(self.dev.queue, out, out_buf)
        out = out[:n]
        leaf_prim = layouts.float_bits_to_int(out[:, 1])
        prim = np.full(n, -1, np.int64)
        prim[leaf_prim >= 0] = self.bvh.order[leaf_prim[leaf_prim >= 0]]
        return out[:, 0].astype(np.float64), prim, out[:, 2], out[:, 3], leaf_prim

    def any(self, o, d, tmax=np.inf):
        n = len(o)
        ro, rd = self._rays(o, d, tmax)
        out = np.zeros(max(n, 1), np.int32)
        out_buf = cl.Buffer(self.dev.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
        self.k_any(self.dev.queue, (max(n, 1),), None, self.nodes_buf, self.tris_buf, ro, rd, out_buf,
                   np.int32(n))
        cl.enqueue_copy(self.dev.queue, out, out_buf)
        return out[:n].astype(bool)


def brute_force(v0, v1, v2, o, d, tmax=np.inf):
    """Closest hit of every ray with every triangle in float64 (Moeller-Trumbore on the float32 vertices the
    device uses). Returns (t, prim) with t = inf, prim = -1 for a miss, and the full (rays, tris) t matrix."""
    a, _, _, b, c = device_vertices(v0, v1, v2)
    a, b, c = (x.astype(np.float64) for x in (a, b, c))
    o = np.asarray(o, np.float32).astype(np.float64)
    d = np.asarray(d, np.float32).astype(np.float64)
    tmax = np.broadcast_to(np.asarray(tmax, np.float32).astype(np.float64), (len(o),))
    e1, e2 = b - a, c - a
    tall = np.full((len(o), len(a)), np.inf)
    for s in range(0, len(o), 256):
        oo, dd = o[s:s + 256, None, :], d[s:s + 256, None, :]
        p = np.cross(dd, e2[None])
        det = np.einsum("rtk,tk->rt", p, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tv = oo - a[None]
            u = np.einsum("rtk,rtk->rt", tv, p) * inv
            q = np.cross(tv, e1[None])
            v = np.einsum("rtk,rtk->rt", dd, q) * inv
            t = np.einsum("rtk,tk->rt", q, e2) * inv
            ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & (t < tmax[s:s + 256, None])
        tall[s:s + 256] = np.where(ok, t, np.inf)
    prim = np.argmin(tall, axis=1) if len(a) else np.zeros(len(o), np.int64)
    t = tall[np.arange(len(o)), prim] if len(a) else np.full(len(o), np.inf)
    prim = np.where(np.isfinite(t), prim, -1)
    return t, prim, tall


def random_soup(rng, n, spread=10.0, size=0.6):
    """Clustered triangles of mixed sizes."""
    centers = rng.normal(size=(max(1, n // 50), 3)) * spread
    c = centers[rng.integers(0, len(centers), n)] + rng.normal(size=(n, 3)) * spread * 0.15
    s = size * np.exp(rng.normal(size=(n, 1)) * 0.7)
    return c + rng.normal(size=(n, 3)) * s, c + rng.normal(size=(n, 3)) * s, c + rng.normal(size=(n, 3)) * s


def random_rays(rng, n, spread=10.0):
    o = rng.normal(size=(n, 3)) * spread * 1.5
    target = rng.normal(size=(n, 3)) * spread * 0.5
    d = target - o
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return o, d


def grid_mesh(nx, ny, size=1.0):
    """A flat grid in z = 0 of nx * ny quads, two triangles each; (v0, v1, v2)."""
    xs = np.linspace(-size, size, nx + 1)
    ys = np.linspace(-size, size, ny + 1)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    V = np.stack([X, Y, np.zeros_like(X)], -1)
    a, b, c, d = V[:-1, :-1], V[1:, :-1], V[1:, 1:], V[:-1, 1:]
    v0 = np.concatenate([a.reshape(-1, 3), a.reshape(-1, 3)])
    v1 = np.concatenate([b.reshape(-1, 3), c.reshape(-1, 3)])
    v2 = np.concatenate([c.reshape(-1, 3), d.reshape(-1, 3)])
    return v0, v1, v2


def sphere_mesh(n_theta=24, n_phi=48, radius=1.0, center=(0.0, 0.0, 0.0)):
    """A closed UV sphere (poles shared) with consistent winding; (vertices, triangles)."""
    th = np.linspace(0, np.pi, n_theta + 1)[1:-1]
    ph = np.linspace(0, 2 * np.pi, n_phi, endpoint=False)
    T, P = np.meshgrid(th, ph, indexing="ij")
    ring = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1).reshape(-1, 3)
    verts = np.concatenate([[[0, 0, 1]], ring, [[0, 0, -1]]]) * radius + np.asarray(center)
    tris = []
    idx = lambda i, j: 1 + i * n_phi + (j % n_phi)  # noqa: E731
    for j in range(n_phi):
        tris.append((0, idx(0, j), idx(0, j + 1)))
        tris.append((len(verts) - 1, idx(n_theta - 2, j + 1), idx(n_theta - 2, j)))
    for i in range(n_theta - 2):
        for j in range(n_phi):
            tris.append((idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)))
            tris.append((idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)))
    return verts, np.array(tris)


def check_structure(bvh, v0, v1, v2):
    """Every leaf box holds its triangles, every inner child's box holds its node's boxes, all triangles appear
    once, nodes are numbered depth first, and the stack the traversal needs fits."""
    nodes = bvh.nodes
    n = len(v0)
    assert sorted(bvh.order.tolist()) == list(range(n))
    a, _, _, b, c = device_vertices(v0, v1, v2)
    lo = np.minimum(np.minimum(a, b), c)[bvh.order]
    hi = np.maximum(np.maximum(a, b), c)[bvh.order]
    bmin = np.stack([nodes["minx"], nodes["miny"], nodes["minz"]], -1)  # node, slot, axis
    bmax = np.stack([nodes["maxx"], nodes["maxy"], nodes["maxz"]], -1)
    child, count = nodes["child"], nodes["count"]
    seen = np.zeros(n, int)
    stack = [(0, 0)]
    max_depth = 0
    next_dfs = 0
    while stack:
        ni, depth = stack.pop()
        next_dfs += 1
        max_depth = max(max_depth, depth)
        inner = []
        for k in range(4):
            ref, cnt = int(child[ni, k]), int(count[ni, k])
            if ref >= 0:
                assert cnt == 0 and ref > ni  # children after their parent (depth-first numbering)
                used = np.nonzero((child[ref] >= 0) | (count[ref] > 0))[0]
                assert len(used) >= 1
                assert np.all(bmin[ni, k] <= bmin[ref, used]) and np.all(bmax[ref, used] <= bmax[ni, k])
                inner.append((ref, depth + 1))
            elif cnt == 0:
                assert np.all(bmin[ni, k] == np.inf) and np.all(bmax[ni, k] == -np.inf)  # unused slot
            else:
                first = ~ref
                assert 0 < cnt <= leaf_max() and first + cnt <= n
                assert np.all(bmin[ni, k] <= lo[first:first + cnt]) and np.all(hi[first:first + cnt] <= bmax[ni, k])
                seen[first:first + cnt] += 1
        stack.extend(reversed(inner))
    assert next_dfs == len(nodes)
    assert np.all(seen == 1)
    assert 3 * max_depth < 96  # BVH_STACK_SIZE: at most 3 pushes per level
    return max_depth


def assert_same_hits(t, prim, t_ref, prim_ref, tall, o):
    """Same hit/miss, same t (1e-5 relative, or a few float32 steps of the origin's coordinates for hits very
    near the origin); the same triangle, or one the brute force hits at the same t."""
    hit = prim_ref >= 0
    assert np.array_equal(prim >= 0, hit), f"{np.sum((prim >= 0) != hit)} rays disagree on hit/miss"
    atol = 4e-7 * np.max(np.abs(o), axis=1)
    assert np.all(np.abs(t[hit] - t_ref[hit]) <= 1e-5 * t_ref[hit] + atol[hit])
    other = hit & (prim != prim_ref)
    if np.any(other):
        rows = np.nonzero(other)[0]
        assert np.all(np.abs(tall[rows, prim[rows]] - t_ref[rows]) <= 1e-5 * t_ref[rows] + atol[rows])
    assert np.sum(other) <= max(2, 0.002 * np.sum(hit))


# ---- build -------------------------------------------------------------------------------------------------


def test_build_structure_random():
    rng = np.random.default_rng(1)
    v0, v1, v2 = random_soup(rng, 5000)
    bvh = build_bvh(v0, v1, v2)
    check_structure(bvh, v0, v1, v2)
    assert bvh.nodes.dtype == layouts.BVH_NODE
    assert bvh.build_seconds > 0


def test_build_degenerate_inputs():
    # identical triangles (no plane separates their centroids), a line of needles, a huge spread of sizes
    tri = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    same = [np.repeat(tri[k][None], 100, 0) for k in range(3)]
    check_structure(build_bvh(*same), *same)
    x = np.geomspace(1e-3, 1e5, 300)[:, None]
    needles = (np.hstack([x, 0 * x, 0 * x]), np.hstack([x, 0 * x + 1e-3, 0 * x]), np.hstack([x * 1.001, 0 * x, 0 * x]))
    check_structure(build_bvh(*needles), *needles)
    for n in (0, 1, 2, 3, leaf_max() + 1):
        rng = np.random.default_rng(n)
        v = random_soup(rng, n) if n else (np.zeros((0, 3)),) * 3
        bvh = build_bvh(*v)
        assert len(bvh.nodes) >= 1 and len(bvh.order) == n
        check_structure(bvh, *v)


def test_build_rejects_nonfinite():
    v = np.zeros((2, 3))
    w = v.copy()
    w[1, 0] = np.nan
    with pytest.raises(ValueError):
        build_bvh(v, w, v + 1)


def test_make_tris_fields():
    rng = np.random.default_rng(2)
    v0, v1, v2 = random_soup(rng, 50)
    bvh = build_bvh(v0, v1, v2)
    mat = rng.integers(0, 7, 50)
    prim = rng.permutation(50)
    tris = make_tris(v0, v1, v2, mat, prim, bvh.order)
    assert tris.dtype == layouts.TRI and len(tris) == 50
    np.testing.assert_array_equal(layouts.float_bits_to_int(tris["v0"][:, 3]), mat[bvh.order])
    np.testing.assert_array_equal(layouts.float_bits_to_int(tris["e1"][:, 3]), prim[bvh.order])
    # v0 + e1 and v0 + e2 give back the float32 vertices to within one float32 step
    for e, v in (("e1", v1), ("e2", v2)):
        back = tris["v0"][:, :3] + tris[e][:, :3]
        want = v[bvh.order].astype(np.float32)
        step = np.spacing(np.maximum(np.abs(want), np.abs(tris["v0"][:, :3])))
        assert np.all(np.abs(back - want) <= step)


# ---- traversal ---------------------------------------------------------------------------------------------


def test_random_scene_matches_brute_force(dev, prog):
    rng = np.random.default_rng(3)
    v0, v1, v2 = random_soup(rng, 3000)
    sc = Scene(dev, prog, v0, v1, v2)
    o, d = random_rays(rng, 3000)
    t, prim, u, v, _ = sc.closest(o, d)
    t_ref, prim_ref, tall = brute_force(v0, v1, v2, o, d)
    assert np.mean(prim_ref >= 0) > 0.3
    assert_same_hits(t, prim, t_ref, prim_ref, tall, o)
    # barycentrics reproduce the hit point
    hit = prim >= 0
    a, e1, e2, _, _ = device_vertices(v0[prim[hit]], v1[prim[hit]], v2[prim[hit]])
    p = a + u[hit, None] * e1 + v[hit, None] * e2
    q = o[hit] + t[hit, None] * d[hit]
    np.testing.assert_allclose(p, q, atol=1e-3)
    # unnormalised directions: t scales
    t2, prim2, *_ = sc.closest(o, d * 3.0)
    np.testing.assert_array_equal(prim2 >= 0, hit)
    np.testing.assert_allclose(t2[hit] * 3.0, t[hit], rtol=1e-5)


def test_tmax_and_any_hit_agree_with_closest(dev, prog):
    rng = np.random.default_rng(4)
    v0, v1, v2 = random_soup(rng, 2000)
    sc = Scene(dev, prog, v0, v1, v2)
    o, d = random_rays(rng, 4000)
    tmax = rng.uniform(0.0, 40.0, len(o)).astype(np.float32)
    t, prim, *_ = sc.closest(o, d, tmax)
    t_ref, prim_ref, tall = brute_force(v0, v1, v2, o, d, tmax)
    assert 0.1 < np.mean(prim_ref >= 0) < 0.9
    assert_same_hits(t, prim, t_ref, prim_ref, tall, o)
    assert np.all(t[prim >= 0] < tmax[prim >= 0])
    occluded = sc.any(o, d, tmax)
    np.testing.assert_array_equal(occluded, prim >= 0)
    np.testing.assert_array_equal(sc.any(o, d), sc.closest(o, d)[1] >= 0)


def test_no_leaks_through_shared_edges_and_vertices(dev, prog):
    rng = np.random.default_rng(5)
    verts, tris = sphere_mesh(20, 40, radius=3.0, center=(0.3, -0.2, 0.1))
    v0, v1, v2 = (verts[tris[:, k]] for k in range(3))
    sc = Scene(dev, prog, v0, v1, v2)
    # points exactly on shared edges (random positions along them) and on vertices
    ea, eb = np.concatenate([tris[:, 0], tris[:, 1], tris[:, 2]]), np.concatenate([tris[:, 1], tris[:, 2], tris[:, 0]])
    s = rng.uniform(0, 1, (len(ea), 1))
    targets = np.concatenate([verts[ea] + s * (verts[eb] - verts[ea]), verts[ea] + 0.5 * (verts[eb] - verts[ea]),
                              verts])
    targets = targets.astype(np.float32).astype(np.float64)
    center = np.array([0.3, -0.2, 0.1])
    inner = center + rng.normal(size=targets.shape) * 0.3  # points inside the (convex) sphere
    for origin in ("outside", "inside"):
        if origin == "outside":
            # on the line from an inner point through the target, beyond it: the ray enters the sphere at the
            # target (a ray from a random outside point may touch a silhouette edge only, and legitimately miss)
            o = targets + (targets - inner) * rng.uniform(0.5, 3.0, (len(targets), 1))
        else:
            o = inner
        d = targets - o
        t, prim, *_ = sc.closest(o, d)
        assert np.all(prim >= 0), f"{origin}: {np.sum(prim < 0)} of {len(o)} rays leaked"
        assert np.all(sc.any(o, d, 2.0))
    # a flat grid, rays grazing it towards its inner edges and vertices
    g0, g1, g2 = grid_mesh(16, 16, size=2.0)
    sc = Scene(dev, prog, g0, g1, g2)
    xs = np.linspace(-2, 2, 17)[1:-1]
    X, Y = np.meshgrid(xs, np.linspace(-1.9, 1.9, 37), indexing="ij")
    on_edges = np.concatenate([np.stack([X.ravel(), Y.ravel()], 1), np.stack([Y.ravel(), X.ravel()], 1)])
    diag = rng.uniform(-1.9, 1.9, (2000, 1)) * np.array([[1.0, 1.0]])  # diagonal edges x == y (inside cells)
    pts = np.concatenate([on_edges, diag])
    pts3 = np.hstack([pts, np.zeros((len(pts), 1))])
    for elevation in (0.5, 1e-2, 1e-3):
        az = rng.uniform(0, 2 * np.pi, len(pts))
        dirs = np.stack([np.cos(az) * np.cos(elevation), np.sin(az) * np.cos(elevation),
                         -np.full(len(pts), np.sin(elevation))], 1)
        for sign in (1.0, -1.0):  # from above and from below
            dd = dirs * np.array([1.0, 1.0, sign])
            o = pts3 - dd * 1.5
            t, prim, *_ = sc.closest(o, dd)
            assert np.all(prim >= 0), f"elevation {elevation}: {np.sum(prim < 0)} rays leaked"


def test_axis_aligned_rays_on_box_boundaries(dev, prog):
    # Rays along an axis (two zero direction components) exactly through grid vertices and edges: the slab test
    # sees 0 * inf there, and the grid's boxes have faces on those coordinates. Every ray hits, also on the
    # grid's outer border (the edge test is inclusive).
    for offset in (np.zeros(3), np.array([1e5, -1e5, 3.0])):
        g = [x + offset for x in grid_mesh(8, 8, size=2.0)]
        sc = Scene(dev, prog, *g)
        xs = (np.linspace(-2, 2, 17) + offset[0]).astype(np.float32).astype(np.float64)
        ys = (np.linspace(-2, 2, 17) + offset[1]).astype(np.float32).astype(np.float64)
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        n = X.size
        for sign in (1.0, -1.0):
            o = np.stack([X.ravel(), Y.ravel(), np.full(n, offset[2] + 5.0 * sign)], 1)
            d = np.tile([0.0, 0.0, -sign], (n, 1))
            t, prim, *_ = sc.closest(o, d)
            assert np.all(prim >= 0), f"{np.sum(prim < 0)} of {n} axis-aligned rays missed"
            np.testing.assert_allclose(t, 5.0, rtol=1e-6)
            assert np.all(sc.any(o, d, 6.0))
            assert not np.any(sc.any(o, d, 4.0))


def test_offset_scene_no_self_intersection(dev, prog):
    rng = np.random.default_rng(6)
    offset = np.array([1e5, -1e5, 1e5])
    verts, tris = sphere_mesh(24, 48, radius=20.0)
    g0, g1, g2 = grid_mesh(32, 32, size=60.0)
    g = [x + np.array([0.0, 0.0, -30.0]) for x in (g0, g1, g2)]
    v0 = np.concatenate([verts[tris[:, 0]], g[0]]) + offset
    v1 = np.concatenate([verts[tris[:, 1]], g[1]]) + offset
    v2 = np.concatenate([verts[tris[:, 2]], g[2]]) + offset
    n_sphere = len(tris)
    sc = Scene(dev, prog, v0, v1, v2)
    n = 4096
    cam = offset + np.array([5.0, -70.0, 40.0])
    target = offset + np.hstack([rng.uniform(-40, 40, (n, 2)), np.full((n, 1), -30.0)])
    d = target - cam
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    o = np.repeat(cam[None], n, 0)
    # bounce directions: random, flipped later into the hemisphere of the facing normal
    bounce = rng.normal(size=(n, 3))
    bounce /= np.linalg.norm(bounce, axis=1, keepdims=True)
    light = offset + np.array([10.0, -30.0, 80.0])
    k_surface = cl.Kernel(prog, "surface")

    def run(b):
        mf = cl.mem_flags
        ctx = dev.context
        ro = np.zeros((n, 4), np.float32)
        ro[:, :3] = o
        ro[:, 3] = np.inf
        rd = np.zeros((n, 4), np.float32)
        rd[:, :3] = d
        bb = np.zeros((n, 4), np.float32)
        bb[:, :3] = b
        bufs = [cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=x) for x in (ro, rd, bb)]
        out = np.zeros((n, 4), np.float32)
        nrm = np.zeros((n, 4), np.float32)
        ob = cl.Buffer(ctx, mf.WRITE_ONLY, out.nbytes)
        nb = cl.Buffer(ctx, mf.WRITE_ONLY, nrm.nbytes)
        lt = np.array([*light, 0.0], np.float32)
        k_surface(dev.queue, (n,), None, sc.nodes_buf, sc.tris_buf, *bufs, lt, ob, nb, np.int32(n))
        cl.enqueue_copy(dev.queue, out, ob)
        cl.enqueue_copy(dev.queue, nrm, nb)
        return out, nrm[:, :3].astype(np.float64)

    out, ng = run(bounce)
    hit = layouts.float_bits_to_int(out[:, 0]) >= 0
    assert hit.mean() > 0.9
    bounce = np.where(np.sum(bounce * ng, 1, keepdims=True) < 0, -bounce, bounce)
    out, ng = run(bounce)
    prim0 = sc.bvh.order[np.maximum(layouts.float_bits_to_int(out[:, 0]), 0)]
    bprim = layouts.float_bits_to_int(out[:, 1])
    bprim = np.where(bprim >= 0, sc.bvh.order[np.maximum(bprim, 0)], -1)
    on_sphere = hit & (prim0 < n_sphere)
    on_ground = hit & (prim0 >= n_sphere)
    assert on_sphere.sum() > 200 and on_ground.sum() > 200
    # leaving a convex sphere outwards never hits it again; leaving the plane upwards never hits the plane
    assert not np.any(on_sphere & (bprim >= 0) & (bprim < n_sphere)), "self-intersection on the sphere"
    assert not np.any(on_ground & (bprim >= n_sphere)), "self-intersection on the ground"
    # shadow rays to the light: a sphere point facing the light sees it; one facing away does not
    prim_leaf = layouts.float_bits_to_int(out[:, 0])
    a, e1, e2, _, _ = device_vertices(v0, v1, v2)
    tl = sc.tris[np.maximum(prim_leaf, 0)]
    centroid = tl["v0"][:, :3] + (tl["e1"][:, :3] + tl["e2"][:, :3]) / 3.0
    to_light = light - centroid.astype(np.float64)
    facing = np.sum(to_light * ng, 1) / np.linalg.norm(to_light, axis=1)
    occluded = out[:, 3] > 0.5
    assert not np.any(on_sphere & (facing > 0.05) & occluded), "sphere points facing the light are shadowed"
    assert np.all(occluded[on_sphere & (facing < -0.5)])


def test_offset_ray_origin_scales_with_position(dev, prog):
    p = np.array([[0.0, 0, 0], [1e-3, 2, -3], [1e5, -1e5, 1e5], [-7.5, 1e4, 0.01]], np.float32)
    ng = np.array([[0, 0, 1], [0.6, 0.0, 0.8], [-1, 0, 0], [0.0, -0.6, 0.8]], np.float32)
    n = len(p)
    mf = cl.mem_flags
    pb = np.zeros((n, 4), np.float32)
    pb[:, :3] = p
    nb = np.zeros((n, 4), np.float32)
    nb[:, :3] = ng
    bufs = [cl.Buffer(dev.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=x) for x in (pb, nb)]
    out = np.zeros((n, 4), np.float32)
    ob = cl.Buffer(dev.context, mf.WRITE_ONLY, out.nbytes)
    prog.offset(dev.queue, (n,), None, *bufs, ob, np.int32(n))
    cl.enqueue_copy(dev.queue, out, ob)
    moved = out[:, :3].astype(np.float64) - p
    # moves to the normal's side, by more than the float spacing at p, by little relative to |p|
    assert np.all(np.sum(moved * ng, 1) > 0)
    assert np.all(np.abs(moved) <= 1e-3 * np.maximum(np.abs(p), 1e-2) + 1e-4)
    big = np.abs(ng) > 0.1
    assert np.all(np.abs(moved[big]) >= 4 * np.spacing(np.abs(p[big]).astype(np.float32)))


def test_empty_scene_and_one_triangle(dev, prog):
    z = np.zeros((0, 3))
    sc = Scene(dev, prog, z, z, z)
    o = np.array([[0.0, 0, -1], [0, 0, 0], [1, 2, 3]])
    d = np.array([[0.0, 0, 1], [1, 0, 0], [0, -1, 0]])
    t, prim, *_ = sc.closest(o, d)
    assert np.all(prim == -1) and np.all(np.isinf(t))
    assert not np.any(sc.any(o, d))
    tri = [np.array([[0.0, 0, 0]]), np.array([[1.0, 0, 0]]), np.array([[0.0, 1, 0]])]
    sc = Scene(dev, prog, *tri)
    o = np.array([[0.25, 0.25, -1], [0.25, 0.25, 1], [0.8, 0.8, -1], [0.25, 0.25, -1], [0, 0, -1], [1, 0, -1]])
    d = np.array([[0.0, 0, 1], [0, 0, -2], [0, 0, 1], [0, 0, -1], [0, 0, 1], [0, 0, 1]])
    t, prim, u, v, _ = sc.closest(o, d)
    np.testing.assert_array_equal(prim, [0, 0, -1, -1, 0, 0])  # corners hit (inclusive edges)
    np.testing.assert_allclose(t[:2], [1.0, 0.5])
    np.testing.assert_allclose(u[:2], [0.25, 0.25], atol=1e-6)
    np.testing.assert_allclose(v[:2], [0.25, 0.25], atol=1e-6)
    np.testing.assert_array_equal(sc.any(o, d), prim >= 0)
    np.testing.assert_array_equal(sc.any(o, d, 0.5), [False] * 6)  # tmax before the triangle


def test_nan_and_degenerate_rays_miss(dev, prog):
    rng = np.random.default_rng(7)
    sc = Scene(dev, prog, *random_soup(rng, 500, spread=2.0))
    nan, inf = np.nan, np.inf
    o = np.array([[0.0, 0, -20]] * 8 + [[nan, 0, -20], [inf, 0, 0]])
    d = np.array([[nan, 0, 1], [0, nan, nan], [inf, 0, 1], [0, 0, 0], [0, 0, 1], [0, 0, 1], [-inf, inf, 1],
                  [0, 0, 1], [0, 0, 1], [1, 0, 0]])
    tmax = np.array([inf, inf, inf, inf, nan, -1.0, inf, 0.0, inf, inf])
    t, prim, *_ = sc.closest(o, d, tmax)
    assert np.all(prim == -1) and np.all(np.isinf(t))
    assert not np.any(sc.any(o, d, tmax))
    # axis-aligned directions (zero components) still hit
    o = np.array([[0.0, 0, -20], [0, -20, 0], [-20, 0, 0]])
    d = np.array([[0.0, 0, 1], [0, 1, 0], [1, 0, 0]])
    t, prim, *_ = sc.closest(o, d)
    t_ref, prim_ref, tall = brute_force(sc.v0, sc.v1, sc.v2, o, d)
    assert_same_hits(t, prim, t_ref, prim_ref, tall, o)


def test_large_scene_matches_brute_force_on_sample(dev, prog):
    # deeper tree; brute force on a subset of rays
    rng = np.random.default_rng(8)
    v0, v1, v2 = random_soup(rng, 30000, spread=30.0, size=0.3)
    sc = Scene(dev, prog, v0, v1, v2)
    check_structure(sc.bvh, v0, v1, v2)
    o, d = random_rays(rng, 300, spread=30.0)
    t, prim, *_ = sc.closest(o, d)
    t_ref, prim_ref, tall = brute_force(v0, v1, v2, o, d)
    assert_same_hits(t, prim, t_ref, prim_ref, tall, o)
