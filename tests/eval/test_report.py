"""`restircl report` (restircl/eval/report*.py): error against run time for a still camera, error per frame for a
moving camera, the reference cache, the files written, and Cycles beside the methods where bpy imports
(tests/eval/test_report.py runs in both venvs: without bpy the Cycles rows are replaced by a note).

The bounds on the slope of relMSE against time come from the variance of the relMSE measurements: relMSE is a
mean of per-pixel terms, so its relative standard error is std(terms) / (mean(terms) sqrt(pixels)), measured on
the image itself (conservative: the spread across pixels includes how their noise levels differ, not only chance).
"""

from __future__ import annotations

import csv
import json
import math
import shutil

import numpy as np
import pytest
from restircl import Renderer, Settings, scenes
from restircl.eval.cycles import bridge as cycles
from restircl.eval.metrics import flip, rel_mse
from restircl.eval.report import main as R
from restircl.eval.report.moving import run_moving
from restircl.eval.report.reference import get_reference

W = H = 32
# long and far enough apart (16x) that the slope against seconds has its power while another pytest worker shares the
# CPU (with 0.05..0.4 s the spread of the two relMSE figures was as large as the fall being tested)
BUDGETS = (0.1, 0.2, 0.4, 0.8, 1.6)


def quiet(_msg: str) -> None:
    pass


def relmse_cv(img: np.ndarray, ref: np.ndarray) -> float:
    """Relative standard error of rel_mse(img, ref): the std of the per-pixel terms (channels summed: they share
    their light) over their mean, over sqrt(pixels)."""
    img = np.asarray(img, dtype=np.float64)[..., :3]
    ref = np.asarray(ref, dtype=np.float64)[..., :3]
    terms = ((img - ref) ** 2 / (ref * ref + 0.01)).sum(axis=-1).ravel()
    return float(terms.std() / (terms.mean() * math.sqrt(terms.size)))


@pytest.fixture(scope="module")
def cornell(tmp_path_factory, device):
    cache = tmp_path_factory.mktemp("refs")
    scene = scenes.cornell_box(W, H)
    ref = get_reference(scene, 0, seconds_hint=8.0, device=device, cache_dir=cache, log=quiet)
    return scene, ref, cache


@pytest.fixture(scope="module")
def still_report(cornell, device, tmp_path_factory):
    scene, ref, _ = cornell
    rep = R.run_report(scene, ["ris", "restir"], BUDGETS, ("accumulate", "taa"), device=device, reference=ref,
                       log=quiet, cycles=True)
    out = tmp_path_factory.mktemp("report")
    return rep, rep.write(out)


def test_reference_is_cached_and_keyed_by_sources(cornell, device, tmp_path, monkeypatch):
    scene, ref, cache = cornell
    logs: list[str] = []
    again = get_reference(scene, 0, seconds_hint=8.0, device=device, cache_dir=cache, log=logs.append)
    assert any("cached" in m for m in logs)
    assert np.array_equal(again.image, ref.image)
    assert ref.frames >= 256 and ref.est_rel_mse is not None and ref.est_rel_mse < 1e-3
    # a kernel edit that changes what the reference estimator renders gives another key: a stale reference is
    # never reused (the copied sources with the BRDF's 1/pi edited; the in-process program cache is emptied)
    from restircl.core import program

    src = tmp_path / "opencl"
    shutil.copytree(program.opencl_dir(), src)
    monkeypatch.setattr(program, "opencl_dir", lambda: src)
    monkeypatch.setattr(program, "_PROGRAMS", {})
    logs.clear()
    same = get_reference(scene, 0, seconds_hint=8.0, device=device, cache_dir=cache, log=logs.append)
    assert any("cached" in m for m in logs) and same.path == ref.path
    edited = src / "bsdf/lambert.h"
    edited.write_text(edited.read_text().replace("albedo * RESTIRCL_INV_PI", "albedo * 0.3f"))
    monkeypatch.setattr(program, "_PROGRAMS", {})
    logs.clear()
    other = get_reference(scene, 0, frames=8, device=device, cache_dir=cache, log=logs.append)
    assert not any("cached" in m for m in logs) and other.path != ref.path


