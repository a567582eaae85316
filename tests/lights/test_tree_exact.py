"""The light tree's exact pick below small nodes (lights/tree_exact.py, opencl/lights/tree_exact.h): the leaves it
walks are those below the node, the device's pick and its light_pick_pdf agree with each other and with the host's
pmf (the picks follow it, a recomputation by the branches alone is rejected), and at a point 0.2 m from a light that
brings it most of its light the pick comes near that light's share of the point's light, for point, spot and area
lights. The pick is taken only near the node's box (NEAR): far from every small node the pmf is the branches' alone,
and at a point near one small node and far from the other both rules meet in one pmf, device and host alike."""


import numpy as np
import pytest
from restircl import Camera, Light, Material, Mesh, Scene, look_at, scenes, translation
from restircl.lights import tree as light_tree
from restircl.lights.device_lights import scene_lights
from restircl.lights.record import LUMINANCE
from restircl.lights.registry import type_with_code
from restircl.lights.tree import build_light_tree, pmf
from restircl.lights.tree_exact import EXACT, NEAR, exact_shares, near_nodes, subtree_leaf_nodes

from ..stats import pooled_chi2
from .test_tree import DeviceTree

LEVELS = (0.8, 1.6, 2.4)  # the lights' heights: a point 0.2 m below one has every light wholly above or below it


def _room(seed: int, count: int = 42) -> Scene:
    """`count` lights over a 10 x 5 m floor at the heights LEVELS, powers log-uniform over 0.5..200 W, in turn a point
    light (radius 0..5 cm), a spot pointing down (cone 1.2 rad) and a 0.3 m square area light facing down."""
    rng = np.random.default_rng(seed)
    lights = []
    for k in range(count):
        c = (*rng.uniform((-5, -2.5), (5, 2.5)), float(rng.choice(LEVELS)))
        power = float(np.exp(rng.uniform(np.log(0.5), np.log(200.0))))
        if k % 3 == 0:
            lights.append(Light(f"p{k}", "point", (1, 1, 1), power, translation(*c),
                                radius=float(rng.uniform(0, 0.05)), soft_falloff=False))
        elif k % 3 == 1:
            below = (c[0], c[1], c[2] - 1.0)
            lights.append(Light(f"s{k}", "spot", (1, 1, 1), power, look_at(c, below), spot_size=1.2, spot_blend=0.2))
        else:
            lights.append(Light(f"a{k}", "area", (1, 1, 1), power, translation(*c), shape="SQUARE", size=0.3))
    fv, ft = scenes.quad(10, 5)
    cam = Camera(look_at((0, -6, 2), (0, 0, 1)), 16, 12, lens=28.0)
    return Scene([Mesh("floor", fv, ft, 0)], [Material("floor", (0.7, 0.7, 0.7))], lights, cam, name="room")


def _points_below(lanes: np.ndarray, types: np.ndarray) -> np.ndarray:
    """0.2 m below each light's centre (a quad record's p is a corner, its spans a and b)."""
    centre = lanes[:, :3].copy()
    quad = types == 1
    centre[quad] += 0.5 * (lanes[quad, 4:7] + lanes[quad, 8:11])
    return centre - (0.0, 0.0, 0.2)


def _shares(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray, types: np.ndarray) -> np.ndarray:
    """Each light's share of the unshadowed direct light at x: its type's closed form x its radiance's luminance."""
    q = np.array([type_with_code(types[i]).analytic(x[None], n[None], lanes[i:i + 1], flags[i:i + 1])[0, 0]
                  for i in range(len(lanes))]) * (lanes[:, 12:15] @ LUMINANCE)
    return q / q.sum()


@pytest.mark.parametrize("leaves", [1, 2, 5, 13, 42, 100])
def test_subtree_leaf_nodes_are_the_leaves_below(leaves):
    def below(j):
        return [j] if j >= leaves - 1 else below(2 * j + 1) + below(2 * j + 2)

    for j in range(2 * leaves - 1):
        walked = subtree_leaf_nodes(j, leaves).tolist()
        assert sorted(walked) == sorted(below(j)) and len(set(walked)) == len(walked)


