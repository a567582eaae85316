"""Agreement with Cycles 5.3 on Thin Wall (issue 39): eval/scenes/thin_wall.py's pane (one tinted quad, Principled
Transmission 1, IOR 1.5, Thin Wall on, standing turned to the view over a floor lit by an area light) at 48x36, smooth
and frosted (Roughness 0.35), the same Light Paths on both sides; the converged relMSE (each side's noise taken out
from two renders a side, test_blender_cycles_glass.converged_relmse) must be below 1e-2 and the image means agree
within Z standard errors. The negative control, the same quad rendered as before Thin Wall was modelled (a solid's
surface: the ray refracts in and never out), must fail the bound. Blender 5.3 only: older Principled BSDFs have no
Thin Wall (skipped there). Measured when written (128 spp a side, 2 renders): converged relMSE 0.0002 (smooth),
about 0 (frosted); the solid control 0.020 (smooth) and 0.015 (frosted). Slow cases: IOR 1.1 rough 0.3 (0.0023) and
smooth (about 0), Transmission 0.5 over the Principled's specular and diffuse (0.0003) and Roughness 0.6 (0.0003),
both Multiscatter GGX."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl import Renderer, Settings  # noqa: E402
from restircl.eval.cycles import bridge  # noqa: E402
from restircl.eval.scenes.thin_wall import thin_pane  # noqa: E402

from .test_blender_cycles_glass import PATHS, SEEDS, Z, converged_relmse  # noqa: E402
from .test_blender_support import needs_renderer  # noqa: E402
from .test_blender_thin_walled import principled_has_thin_wall  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

SPP = 128
BOUND = 1e-2


def _ours(sheet: dict, thin_wall: bool) -> list[np.ndarray]:
    return [Renderer(thin_pane(48, 36, thin_wall=thin_wall, **sheet), Settings(**{**PATHS.__dict__, "seed": s}))
            .render_still(0, SPP).color[..., :3].astype(np.float64) for s in SEEDS]


@pytest.mark.parametrize("sheet", [
    {"roughness": 0.0}, {"roughness": 0.35},
    pytest.param({"roughness": 0.3, "ior": 1.1}, marks=pytest.mark.slow),
    pytest.param({"roughness": 0.0, "ior": 1.1}, marks=pytest.mark.slow),
    pytest.param({"roughness": 0.3, "transmission": 0.5, "distribution": "multi_ggx"}, marks=pytest.mark.slow),
    pytest.param({"roughness": 0.6, "distribution": "multi_ggx"}, marks=pytest.mark.slow),
])
def test_thin_pane_agrees_with_cycles(sheet, record_property):
    if not principled_has_thin_wall():
        pytest.skip("this Blender's Principled BSDF has no Thin Wall input")
    sc = bridge.to_bpy(thin_pane(48, 36, **sheet))
    cyc = [bridge.render(sc, samples=SPP, seed=s, paths=PATHS).image[..., :3].astype(np.float64) for s in SEEDS]
    rel, raw, z = converged_relmse(_ours(sheet, True), cyc)
    msg = f"{sheet}: converged relMSE {rel:.4f} (with the noise {raw:.4f}), means {z:.1f} SE apart"
    record_property("agreement", msg)
    assert rel < BOUND and z < Z, msg
    if sheet == {"roughness": 0.0}:  # the negative control: the quad as a solid's surface
        solid, _, _ = converged_relmse(_ours(sheet, False), cyc)
        record_property("solid control", f"converged relMSE {solid:.4f}")
        assert solid > BOUND, solid
