"""The light tree (lights/tree.py, lights/tree.h): its bounds hold every light, its device pick follows the pmf that
light_pick_pdf evaluates for a given light (chi-square at fixed shading points), that pmf sums to one over the
lights and agrees with the host's float64 reference, and every emitting light keeps a nonzero probability at every
point, behind surfaces too (the power floor)."""

import time

import numpy as np
import pyopencl as cl
import pytest
from restircl import scenes
from restircl.core.program import build_program
from restircl.lights.device_lights import scene_lights
from restircl.lights.tree import build_light_tree, light_bounds, merge_cones, path_tree, pmf
from restircl.render.features import general_flags

from ..helpers import mixed_lights_scene
from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "numerics.h"
#include "sampling/rng.h"
#include "lights/lights.h"
#include "lights/array.h"
#include "lights/tree.h"
__kernel void tree_picks(const __global LightTreeNode* nodes, const __global int2* info,
                         const __global int8* distant, SamplerParams sp, float4 x, float4 n, int per_item,
                         volatile __global int* counts, __global float* pdf_err)
{
    int i = get_global_id(0);
    LightPick lp = light_pick_source(0, 0, nodes, info, distant, sp);
    uint rng = rng_seed((uint)i, 0u, 23u, 0u);
    float worst = 0.0f;
    for (int k = 0; k < per_item; ++k) {
        uint bits = rng_next_uint(&rng);
        int light;
        float p;
        light_pick_lights(&lp, x.xyz, n.xyz, &bits, 1, 0, &light, &p);
        atomic_inc(&counts[light]);
        float q = light_pick_pdf(&lp, light, x.xyz, n.xyz);
        worst = fmax(worst, fabs(p - q) / q);
    }
    pdf_err[i] = worst;
}
__kernel void tree_pmf(const __global LightTreeNode* nodes, const __global int2* info,
                       const __global int8* distant, SamplerParams sp, float4 x, float4 n, __global float* out)
{
    int l = get_global_id(0);
    LightPick lp = light_pick_source(0, 0, nodes, info, distant, sp);
    out[l] = light_pick_pdf(&lp, l, x.xyz, n.xyz);
}
"""


def _sampler(tree):
    from restircl.core import layouts as L

    return L.pack(L.SAMPLER_PARAMS, light_tree=1, tree_leaves=tree.leaves, tree_distant=tree.distant_count,
                  tree_p_local=tree.p_local)


class DeviceTree:
    def __init__(self, device, tree, options: tuple[str, ...] = ()):
        self.device, self.tree = device, tree
        self.prog = build_program(device, general_flags(), source=SRC, extra_options=options)
        mf, ctx = cl.mem_flags, device.context

        def buf(a):
            a = np.ascontiguousarray(a)
            return cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=a if a.nbytes else np.zeros(16, np.uint8))

        self.bufs = (buf(tree.nodes), buf(tree.light_info), buf(tree.distant))
        self.n = len(tree.light_info)

    def pmf(self, x, n) -> np.ndarray:
        q = self.device.queue
        out = cl.Buffer(self.device.context, cl.mem_flags.WRITE_ONLY, 4 * self.n)
        cl.Kernel(self.prog, "tree_pmf")(q, (self.n,), None, *self.bufs, _sampler(self.tree), _f4(x), _f4(n), out)
        res = np.zeros(self.n, np.float32)
        cl.enqueue_copy(q, res, out)
        return res.astype(np.float64)

    def picks(self, x, n, items=2048, per_item=128) -> tuple[np.ndarray, float]:
        q, ctx = self.device.queue, self.device.context
        counts = np.zeros(self.n, np.int32)
        cb = cl.Buffer(ctx, cl.mem_flags.READ_WRITE | cl.mem_flags.COPY_HOST_PTR, hostbuf=counts)
        err = cl.Buffer(ctx, cl.mem_flags.WRITE_ONLY, 4 * items)
        cl.Kernel(self.prog, "tree_picks")(q, (items,), None, *self.bufs, _sampler(self.tree), _f4(x), _f4(n),
                                           np.int32(per_item), cb, err)
        e = np.zeros(items, np.float32)
        cl.enqueue_copy(q, counts, cb)
        cl.enqueue_copy(q, e, err)
        return counts, float(e.max())


def _f4(v):
    return np.array([*v, 0.0], np.float32)


def _unit(v):
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v)


def mixed_lights():
    s = mixed_lights_scene()
    return scene_lights(s, 0)


def many_lights():
    return scene_lights(scenes.many_lights(width=16, height=12, frames=1, lamps=60, point_lights=40, objects=4), 0)


# shading points: on the floor looking up, on a wall, below the floor looking down (every light behind it), and one
# inside a light's bounds
POINTS = [((0.1, 0.2, 0.0), (0, 0, 1)), ((0.0, 1.5, 1.0), (0, -1, 0)), ((0.3, -0.4, -1.0), (0, 0, -1)),
          ((-1.2, -1.2, 0.03), _unit((0.3, 0.1, 1)))]


@pytest.mark.parametrize("which", ["mixed", "many"])
def test_bounds_hold_every_light(which):
    dl = mixed_lights() if which == "mixed" else many_lights()
    tree = build_light_tree(dl.records, dl.types, dl.power)
    b = light_bounds(dl.records, dl.types, dl.power)
    nodes = tree.nodes
    assert tree.leaves == int(b.local.sum())
    # every ancestor of a leaf holds its box, its power and its normal cone
    for light in np.flatnonzero(b.local):
        j = int(tree.light_info[light, 0])
        assert nodes["meta"][j, 0] == light
        while True:
            assert np.all(nodes["lo"][j, :3] <= b.lo[light] + 1e-5) and np.all(nodes["hi"][j, :3] >= b.hi[light] - 1e-5)
            cos_o = nodes["hi"][j, 3]
            ang = np.arccos(np.clip(np.dot(nodes["axis"][j, :3], b.axis[light]), -1, 1))
            assert cos_o <= -0.999 or ang + b.theta_o[light] <= np.arccos(np.clip(cos_o, -1, 1)) + 2e-3  # float32 lanes
            if j == 0:
                break
            j = (j - 1) // 2
    assert np.isclose(nodes["lo"][0, 3], b.phi[b.local].sum(), rtol=1e-5)


def test_merge_cones_contains_both():
    rng = np.random.default_rng(4)
    wa, wb = (_unit_rows(rng.normal(size=(500, 3))) for _ in range(2))
    ta, tb = rng.uniform(0, 1.5, 500), rng.uniform(0, 1.5, 500)
    w, t = merge_cones(wa, ta, wb, tb)
    for w0, t0 in ((wa, ta), (wb, tb)):
        ang = np.arccos(np.clip(np.einsum("ij,ij->i", w, w0), -1, 1))
        assert np.all((t >= np.pi - 1e-9) | (ang + t0 <= t + 1e-6))


def _unit_rows(v):
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.mark.parametrize("which", ["mixed", "many"])
def test_pmf_sums_to_one_and_matches_the_host(device, which):
    dl = mixed_lights() if which == "mixed" else many_lights()
    tree = build_light_tree(dl.records, dl.types, dl.power)
    dt = DeviceTree(device, tree)
    emits = dl.power > 0
    for x, n in POINTS:
        dev = dt.pmf(x, n)
        host = pmf(tree, np.array(x, float), _unit(n))
        assert abs(dev.sum() - 1.0) < 1e-4 and abs(host.sum() - 1.0) < 1e-9
        assert np.all(dev[emits] > 0) and np.all(dev[~emits] == 0)
        np.testing.assert_allclose(dev, host, rtol=2e-3, atol=1e-12)


@pytest.mark.parametrize("which", ["mixed", "many"])
def test_picks_follow_the_pmf(device, which):
    dl = mixed_lights() if which == "mixed" else many_lights()
    tree = build_light_tree(dl.records, dl.types, dl.power)
    dt = DeviceTree(device, tree)
    dofs = []
    for x, n in POINTS:
        counts, err = dt.picks(x, n)
        # the pick's own pdf is the evaluated one (the same arithmetic, up to float rounding)
        assert err < 1e-5, err
        stat, p, dof = pooled_chi2(counts, dt.pmf(x, n))
        assert dof >= 3 and p > 1e-4, (x, stat, p, dof)
        dofs.append(dof)
    # at the point below the floor two lights hold all but 3e-4 of the pmf (4 pooled bins); every other point keeps
    # the test's power with 5 or more
    assert sum(d < 5 for d in dofs) <= 1, dofs


def test_the_tree_prefers_near_lights(device):
    """Not the proof of anything, a sanity check of the bound: at a point next to a weak lamp of many_lights the
    tree gives it more probability than its power share."""
    dl = many_lights()
    tree = build_light_tree(dl.records, dl.types, dl.power)
    b = light_bounds(dl.records, dl.types, dl.power)
    centre = 0.5 * (b.lo + b.hi)
    share = dl.power / dl.power.sum()
    weak = int(np.argmin(np.where(b.local & (centre[:, 2] > 0.5), share, np.inf)))
    x = centre[weak] - (0, 0, 0.3)
    p = DeviceTree(device, tree).pmf(x, (0, 0, 1))
    assert p[weak] > 10 * share[weak], (p[weak], share[weak])


def test_million_lights_build():
    """1e6 point lights of powers 1e-6..1e6: the build is vectorised (its time is printed, the figure is in
    docs/measurements/benchmarks.md) and its root holds them all."""
    rng = np.random.default_rng(5)
    n = 1_000_000
    rec = np.zeros((n, 16), np.float32)
    rec[:, 0:3] = rng.uniform(-100, 100, (n, 3))
    rec[:, 3] = np.int32(3).view(np.float32)
    rec[:, 12:15] = 1.0
    power = np.exp(rng.uniform(np.log(1e-6), np.log(1e6), n))
    from restircl.core import layouts as L

    records = np.zeros(n, L.LIGHT)
    records.view(np.float32).reshape(-1, 16)[:] = rec
    t0 = time.perf_counter()
    tree = build_light_tree(records, np.full(n, 3), power)
    seconds = time.perf_counter() - t0
    print(f"light tree build, 1e6 point lights: {seconds:.2f} s")
    assert tree.leaves == n and len(tree.nodes) == 2 * n - 1
    assert np.isclose(tree.nodes["lo"][0, 3], power.sum(), rtol=1e-4)
    assert np.all(tree.light_info[:, 0] >= n - 1)


def test_proposal_setting_flags_and_tiles(device):
    """The tree is compiled in and used only where light_proposal asks for it (auto keeps the array: measured,
    docs/measurements/benchmarks.md); with the tree, presampled light tiles are off (a tile has no shading point); the
    specialised build gives the general build's image bit for bit."""
    from restircl import Renderer, Settings

    scene = mixed_lights_scene(16, 12)
    default = Renderer(scene, Settings(method="ris"), device)
    assert not default.uses_light_tree and not default.flags["HAS_LIGHT_TREE"]
    assert default.device_scene.light_tree is None
    tree = Renderer(scene, Settings(method="ris", light_proposal="tree", light_tiles="on", seed=2), device)
    assert tree.uses_light_tree and tree.flags["HAS_LIGHT_TREE"] and not tree.will_use_light_tiles()
    a = tree.render_frame(0, still=True).noisy
    assert not tree.light_tiles_used
    general = Renderer(scene, Settings(method="ris", light_proposal="tree", light_tiles="on", seed=2,
                                       specialise=False), device)
    np.testing.assert_array_equal(general.render_frame(0, still=True).noisy, a)
    assert not Renderer(scene, Settings(method="light_array", light_proposal="tree"), device).uses_light_tree