def test_exact_shares_sum_to_one_and_keep_the_floor():
    near, far = np.array([5.0, 0.0, 1e-3, 2.0]), np.array([1.0, 0.0, 1e-4, 3.0])
    phi = np.array([1.0, 2.0, 3.0, 4.0])
    p = exact_shares(near, far, phi)
    # (1 - 0.1) x the mean of the two importance shares + 0.1 x the power share, written out
    want = 0.9 * 0.5 * (near / near.sum() + far / far.sum()) + 0.1 * phi / phi.sum()
    np.testing.assert_allclose(p, want, rtol=1e-12)
    assert abs(p.sum() - 1) < 1e-12 and p[1] == pytest.approx(0.1 * 0.2)
    np.testing.assert_allclose(exact_shares(np.zeros(4), np.zeros(4), phi), phi / phi.sum())


def _room_tree(seed: int):
    dl = scene_lights(_room(seed), 0)
    return dl, build_light_tree(dl.records, dl.types, dl.power)


def test_the_room_has_branches_above_exact_nodes():
    """The room's 42 lights are more than EXACT: the descent branches at the root and picks exactly below."""
    _, tree = _room_tree(1)
    assert tree.leaves > EXACT >= tree.nodes["meta"][1, 3] and tree.nodes["meta"][0, 3] == tree.leaves


def test_device_pmf_and_picks_follow_the_host(device):
    dl, tree = _room_tree(2)
    dt = DeviceTree(device, tree)
    lanes = dl.records.view(np.float32).reshape(-1, 16).astype(np.float64)
    for x in _points_below(lanes, dl.types)[:6]:
        n = np.array([0.0, 0.0, 1.0])
        dev, host = dt.pmf(x, n), pmf(tree, x, n)
        assert abs(dev.sum() - 1) < 1e-4 and abs(host.sum() - 1) < 1e-9 and np.all(dev > 0)
        np.testing.assert_allclose(dev, host, rtol=2e-3, atol=1e-9)
        counts, err = dt.picks(x, n, items=1024, per_item=128)
        assert err < 1e-5, err
        stat, p, dof = pooled_chi2(counts, dev)
        assert dof >= 5 and p > 1e-4, (x, stat, p, dof)


def test_pdf_by_branches_alone_is_rejected(device):
    """Negative control: light_pick_pdf recomputed by the branches all the way down (TEST_TREE_EXACT_BRANCH_PDF, the
    rule before the exact pick) is not the pdf the pick draws with."""
    dl, tree = _room_tree(2)
    dt = DeviceTree(device, tree, options=("-DTEST_TREE_EXACT_BRANCH_PDF=1",))
    lanes = dl.records.view(np.float32).reshape(-1, 16).astype(np.float64)
    x, n = _points_below(lanes, dl.types)[0], np.array([0.0, 0.0, 1.0])
    counts, err = dt.picks(x, n, items=1024, per_item=128)
    assert err > 0.1, err
    assert pooled_chi2(counts, dt.pmf(x, n))[1] < 1e-6


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_point_beside_a_light_picks_it_by_its_share(device, seed):
    """At 0.2 m below each light of the room (a point under a lamp, a spot or an area light), wherever that light
    brings more than half the point's unshadowed light, the device picks it with more than 0.1 of its share and 0.6
    in the median, and the variance factor sum q^2 / p (q each light's share, 1 for a pick by share) is below 2.2
    on average. Host pmf, seeds 1 / 2 / 3: before the exact pick below small nodes pick / share down to 0.074 /
    0.022 / 0.073, median 0.41 / 0.37 / 0.38, factors 3.1 / 3.8 / 2.9 on average; with it 0.21 / 0.25 / 0.12, 0.76 /
    0.73 / 0.67, 1.50 / 1.59 / 1.85. The lowest are spots: the tree weighs a light by its power, and a spot's is its
    cone's, 10-30x less than that of a point light as bright along the spot's axis."""
    dl, tree = _room_tree(seed)
    dt = DeviceTree(device, tree)
    lanes = dl.records.view(np.float32).reshape(-1, 16).astype(np.float64)
    flags = dl.records.view(np.int32).reshape(-1, 16)[:, 15]
    n = np.array([0.0, 0.0, 1.0])
    factors, ratios = [], []
    for k, x in enumerate(_points_below(lanes, dl.types)):
        q = _shares(x, n, lanes, flags, dl.types)
        p = dt.pmf(x, n)
        lit = q > 0
        factors.append(float(np.sum(q[lit] ** 2 / p[lit])))
        if q[k] > 0.5:
            ratios.append((p[k] / q[k], int(dl.types[k])))
    assert len(ratios) >= 20 and {t for _, t in ratios} == {1, 3, 4}
    r = np.array([r for r, _ in ratios])
    assert r.min() > 0.1 and np.median(r) > 0.6, sorted(ratios)[:5]
    assert np.mean(factors) < 2.2, (np.mean(factors), max(factors))