def test_report_files(still_report):
    rep, paths = still_report
    names = {p.suffix: p for p in paths}
    assert set(names) >= {".csv", ".json"}
    with open(names[".csv"]) as f:
        rows = list(csv.DictReader(f))
    methods = {"ris", "restir"} | ({"cycles"} if cycles.available() else set())
    assert {r["method"] for r in rows} == methods
    n_ours = 2 * 2 * len(BUDGETS)
    assert len(rows) == n_ours + (len(BUDGETS) if cycles.available() else 0)
    for r in rows:
        assert math.isfinite(float(r["rel_mse"])) and float(r["rel_mse"]) > 0
        assert float(r["seconds"]) >= float(r["budget_s"])
    meta = json.loads(names[".json"].read_text())
    assert meta["width"] == W and meta["height"] == H and meta["device"]
    assert meta["reference"]["method"] == "reference" and meta["reference"]["frames"] >= 256
    assert "ris (accumulate)" in meta["slopes"]
    loaded = R.load(names[".json"])
    assert loaded.rows == rep.rows
    if not cycles.available():
        assert any("bpy is not importable" in n for n in meta["notes"])
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        assert ".png" not in names
        return
    assert names[".png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert R.replot(names[".json"]) == [names[".png"]]


def test_error_falls_with_time_for_an_unbiased_method(still_report, cornell, device):
    """RIS (unbiased, independent frames) accumulated: relMSE falls like 1/n or faster (the pixel jitter is
    stratified), so the slope against samples is at most -1 up to four standard errors, and the slope against
    seconds is negative by more than four standard errors. The standard errors come from relmse_cv of images at
    the first and last budgets' sample counts."""
    rep, _ = still_report
    scene, ref, _ = cornell
    rows = rep.series("ris", "accumulate")
    assert [r.budget_s for r in rows] == list(BUDGETS)
    first, last = rows[0], rows[-1]
    assert last.frames >= 2 * first.frames, "the budgets did not give the method more samples"
    floor = ref.est_rel_mse or 0.0  # the reference's own remaining error is in every measurement
    cvs = []
    for n in (first.frames, last.frames):
        img = Renderer(scene, Settings(method="ris", seed=99), device).render_still(0, n).color
        cvs.append(relmse_cv(img, ref.image))
    sd_log = sum(cvs)  # sd of log(last) - log(first), whatever their correlation
    dy = math.log(last.rel_mse - floor) - math.log(first.rel_mse - floor)
    per_sample = dy / math.log(last.frames / first.frames)
    per_second = dy / math.log(last.seconds / first.seconds)
    sd_sample = sd_log / math.log(last.frames / first.frames)
    sd_second = sd_log / math.log(last.seconds / first.seconds)
    print(f"slope {per_sample:.2f} +- {sd_sample:.2f} per sample, {per_second:.2f} +- {sd_second:.2f} per second")
    assert per_sample <= -1.0 + 4 * sd_sample
    assert per_second + 4 * sd_second < 0
    assert R.slope(rows) < 0


def test_taa_rows_are_the_taa_output(still_report):
    rep, _ = still_report
    for method in ("ris", "restir"):
        rows = rep.series(method, "taa")
        assert [r.budget_s for r in rows] == list(BUDGETS)
        assert all(r.frames >= 1 and math.isfinite(r.rel_mse) for r in rows)


@pytest.mark.skipif(cycles.available(), reason="bpy imports here: Cycles is rendered, not skipped")
def test_cycles_skipped_without_bpy(cornell, device):
    scene, ref, _ = cornell
    logs: list[str] = []
    rep = R.run_report(scene, ["light_array"], (0.02,), device=device, reference=ref, log=logs.append, cycles=True)
    assert {r.method for r in rep.rows} == {"light_array"}
    assert any("Cycles was skipped" in n for n in rep.notes) and any("Cycles was skipped" in m for m in logs)


@pytest.mark.skipif(not cycles.available(), reason="bpy is not installed")
def test_cycles_rows(still_report, cornell):
    """Cycles at the same budgets: its own render time is recorded, and its error falls from the first budget to
    the last by more than four standard errors of the difference of the two log errors (the two renders are
    independent: their relative standard errors, relmse_cv of Cycles' own images, add in quadrature), where their
    render times differ enough to show it."""
    rep, _ = still_report
    _, ref, _ = cornell
    rows = rep.series("cycles", "accumulate")
    assert [r.budget_s for r in rows] == list(BUDGETS)
    assert all(r.seconds > 0 and math.isfinite(r.rel_mse) for r in rows)
    sc = cycles.to_bpy(scenes.cornell_box(W, H))
    imgs = [cycles.render(sc, seconds=b, seed=1).image for b in (BUDGETS[0], BUDGETS[-1])]
    sd = math.hypot(*(relmse_cv(img, ref.image) for img in imgs))
    # Cycles' samples follow its render time, not the budget: on a loaded machine its first budget takes one
    # sample of several tenths of a second, and the time ratio (the expected fall of the log error) can shrink
    # below what the bound can see. Then the renders show nothing either way.
    expected_fall = math.log(rows[-1].seconds / rows[0].seconds)
    if expected_fall < 6 * sd:
        pytest.skip(f"Cycles' render times {rows[0].seconds:.2f} / {rows[-1].seconds:.2f} s: a fall of "
                    f"{expected_fall:.2f} in log error is within 6 standard errors ({6 * sd:.2f}) on this machine now")
    assert math.log(rows[-1].rel_mse) - math.log(rows[0].rel_mse) + 4 * sd < 0


@pytest.mark.skipif(not cycles.available(), reason="bpy is not installed")
def test_scene_written_to_bpy_renders_like_ours(cornell):
    """A restircl Scene written into bpy and rendered by Cycles (direct light only) agrees with our reference:
    the bound of the Blender agreement tests (relMSE 1 %, image sums within 1 %)."""
    scene, ref, _ = cornell
    res = cycles.render(cycles.to_bpy(scene), samples=256, seed=3)
    assert res.image.shape == (H, W, 3) and res.samples == 256 and res.render_seconds > 0
    assert rel_mse(res.image, ref.image) < 0.01
    assert float(res.image.sum() / ref.image.sum()) == pytest.approx(1.0, abs=0.01)


@pytest.mark.skipif(not cycles.available(), reason="bpy is not installed")
def test_blend_scene_loads_through_the_exporter():
    from pathlib import Path

    blend = Path(__file__).resolve().parents[2] / "blend" / "area_interior.blend"
    scene, sc, _warnings = cycles.load_blend(blend, 40, 30)
    assert (scene.camera.width, scene.camera.height) == (40, 30)
    assert len(scene.lights) >= 4 and sc.render.resolution_x == 40
    assert all(not ob.visible_camera for ob in sc.objects if ob.type == "LIGHT")


def test_cycles_time_parsing():
    assert cycles.parse_time("00:01.50") == pytest.approx(1.5)
    assert cycles.parse_time("01:02:03.25") == pytest.approx(3723.25)
    assert cycles.parse_time("soon") is None


def test_moving_report(tmp_path, device):
    """Every frame rendered in order with equal time per frame; errors of every other frame (and the last)
    against per-frame references, which are cached."""
    scene = scenes.many_lights(32, 18, frames=5)
    cache = tmp_path / "refs"
    logs: list[str] = []
    rep = run_moving(scene, ["light_array", "restir"], None, every=2, modes=("taa", "frame"), device=device,
                       log=logs.append, reference_seconds=1.0, cache_dir=cache)
    frames = [0, 2, 4]
    assert sorted({r.frame for r in rep.rows}) == frames
    assert len(rep.rows) == 2 * 2 * len(frames)
    assert all(r.samples >= 1 and math.isfinite(r.rel_mse) and r.rel_mse > 0 for r in rep.rows)
    assert sum("reference: saved" in m for m in logs) == len(frames)
    # with TAA a faster method renders k frames along the path per animation frame, the same k all along; the
    # budget is the slowest method's frame time, whose k is 1
    ks = {m: {r.samples for r in rep.rows if r.method == m and r.mode == "taa"} for m in ("light_array", "restir")}
    assert all(len(k) == 1 for k in ks.values()) and ks["restir"] == {1}
    paths = rep.write(tmp_path / "out")
    assert paths[0].name == "report_moving_many_lights_32x18.csv"
    meta = json.loads(paths[1].read_text())
    assert meta["budget_ms"] == rep.budget_ms and set(meta["references"]) == {"0", "2", "4"}
    assert R.load(paths[1]).rows == rep.rows
    logs.clear()
    run_moving(scene, ["light_array"], rep.budget_ms, every=2, device=device, log=logs.append, cache_dir=cache)
    assert sum("reference: cached" in m for m in logs) == len(frames)


def test_cli_report(tmp_path, capsys, device):
    from restircl.cli.main import main

    args = ["report", "cornell_box", "--width", "16", "--height", "16", "--methods", "ris,light_array",
            "--budgets", "0.02,0.05", "--modes", "accumulate", "--no-cycles", "--reference-seconds", "1",
            "--cache-dir", str(tmp_path / "refs"), "--out", str(tmp_path / "out")]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "relMSE" in out and "slope" in out
    assert (tmp_path / "out" / "report_cornell_box_16x16.csv").exists()
    assert main(["report", "cornell_box", "--methods", "nope", "--no-cycles"]) == 2
    args = ["report", "many_lights", "--moving", "--frames", "3", "--every", "2", "--width", "16", "--height",
            "9", "--methods", "light_array", "--reference-seconds", "0.5", "--cache-dir", str(tmp_path / "refs"),
            "--out", str(tmp_path / "out")]
    assert main(args) == 0
    assert (tmp_path / "out" / "report_moving_many_lights_16x9.json").exists()


def test_flip_metric_when_installed():
    """FLIP (HDR) is reported when flip-evaluator is installed: 0 for identical images, larger for more noise."""
    pytest.importorskip("flip_evaluator")
    rng = np.random.default_rng(1)
    ref = rng.uniform(0.1, 1.0, (48, 64, 3)).astype(np.float32)
    noisy = [np.clip(ref + rng.normal(0, s, ref.shape).astype(np.float32), 0, None) for s in (0.05, 0.2)]
    same, low, high = flip(ref, ref), flip(noisy[0], ref), flip(noisy[1], ref)
    assert same is not None and low is not None and high is not None
    assert same < 1e-6 < low < high < 1.0


def test_flip_absent_gives_a_clear_note(device, monkeypatch):
    """Without flip-evaluator the FLIP column is empty and the report says why (logged and in its notes)."""
    import sys

    from restircl.eval.metrics import FLIP_MISSING, flip_available

    monkeypatch.setitem(sys.modules, "flip_evaluator", None)  # import flip_evaluator raises ImportError
    assert not flip_available()
    ref = np.full((9, 16, 3), 0.5, np.float32)
    assert flip(ref, ref) is None
    scene = scenes.cornell_box(16, 9)
    logs: list[str] = []
    rep = R.run_report(scene, ["light_array"], (0.02,), device=device, reference=ref, log=logs.append)
    assert FLIP_MISSING in rep.notes and FLIP_MISSING in logs
    assert "flip-evaluator" in FLIP_MISSING and all(r.flip is None for r in rep.rows)


def test_reference_key_ignores_the_order_of_the_triangles(cornell, device):
    # the same triangles listed in another order and started at other corners (as Blender's exports of one mesh
    # differ between processes) find the cached reference; a moved vertex does not
    import dataclasses

    scene, ref, cache = cornell
    rng = np.random.default_rng(2)
    meshes = []
    for m in scene.meshes:
        order = rng.permutation(len(m.triangles))
        shift = rng.integers(0, 3, len(order))
        tris = np.array([np.roll(t, -int(s)) for t, s in zip(m.triangles[order], shift, strict=True)])
        meshes.append(dataclasses.replace(m, triangles=tris, material_ids=m.material_ids[order]))
    logs: list[str] = []
    same = get_reference(dataclasses.replace(scene, meshes=meshes), 0, seconds_hint=8.0, device=device,
                         cache_dir=cache, log=logs.append)
    assert any("cached" in m for m in logs) and same.path == ref.path
    moved = [dataclasses.replace(m, vertices=m.vertices + (0.01 if i == 0 else 0.0)) for i, m in enumerate(meshes)]
    logs.clear()
    other = get_reference(dataclasses.replace(scene, meshes=moved), 0, frames=8, device=device, cache_dir=cache,
                          log=logs.append)
    assert not any("cached" in m for m in logs) and other.path != ref.path
