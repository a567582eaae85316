"""`restircl bench frame`'s last lines (eval/bench.bench_floor): the default frame and the lightest ReSTIR frame
against the floor of one camera ray, one shadow ray and TAA. The frames' timing is replaced by fixed stage times
(timing itself belongs to the benchmark, not to a test); what is checked is which frames are timed and the
arithmetic of the floor and of both ratios."""

from __future__ import annotations

import math

import pytest
from restircl import Settings
from restircl.eval.bench import main as bench

# stage ms per method, as time_frames returns them (median frame ms, mean stage ms)
FAKE = {
    "default": (300.0, {"primary": 30.0, "initial": 100.0, "temporal": 50.0, "spatial": 60.0, "shade": 9.0,
                        "taa": 20.0, "cpu": 1.0}),
    "light_array": (90.0, {"primary": 31.0, "shade": 35.0, "taa": 19.0, "cpu": 1.0}),
    "lightest": (180.0, {"primary": 30.0, "initial": 20.0, "temporal": 30.0, "spatial": 45.0, "shade": 34.0,
                         "taa": 20.0, "cpu": 1.0}),
}


def test_bench_floor_times_default_floor_and_lightest_restir(monkeypatch: pytest.MonkeyPatch) -> None:
    seen: list[Settings] = []

    def fake_time_frames(scene, settings: Settings, frames: int = 6, **kw):
        seen.append(settings)
        if settings.method == "light_array":
            return FAKE["light_array"]
        if settings == Settings():
            return FAKE["default"]
        return FAKE["lightest"]

    monkeypatch.setattr(bench, "time_frames", fake_time_frames)
    monkeypatch.setattr(bench, "many_lights", lambda **kw: None)
    lines: list[str] = []
    out = bench.bench_floor(64, 36, print_fn=lines.append)

    lightest = Settings(**bench.LIGHTEST_RESTIR)
    assert seen == [Settings(), Settings(method="light_array"), lightest]
    assert (lightest.method, lightest.candidates, lightest.bsdf_sampling, lightest.visibility_reuse) == (
        "restir", 1, "off", False)
    # floor: the light_array frame's camera rays and shade stage, the default frame's TAA
    assert out["floor"]["ms"] == pytest.approx(31.0 + 35.0 + 20.0)
    assert out["ratio"] == pytest.approx(300.0 / 86.0)
    assert out["lightest_ratio"] == pytest.approx(180.0 / 86.0)
    assert math.isfinite(out["lightest_ms"])
    assert any("default frame / floor: 3.49" in s for s in lines)
    assert any("lightest ReSTIR frame" in s and "/ floor: 2.09" in s for s in lines)
