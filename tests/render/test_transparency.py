"""Transparent and alpha-masked surfaces (Material.alpha, opencl/bvh/transparent.h): camera rays and shadow rays
pass a surface of coverage a with probability 1 - a, so that a pixel seen through it converges to a times the
surface plus (1 - a) times what lies behind, and the light through it to (1 - a) times the light without it
(Cycles' transparent shadows); Light Paths > Transparent bounds the surfaces a ray passes; Film > Transparent's
alpha is the coverage.

The expected values are closed forms in renders of opaque scenes (the transparency code never runs there): a pane
of coverage a over a floor lit through it shows a P + (1 - a)^2 F, P the pane as an opaque surface and F the floor
without the pane."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Environment, Light, Material, Mesh, Renderer, Scene, Settings, look_at, translation
from restircl.eval.scenes.alpha_cards import card

from ..bias_controls import built_with

SAMPLES = 96


def pane_scene(alpha: float | None, world: bool = False) -> Scene:
    """A floor lit by a small area light 3 m above, seen straight down from 6 m; a 3 x 3 m pane of coverage `alpha`
    (None: no pane) 1 m above the floor covers the light from every floor point the camera sees. `world`: no floor,
    a grey world, and a 1 x 1 m pane in the middle of the view."""
    materials = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"),
                 Material("pane", (0.7, 0.3, 0.2), kind="diffuse", alpha=1.0 if alpha is None else alpha)]
    meshes = [] if world else [card("floor", (-3, -3, 0), (6, 0, 0), (0, 6, 0), 0)]
    if alpha is not None:
        size = 1.0 if world else 3.0
        meshes.append(card("pane", (-size / 2, -size / 2, 1.0), (size, 0, 0), (0, size, 0), 1))
    light = Light("lamp", "area", (1.0, 1.0, 1.0), 100.0, translation(0.0, 0.0, 3.0), shape="SQUARE", size=0.2)
    cam = Camera_down(6.0)
    env = Environment(color=(0.3, 0.3, 0.3), strength=1.0) if world else None
    return Scene(meshes, materials, [light], cam, name="pane", environment=env)


def Camera_down(height: float):  # noqa: N802 - reads as the scene's camera
    from restircl import Camera

    return Camera(look_at((0.0, -0.01, height), (0.0, 0.0, 0.0)), 16, 12, lens=80.0)


def _mean(scene: Scene, **kw) -> np.ndarray:
    r = Renderer(scene, Settings(method="ris", seed=5, **kw))
    return r.render_still(0, samples=SAMPLES).color[..., :3]


def test_a_pane_over_a_lit_floor_is_the_closed_form(device):
    a = 0.4
    seen = _mean(pane_scene(a)).mean()
    pane = _mean(pane_scene(1.0)).mean()
    floor = _mean(pane_scene(None)).mean()
    expected = a * pane + (1 - a) ** 2 * floor
    assert pane > 0.05 and floor > 0.05
    assert seen == pytest.approx(expected, rel=0.03)


def test_shadows_that_ignore_alpha_are_seen(device, monkeypatch):
    """The negative control: shadow rays stopped by the pane (TEST_OPAQUE_SHADOWS) miss the closed form."""
    a = 0.4
    pane = _mean(pane_scene(1.0)).mean()
    floor = _mean(pane_scene(None)).mean()
    built_with(monkeypatch, "TEST_OPAQUE_SHADOWS")
    seen = _mean(pane_scene(a)).mean()
    assert abs(seen / (a * pane + (1 - a) ** 2 * floor) - 1) > 0.2


def test_alpha_zero_and_one_are_no_pane_and_an_opaque_pane(device):
    clear, none = _mean(pane_scene(0.0)), _mean(pane_scene(None))
    assert clear.mean() == pytest.approx(none.mean(), rel=0.03)
    opaque = Renderer(pane_scene(1.0), Settings(method="ris", seed=5))
    assert "transparency" not in opaque.features  # coverage 1 everywhere compiles none of it
    assert "transparency" in Renderer(pane_scene(0.5), Settings(method="ris")).features


def test_film_alpha_is_the_coverage(device):
    """Seen through a pane of coverage 0.3 to the world, the film's alpha is 0.3; outside the pane 0."""
    f = Renderer(pane_scene(0.3, world=True), Settings(method="ris", seed=2)).render_still(0, samples=256)
    assert f.coverage is not None
    inside = f.coverage[4:8, 6:10]
    assert inside.mean() == pytest.approx(0.3, abs=0.02)  # 4096 Bernoulli samples: sd 0.007
    assert f.coverage[0, 0] == 0.0
    assert np.isfinite(f.color).all()


