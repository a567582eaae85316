"""ReSTIR GI in animation frames of scenes with glass (render/plan.py path_plan, PathParams / GIShadeParams
split_glass): ReSTIR GI reconnects at the first bounce as a reflection, so a sample refracted at the visible point is
none it can reuse; the path pass runs beside it and shades the pixels whose first surface transmits, ReSTIR GI the
rest. On eval/scenes/glass.py's table (a smooth and a rough glass sphere, a glass pane; 8 bounces): each pixel of a
split frame is, to the bit, the frame of the estimator that shades it alone (the path pass alone at the pixels that
transmit, ReSTIR GI everywhere at the rest: the same random streams), so the glass pixels keep the path pass's
unbiased light and the rest ReSTIR GI's lower noise. Negative control:
ReSTIR GI everywhere loses the light refracted at the glass pixels (their bounced light at a fraction of the path
pass's). Measured in tools/experiments/restir_gi_glass.py (48x36, 16 frames after 8, against a 512-spp still):
glass pixels at x0.18 of the reference's brightness with ReSTIR GI everywhere, x0.95-0.98 with the path pass; the
rest's one-frame relMSE 0.097 split vs 1.17 with the path pass alone."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.eval.scenes.glass import glass_table
from restircl.render import plan

B = 8
FRAMES = 5


def _frames(variant: str, monkeypatch: pytest.MonkeyPatch) -> list:
    with monkeypatch.context() as m:
        if variant == "gi":  # the plan told the scene does not refract: ReSTIR GI at every pixel
            real = plan.path_plan
            m.setattr(plan, "path_plan", lambda s, x, h: real(s, dataclasses.replace(x, transmission=False), h))
        r = Renderer(glass_table(32, 24), Settings(method="restir", max_bounces=B, diffuse_bounces=B, glossy_bounces=B,
                                                   transmission_bounces=B, light_passes=True, seed=5,
                                                   gi_reuse=variant != "paths"))
        out = [r.render_frame(0) for _ in range(FRAMES)]
        p = r.last_plan
        assert p is not None and (p.gi, p.paths) == {"paths": (False, True), "gi": (True, False),
                                                     "split": (True, True)}[variant]
    return out


@pytest.fixture(scope="module")
def runs(device):
    with pytest.MonkeyPatch.context() as mp:
        return {v: _frames(v, mp) for v in ("paths", "gi", "split")}


def test_split_frames_are_the_path_pass_at_glass_and_restir_gi_elsewhere(runs):
    for k, f in enumerate(runs["split"]):
        glass = f.transmission_color.max(axis=-1) > 0  # this frame's first surface transmits
        assert 0.05 < glass.mean() < 0.5
        assert np.array_equal(f.noisy[glass], runs["paths"][k].noisy[glass]), k
        assert np.array_equal(f.noisy[~glass], runs["gi"][k].noisy[~glass]), k
        # no pixel's bounced light was left out or counted twice: the indirect passes are the two estimators'
        assert np.array_equal(f.transmission_indirect[glass], runs["paths"][k].transmission_indirect[glass])
        assert np.array_equal(f.diffuse_indirect[~glass], runs["gi"][k].diffuse_indirect[~glass])


def test_restir_gi_everywhere_loses_the_light_refracted_at_glass(runs):
    """Negative control: at the glass pixels ReSTIR GI's bounced light is only the reflected part."""
    def bounced(variant: str) -> float:
        total = 0.0
        for f in runs[variant]:
            glass = f.transmission_color.max(axis=-1) > 0
            ind = f.diffuse_indirect * f.albedo + f.glossy_indirect * f.glossy_color \
                + f.transmission_indirect * f.transmission_color
            total += float(ind[glass].sum())
        return total
    assert bounced("gi") < 0.5 * bounced("paths")
    assert bounced("split") == bounced("paths")