def test_near_nodes_by_the_box_diagonal():
    """A unit cube (diagonal sqrt 3): a point 1 m from its face is within 1 x the diagonal (1 <= 3 in squares), 2 m
    is not (4 > 3), inside is near at any factor >= 0; at factor 0.5 (0.75 in squares) the point at 1 m is far."""
    lo, hi = np.zeros((1, 3)), np.ones((1, 3))
    at = {(2.0, 0.5, 0.5): (True, False), (3.0, 0.5, 0.5): (False, False), (0.5, 0.5, 0.5): (True, True),
          (1.6, 1.6, 0.5): (True, True)}  # the last 0.6 x sqrt 2 = 0.85 m from the edge: 0.72 <= 0.75
    for x, (at1, at_half) in at.items():
        assert near_nodes(lo, hi, np.array(x), 1.0)[0] == at1, x
        assert near_nodes(lo, hi, np.array(x), 0.5)[0] == at_half, x


def _small_nodes_near(tree, x) -> np.ndarray:
    """Whether each inner node of at most EXACT lights is near x (the nodes where the pick may stop)."""
    inner = np.arange(tree.leaves - 1)
    small = inner[tree.nodes["meta"][inner, 3] <= EXACT]
    return near_nodes(tree.nodes["lo"][small, :3], tree.nodes["hi"][small, :3], x, NEAR)


def test_a_point_far_from_small_nodes_branches(monkeypatch):
    """30 m above the 10 x 5 m room every small node is far: the pmf is that of the branches down to each leaf
    (the tree with EXACT = 0), while 0.2 m below a light it is not."""
    dl, tree = _room_tree(2)
    n = np.array([0.0, 0.0, -1.0])
    far_x = np.array([0.0, 0.0, 30.0])
    lanes = dl.records.view(np.float32).reshape(-1, 16).astype(np.float64)
    near_x = _points_below(lanes, dl.types)[0]
    assert not _small_nodes_near(tree, far_x).any() and _small_nodes_near(tree, near_x).any()
    adaptive_far, adaptive_near = pmf(tree, far_x, n), pmf(tree, near_x, -n)
    monkeypatch.setattr(light_tree, "EXACT", 0)
    np.testing.assert_allclose(adaptive_far, pmf(tree, far_x, n), rtol=1e-12)
    assert np.abs(adaptive_near - pmf(tree, near_x, -n)).max() > 1e-3


@pytest.mark.parametrize("x", [(0.0, 0.0, 30.0), (5.5, 0.0, 1.0)])
def test_device_follows_the_host_far_and_half_near(device, x):
    """Device pmf = host pmf and the picks follow it at a point far from every small node and at one beside the
    room, near one side's small nodes and far from the other's (both rules in one descent)."""
    dl, tree = _room_tree(2)
    x, n = np.array(x), _unit_towards(np.array(x), np.zeros(3))
    near = _small_nodes_near(tree, x)
    assert not near.any() if x[2] > 10 else (near.any() and not near.all())
    dt = DeviceTree(device, tree)
    dev, host = dt.pmf(x, n), pmf(tree, x, n)
    assert abs(dev.sum() - 1) < 1e-4 and np.all(dev > 0)
    np.testing.assert_allclose(dev, host, rtol=2e-3, atol=1e-9)
    counts, err = dt.picks(x, n, items=1024, per_item=128)
    assert err < 1e-5, err
    stat, p, dof = pooled_chi2(counts, dev)
    assert dof >= 5 and p > 1e-4, (x, stat, p, dof)


def _unit_towards(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    d = y - x
    return d / np.linalg.norm(d)


def test_device_exact_at_every_small_node_is_not_the_hosts(device):
    """Negative control: kernels built to pick exactly at every small node, near or not (TEST_LIGHT_TREE_NEAR
    1e15: no near test), give another pmf than the host's at the point 30 m above the room."""
    _, tree = _room_tree(2)
    x, n = np.array([0.0, 0.0, 30.0]), np.array([0.0, 0.0, -1.0])
    dt = DeviceTree(device, tree, options=("-DTEST_LIGHT_TREE_NEAR=1e15f",))
    assert np.abs(dt.pmf(x, n) - pmf(tree, x, n)).max() > 1e-3