def _shadow_scene(cards: int, alpha: float) -> Scene:
    """A floor seen straight down where no card is over it, lit by a lamp whose light reaches that floor through
    `cards` stacked cards of coverage `alpha` (off to the side, 0.05 m apart)."""
    materials = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"),
                 Material("card", (0.2, 0.6, 0.2), kind="diffuse", alpha=alpha)]
    meshes = [card("floor", (-4, -3, 0), (8, 0, 0), (0, 6, 0), 0)]
    meshes += [card(f"card{k}", (-3, -2, 1.0 + 0.05 * k), (4, 0, 0), (0, 4, 0), 1) for k in range(cards)]
    light = Light("lamp", "area", (1.0, 1.0, 1.0), 100.0, translation(-3.0, 0.0, 3.0), shape="SQUARE", size=0.2)
    from restircl import Camera

    cam = Camera(look_at((1.5, -0.01, 4.0), (1.5, 0.0, 0.0)), 8, 6, lens=200.0)
    return Scene(meshes, materials, [light], cam, name="shadow_cards")


def _floor(cards: int, alpha: float, bound: int) -> float:
    r = Renderer(_shadow_scene(cards, alpha), Settings(method="ris", seed=1, transparent_max_bounces=bound))
    return float(r.render_still(0, samples=32).color[..., :3].mean())


def test_shadows_multiply_the_transparencies(device):
    open_floor = _floor(0, 1.0, 8)
    assert open_floor > 0.05
    assert _floor(2, 0.5, 8) == pytest.approx(0.25 * open_floor, rel=0.05)


def test_shadow_rays_pass_at_most_transparent_max_bounces_surfaces(device):
    open_floor = _floor(0, 1.0, 8)
    assert _floor(4, 0.0, 4) == pytest.approx(open_floor, rel=1e-4)  # four passes allowed
    assert _floor(4, 0.0, 3) == 0.0  # the fourth would be one too many: blocked


def _stack(cards: int, bound: int, world: bool = False) -> object:
    """`cards` fully transparent cards over a lit floor (or over the world alone), seen from above."""
    materials = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"),
                 Material("card", (0.2, 0.6, 0.2), kind="diffuse", alpha=0.0)]
    meshes = [] if world else [card("floor", (-3, -3, 0), (6, 0, 0), (0, 6, 0), 0)]
    verts = np.array([[x, y, 1.0 + 0.05 * k] for k in range(cards) for x, y in ((-2, -2), (2, -2), (2, 2), (-2, 2))])
    tris = np.array([[4 * k + i for i in t] for k in range(cards) for t in ((0, 1, 2), (0, 2, 3))])
    meshes.append(Mesh("cards", verts, tris, 1))
    light = Light("lamp", "area", (1.0, 1.0, 1.0), 100.0, translation(-3.5, 0.0, 3.0), shape="SQUARE", size=0.2)
    from restircl import Camera

    cam = Camera(look_at((0.0, -0.01, 5.0), (0.0, 0.0, 0.0)), 8, 6, lens=120.0)
    env = Environment(color=(0.3, 0.3, 0.3), strength=1.0) if world else None
    scene = Scene(meshes, materials, [light], cam, name="stack", environment=env)
    return Renderer(scene, Settings(method="ris", seed=1, transparent_max_bounces=bound)).render_still(0, samples=16)


