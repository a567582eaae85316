"""The distant lights' pick against the light tree by importance at the shading point (lights/distant_pick.py,
opencl/lights/distant_pick.h): over a world, a sun and local lights of every type the pick's pmf sums to one over
every light at random points and normals, the device's equals the host's float64 mirror, the device's picks follow
the pdf that light_pick_pdf recomputes for the MIS weights (and report it themselves); a build whose recomputation
keeps the fixed shares of the light array (TEST_DISTANT_PICK_FIXED_PDF) fails that agreement. And the shares are
the fixed shares weighed by what reaches the point: a sun behind the surface, or lamps behind it, keep only the
floor."""

import numpy as np
from restircl import Camera, Light, Material, Mesh, Scene, look_at, scenes, translation
from restircl.environment.world import Environment
from restircl.lights.device_lights import scene_lights
from restircl.lights.environment import TYPE as ENVIRONMENT
from restircl.lights.sun import TYPE as SUN
from restircl.lights.tree import build_light_tree, pmf

from ..helpers import mixed_lights_scene
from ..stats import pooled_chi2
from .test_tree import DeviceTree


def _lights():
    scene = mixed_lights_scene()
    scene.environment = Environment("distant_pick_world", color=(0.3, 0.4, 0.5), strength=2.0)
    return scene_lights(scene, 0)


def _tree(dl):
    return build_light_tree(dl.records, dl.types, dl.power)


def _points(count: int, seed: int):
    rng = np.random.default_rng(seed)
    x = rng.uniform((-2.0, -2.0, -0.6), (2.0, 2.0, 2.5), (count, 3))
    n = rng.normal(size=(count, 3))
    return x, n / np.linalg.norm(n, axis=1, keepdims=True)


def test_the_pmf_sums_to_one_and_the_device_matches_the_host(device):
    dl = _lights()
    tree = _tree(dl)
    assert tree.distant_count == 2 and tree.leaves > 5
    dt = DeviceTree(device, tree)
    emits = dl.power > 0
    xs, ns = _points(24, 3)
    for x, n in zip(xs, ns, strict=True):
        host = pmf(tree, x, n)
        dev = dt.pmf(x, n)
        assert abs(host.sum() - 1.0) < 1e-9 and abs(dev.sum() - 1.0) < 1e-4, (x, n, host.sum(), dev.sum())
        assert np.all(dev[emits] > 0) and np.all(dev[~emits] == 0)
        np.testing.assert_allclose(dev, host, rtol=2e-3, atol=1e-12)


# points of _lamp_and_sun where the pick differs from the fixed shares: the sun behind the surface, the lamps behind
# it, the sun at 45 degrees, both behind
SLANTED = [((-0.5, 0.0, 0.3), (-0.8, 0.0, 0.6)), ((0.0, 0.0, 2.0), (0.7071, 0.0, 0.7071)), ((0.3, 0.2, 0.1), (0, 0, 1)),
           ((1.5, 0.0, 0.2), (-0.2, 0.0, -0.98))]


def test_the_picks_follow_the_recomputed_pdf(device):
    dl = _lamp_and_sun()
    tree = _tree(dl)
    dt = DeviceTree(device, tree)
    for x, n in SLANTED:
        np.testing.assert_allclose(dt.pmf(x, n), pmf(tree, np.array(x), np.array(n)), rtol=2e-3, atol=1e-12)
        counts, err = dt.picks(x, n)
        assert err < 1e-5, err  # the pdf the pick reports is the one light_pick_pdf recomputes
        stat, p, dof = pooled_chi2(counts, dt.pmf(x, n))
        assert dof >= 2 and p > 1e-4, (x, stat, p, dof)


def test_the_check_rejects_a_recomputation_with_the_fixed_shares(device):
    """The negative control: sampling by what reaches the point, MIS recomputing the fixed shares (the pick before
    this one)."""
    dl = _lamp_and_sun()
    tree = _tree(dl)
    dt = DeviceTree(device, tree, options=("-DTEST_DISTANT_PICK_FIXED_PDF=1",))
    for x, n in SLANTED:
        counts, err = dt.picks(x, n)
        _, p, _ = pooled_chi2(counts, dt.pmf(x, n))
        assert err > 1e-2 and p < 1e-6, (x, err, p)


def _lamp_and_sun():
    """A floor, two lamps of 50 W 0.8 m above it, a sun of strength 3 at 45 degrees and a grey world."""
    fv, ft = scenes.quad(4, 4)
    lamps = [Light(f"lamp{k}", "point", (1, 1, 1), 50.0, translation(k - 0.5, 0.0, 0.8), radius=0.05) for k in (0, 1)]
    sun = Light("sun", "sun", (1, 1, 1), 3.0, look_at((1.0, 0.0, 1.0), (0, 0, 0)), angle=0.05)
    cam = Camera(look_at((0, -3, 2), (0, 0, 0)), 16, 12)
    world = Environment("distant_pick_grey", color=(0.5, 0.5, 0.5), strength=1.0)
    scene = Scene([Mesh("floor", fv, ft, 0)], [Material("floor", (0.5, 0.5, 0.5))], [*lamps, sun], cam,
                  environment=world)
    return scene_lights(scene, 0)


def test_the_shares_follow_the_light_at_the_point():
    """Shares of the light array (here the power shares) weighed by what reaches the point, mixed with the floor of
    0.1 (written out here from the lights' powers): where the sun is behind the surface and a lamp in front of it
    the lamps and the world share 0.9 by their powers, the sun keeps 0.1 of its share among the distant lights; where
    the lamps are behind the surface and the sun faces it, the tree keeps 0.1 of its share."""
    dl = _lamp_and_sun()
    tree = _tree(dl)
    local = tree.light_info[:, 0] >= 0
    share = dl.power / dl.power.sum()
    world, sun = (int(np.flatnonzero(dl.types == t)[0]) for t in (ENVIRONMENT.code, SUN.code))
    lamps = share[local].sum()
    assert tree.distant_count == 2 and tree.leaves == 2 and 0.05 < lamps < 0.95 and share[sun] > 0.05
    towards = dl.records.view(np.float32).reshape(-1, 16)[sun, 4:7].astype(np.float64)
    away = np.array([-0.8, 0.0, 0.6])  # the sun 98 degrees from it, the lamp above the point 53 degrees
    assert towards @ away < -0.1
    p = pmf(tree, np.array([-0.5, 0.0, 0.3]), away)
    assert np.isclose(p[local].sum(), 0.9 * lamps / (lamps + share[world]) + 0.1 * lamps, rtol=1e-5)
    s, w = share[sun], share[world]
    p_distant = 0.9 * w / (lamps + w) + 0.1 * (s + w)
    assert np.isclose(p[sun], p_distant * 0.1 * s / (s + w), rtol=1e-5)
    p = pmf(tree, np.array([0.0, 0.0, 2.0]), towards)  # above the lamps
    assert np.isclose(p[local].sum(), 0.1 * lamps, rtol=1e-5)
    assert np.isclose(p[sun], (1 - 0.1 * lamps) * s / (s + w), rtol=1e-5)  # the sun's cosine is 1 here
