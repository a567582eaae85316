"""The light tree's importance of four nodes at once (opencl/lights/tree_importance4.h, which the exact pick below
small nodes sums with) gives each lane the scalar light_tree_importance's value: for every run of four nodes of the
trees of point, spot, area and two-sided emissive-triangle lights, at points outside and inside the nodes' boxes,
behind the lights and in front, with a surface's normal n and a transmitting surface's 2 n."""

import numpy as np
import pyopencl as cl
import pytest
from restircl.core.program import build_program
from restircl.eval.scenes.validation import interior
from restircl.lights.device_lights import scene_lights
from restircl.lights.tree import NODE_TWO_SIDED, build_light_tree
from restircl.render.features import general_flags

from .test_tree import many_lights, mixed_lights
from .test_tree_exact import _room_tree

SRC = """
#include "types.h"
#include "numerics.h"
#include "sampling/rng.h"
#include "lights/lights.h"
#include "lights/array.h"
#include "lights/tree.h"
__kernel void importances(const __global LightTreeNode* nodes, int count, const __global float4* xs,
                          const __global float4* ns, __global float4* out)
{
    int m = get_global_id(0), p = get_global_id(1);
    if (m + 3 >= count) return;
    float3 x = xs[p].xyz, n = ns[p].xyz;
    float4 near, far;
    light_tree_importance4(&nodes[m], x, n, &near, &far);
    float2 s = light_tree_importance(&nodes[m + (m & 3)], x, n);  /* lane m & 3 against its scalar value */
    float v[4] = {near.s0, near.s1, near.s2, near.s3}, w[4] = {far.s0, far.s1, far.s2, far.s3};
    out[(size_t)p * count + m] = (float4)(v[m & 3], w[m & 3], s.x, s.y);
}
"""


def _trees():
    yield "mixed", mixed_lights()
    yield "many", many_lights()
    yield "room", _room_tree(2)[0]
    yield "interior", scene_lights(interior(16, 12), 0)


def _points(tree, rng, count=48):
    """Points around the lights' boxes (a third of them at node centres: inside the boxes), random unit normals,
    every second one doubled (a transmitting surface: light_pick_normal's 2 n)."""
    lo, hi = tree.nodes["lo"][:, :3].astype(np.float64), tree.nodes["hi"][:, :3].astype(np.float64)
    span = hi[0] - lo[0]
    x = rng.uniform(lo[0] - 0.3 * span, hi[0] + 0.3 * span, (count, 3))
    centres = 0.5 * (lo + hi)
    x[: count // 3] = centres[rng.integers(0, len(centres), count // 3)]
    n = rng.normal(size=(count, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    n[1::2] *= 2.0
    return x, n


@pytest.mark.parametrize("which", ["mixed", "many", "room", "interior"])
def test_four_lanes_are_the_scalar_importance(device, which):
    dl = dict(_trees())[which]
    tree = build_light_tree(dl.records, dl.types, dl.power)
    if which == "interior":  # the lamp shade's triangles: leaves that emit on both sides
        assert (tree.nodes["meta"][:, 1] & NODE_TWO_SIDED).any()
    x, n = _points(tree, np.random.default_rng(3))
    prog = build_program(device, general_flags(), source=SRC)
    ctx, q, mf = device.context, device.queue, cl.mem_flags
    f4 = lambda a: np.ascontiguousarray(np.c_[a, np.zeros(len(a))].astype(np.float32))  # noqa: E731
    count = len(tree.nodes)
    bufs = [cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=a) for a in (tree.nodes, f4(x), f4(n))]
    out = cl.Buffer(ctx, mf.WRITE_ONLY, 16 * count * len(x))
    cl.Kernel(prog, "importances")(q, (count, len(x)), None, bufs[0], np.int32(count), bufs[1], bufs[2], out)
    res = np.zeros((len(x), count, 4), np.float32)
    cl.enqueue_copy(q, res, out)
    res = res[:, : count - 3]
    vec, scalar = res[..., :2], res[..., 2:]
    # the cases are all there: zero (behind), positive, and the floor's 1e12-scale values inside a box
    assert (scalar == 0).any() and (scalar > 0).any() and (scalar[..., 0] > 1e10).any()
    np.testing.assert_allclose(vec, scalar, rtol=1e-6, atol=0)
