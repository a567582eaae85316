"""Agreement with Cycles for light that bounces: the built-in cornell_box and a glossy scene (material_balls with
its area light alone, point lights removed: their sharp-lobe caustics converge too slowly for a test in either
renderer) with the same Light Paths on both sides (eval/cycles/bridge.py light_paths: 4 bounces, diffuse and glossy
4, no clamp, no threshold; Cycles' transparent limit lifted, Filter Glossy off). What is compared is the image mean
of the bounced light alone: each seed's 4-bounce image less its direct-light image (the same seed), over SEEDS seeds
per side, within Z standard errors of the difference of the two means (the seeds' spread gives each side's). The
renders' seeds are fixed, so the outcome is too. The bound has the power to see a difference of the size that
Cycles' transparent-bounce limit makes (it ends paths at lights): that variant must fail it.
Measured when written (cornell_box 32x32, 4 bounces, 8192 spp against 16384 frames): the bounced light agreed
within 0.1 %; Cycles with its transparent limit at 0 was 1.8 % darker."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl import Renderer, Settings, scenes  # noqa: E402
from restircl.eval.cycles import bridge  # noqa: E402

from .test_blender_support import needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

PATHS = Settings(method="ris", max_bounces=4, diffuse_bounces=4, glossy_bounces=4)
SEEDS = (1, 2, 3, 4, 5, 6)
Z = 4.0


def _glossy_area(w: int, h: int):
    sc = scenes.material_balls(w, h, area_light=True)
    sc.lights = [lt for lt in sc.lights if lt.type == "area"]
    return sc


def _bounced(pairs: list[tuple[np.ndarray, np.ndarray]]) -> tuple[float, float]:
    """Mean over seeds of the bounced light's image mean, and its standard error."""
    m = np.array([float((a[..., :3] - b[..., :3]).mean()) for a, b in pairs])
    return float(m.mean()), float(m.std(ddof=1) / math.sqrt(len(m)))


def _cycles(sc, spp: int, adjust=None) -> tuple[float, float]:
    return _bounced([(bridge.render(sc, samples=spp, seed=s, paths=PATHS, adjust=adjust).image,
                      bridge.render(sc, samples=spp, seed=s).image) for s in SEEDS])


def _ours(scene, frames: int) -> tuple[float, float]:
    return _bounced([(Renderer(scene, Settings(**{**PATHS.__dict__, "seed": s})).render_still(0, frames).color,
                      Renderer(scene, Settings(method="ris", seed=s)).render_still(0, frames).color)
                     for s in SEEDS])


def _check(name: str, ours: tuple[float, float], cyc: tuple[float, float]) -> tuple[bool, str]:
    (o, o_se), (c, c_se) = ours, cyc
    bound = Z * math.hypot(o_se, c_se)
    return abs(o - c) < bound, f"{name}: bounced light ours {o:.5f}, Cycles {c:.5f}, bound {bound:.5f}"


def test_bounced_light_agrees_with_cycles_in_the_cornell_box(record_property):
    scene = scenes.cornell_box(24, 24)
    sc = bridge.to_bpy(scene)
    ours = _ours(scene, 512)
    ok, msg = _check("cornell_box", ours, _cycles(sc, 256))
    record_property("agreement", msg)
    assert ok, msg
    # the bound's power: Cycles ending paths at the light (its transparent limit at 0) is told apart
    limited = _cycles(sc, 256, adjust=lambda c: setattr(c.cycles, "transparent_max_bounces", 0))
    ok_limited, msg_limited = _check("cornell_box, Cycles' transparent limit 0", ours, limited)
    assert not ok_limited, msg_limited


@pytest.mark.slow
def test_bounced_light_agrees_with_cycles_on_glossy_spheres(record_property):
    scene = _glossy_area(48, 27)
    ok, msg = _check("glossy_area", _ours(scene, 512), _cycles(bridge.to_bpy(scene), 256))
    record_property("agreement", msg)
    assert ok, msg
