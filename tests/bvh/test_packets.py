"""Leaf packets (python/restircl/bvh/packets.py, BVH_TRI4 in opencl/bvh/traverse.h): the packet layout, and hits bit
for bit those of the triangle-by-triangle leaf test on the same tree."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pytest
from restircl import get_device
from restircl.bvh import packets as bvh_packets
from restircl.bvh.build import build_bvh, make_tris
from restircl.core.program import build_program

from .test_build import SOURCE, random_rays, random_soup, sphere_mesh


@pytest.fixture(scope="module")
def dev():
    return get_device()


def _trace(dev, packets: bool, nodes, tris, o, d, tmax):
    saved = bvh_packets.ENABLED
    bvh_packets.ENABLED = packets
    try:
        prog = build_program(dev, source=SOURCE)
        nodes, tris = bvh_packets.device_arrays(nodes, tris)
    finally:
        bvh_packets.ENABLED = saved
    ctx, q = dev.context, dev.queue
    mf = cl.mem_flags
    n = len(o)
    ro = np.zeros((n, 4), np.float32)
    ro[:, :3], ro[:, 3] = o, tmax
    rd = np.zeros((n, 4), np.float32)
    rd[:, :3] = d
    bufs = [cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=a) for a in (nodes, tris, ro, rd)]
    out = np.zeros((n, 4), np.float32)
    occ = np.zeros(n, np.int32)
    b_out = cl.Buffer(ctx, mf.WRITE_ONLY, out.nbytes)
    b_occ = cl.Buffer(ctx, mf.WRITE_ONLY, occ.nbytes)
    cl.Kernel(prog, "closest")(q, (n,), None, *bufs, b_out, np.int32(n))
    cl.Kernel(prog, "any_hit")(q, (n,), None, *bufs, b_occ, np.int32(n))
    cl.enqueue_copy(q, out, b_out)
    cl.enqueue_copy(q, occ, b_occ)
    return out, occ


def test_packet_layout():
    rng = np.random.default_rng(3)
    v0, v1, v2 = random_soup(rng, 300)
    bvh = build_bvh(v0, v1, v2, leaf_max=3)
    tris = make_tris(v0, v1, v2, np.zeros(300, np.int64), np.arange(300), bvh.order)
    nodes, dev_tris = bvh_packets.with_packets(bvh.nodes, tris)
    assert np.array_equal(dev_tris[:300], tris)  # the shading's triangles stay where they were
    leaf = (bvh.nodes["child"] < 0) & (bvh.nodes["count"] > 0)
    assert len(dev_tris) == 300 + 3 * int(leaf.sum())
    first, cnt, rec = ~bvh.nodes["child"][leaf], bvh.nodes["count"][leaf], ~nodes["child"][leaf]
    assert np.array_equal(nodes["count"][leaf], first)
    assert np.array_equal(nodes["child"][~leaf], bvh.nodes["child"][~leaf])
    flat = dev_tris.view(np.float32).reshape(-1, 3, 4)  # Tri slot, field, component
    for f, c, r in zip(first, cnt, rec, strict=True):
        for s, field in enumerate(("v0", "e1", "e2")):
            lanes = flat[r + s, :3, :]  # axis, lane
            assert np.array_equal(lanes[:, :c].T, tris[field][f:f + c, :3])
            assert np.all(np.isnan(lanes[:, c:]))
    with pytest.raises(ValueError):
        bvh_packets.with_packets(build_bvh(v0, v1, v2, leaf_max=5).nodes, tris)


@pytest.mark.parametrize("leaf_max", [1, 2, 4])
def test_packets_give_the_same_hits_bit_for_bit(dev, leaf_max):
    """Soup and closed spheres (shared edges): t, triangle, u, v and occlusion of the packet traversal equal the
    one-triangle-at-a-time test's exactly, for unbounded and bounded rays."""
    rng = np.random.default_rng(11 + leaf_max)
    a = random_soup(rng, 2000)
    sv, st = sphere_mesh(12, 24, radius=2.0)
    b = tuple(sv[st[:, k]] for k in range(3))
    v0, v1, v2 = (np.concatenate([a[k], b[k]]) for k in range(3))
    n = len(v0)
    bvh = build_bvh(v0, v1, v2, leaf_max=leaf_max)
    tris = make_tris(v0, v1, v2, np.zeros(n, np.int64), np.arange(n), bvh.order)
    o, d = random_rays(rng, 20000)
    o[:5000] = rng.normal(0.0, 0.5, (5000, 3))  # from inside the sphere: every ray crosses its shared edges' mesh
    for tmax in (np.inf, 5.0):
        ref, ref_occ = _trace(dev, False, bvh.nodes, tris, o, d, tmax)
        got, got_occ = _trace(dev, True, bvh.nodes, tris, o, d, tmax)
        hit = ref[:, 1].view(np.int32) >= 0
        assert hit.mean() > 0.2 and ref_occ.mean() > 0.2
        assert np.array_equal(got.view(np.int32), ref.view(np.int32))
        assert np.array_equal(got_occ, ref_occ)