def test_path_light_pick_chooses_the_tree_for_path_vertices():
    """Settings.path_light_pick: array never, tree and auto wherever there are two lights or more (a tree over one
    light picks it); with one light neither."""
    two, one = np.array([0, 3]), np.array([3])
    assert not path_tree("array", False, two) and not path_tree("array", True, two)
    assert path_tree("tree", False, two) and path_tree("auto", False, two) and path_tree("auto", True, two)
    assert not path_tree("tree", False, one) and not path_tree("auto", True, one)


def test_path_tree_leaves_the_direct_light_alone(device):
    """Bounces build the tree for the path's NEE only: the still's direct light keeps its per-pixel table, and Max
    Bounces 0 builds no tree (its images stay those of before)."""
    from restircl import Renderer, Settings
    from restircl.render.still_method import still_settings

    scene = mixed_lights_scene(16, 12)
    direct = Renderer(scene, still_settings(Settings(method="ris").validate(), scene), device)
    assert not direct.path_light_tree and not direct.flags["HAS_LIGHT_TREE"]
    assert direct.device_scene.light_tree is None
    paths = Renderer(scene, still_settings(Settings(method="ris", max_bounces=2).validate(), scene), device)
    assert paths.path_light_tree and not paths.uses_light_tree and paths.flags["HAS_LIGHT_TREE"]
    assert paths.device_scene.light_tree is not None
    assert direct.flags["HAS_PICK_TABLE"] == paths.flags["HAS_PICK_TABLE"]
    array = Renderer(scene, Settings(method="ris", max_bounces=2, path_light_pick="array").validate(), device)
    assert not array.path_light_tree and array.device_scene.light_tree is None