def test_camera_rays_end_black_after_transparent_max_bounces(device):
    """Four fully transparent cards: with the bound at 8 the camera sees the floor lit (its shadow rays pass the
    four cards again: 4 + 4 <= 8); at 5 it sees the floor but the floor's shadow rays may pass only 5 - 4 = 1
    (Cycles counts the camera ray's passes off them): black, opaque; at 4 its ray, having passed four, ends at the
    floor, black and opaque (Cycles ends the path at the surface after the pass that reached the bound); a bound
    of 0 still lets one pass, as in Cycles: the world behind one card is seen."""
    assert _stack(4, 8).color[..., :3].mean() > 0.05
    unlit = _stack(4, 5)
    assert unlit.color[..., :3].max() == 0.0 and np.all(unlit.coverage == 1.0)
    ended = _stack(4, 4)
    assert ended.color[..., :3].max() == 0.0
    assert np.all(ended.coverage == 1.0)
    one = _stack(1, 0, world=True)
    assert np.all(one.coverage == 0.0) and one.color[..., :3].mean() > 0.1
    seen_world = _stack(4, 5, world=True)  # no floor: the world, alpha 0
    assert np.all(seen_world.coverage == 0.0) and seen_world.color[..., :3].mean() > 0.1


def test_a_thousand_stacked_cards_cost_a_bounded_time(device):
    """Every ray meets a thousand cards of coverage 0.5, but passes at most Transparent Max Bounces (8) of them:
    a frame costs a few times the frame of one card (3-4x measured at 32x24, load 18), far from a thousand."""
    import time

    from restircl.eval.scenes.alpha_cards import card_stack

    def seconds(cards: int) -> float:
        r = Renderer(card_stack(cards, 0.5, 32, 24, spacing=1e-3), Settings(method="ris"))
        r.render_still(0, samples=2)
        t0 = time.perf_counter()
        f = r.render_still(0, samples=32)
        assert np.isfinite(f.color).all()
        return time.perf_counter() - t0

    one, many = min(seconds(1) for _ in range(2)), min(seconds(1000) for _ in range(2))
    assert many < 40 * one, (many, one)


def test_the_primary_hit_is_the_first_surface_not_passed(device):
    """The G-buffer that ReSTIR, TAA and the motion vectors read holds the first surface a camera ray stops at: where
    the leaf image is cut out (alpha 0) the floor behind, exactly as without the leaves; where it is opaque, the
    leaf."""
    from restircl.eval.scenes.alpha_cards import alpha_cards

    def depth(scene) -> np.ndarray:
        return Renderer(scene, Settings(method="ris", jitter=False)).render_still(0, samples=1).depth

    with_leaves = alpha_cards(48, 36, pane_alpha=1.0)
    without = alpha_cards(48, 36, pane_alpha=1.0)
    without.meshes = [m for m in without.meshes if not m.name.startswith("leaf")]
    cards = alpha_cards(48, 36, pane_alpha=1.0)
    cards.materials[1].alpha = 1.0  # the leaves' quads, opaque
    d_leaves, d_plain, d_cards = depth(with_leaves), depth(without), depth(cards)
    on_card = d_cards < d_plain
    assert np.all((d_leaves >= d_cards) & (d_leaves <= d_plain))  # between the nearest quad and the floor
    cut_out = on_card & (d_leaves > d_cards)  # through the nearest quad's cut-out, to another leaf or the floor
    leaf = on_card & (d_leaves == d_cards)
    assert cut_out.sum() > 10 and leaf.sum() > 10, (cut_out.sum(), leaf.sum())
    assert np.all(d_leaves[~on_card] == d_plain[~on_card])
