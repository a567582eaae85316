"""The reference-free error estimate of still renders (Renderer.error_estimate, render/half_error.py): it tracks the
true relMSE within a factor of two on the built-in scenes, where the error is fireflies it reads what it was measured
to read (about 0.7-1.7x, not the 0.03-0.13x of r^2 from the pixel's own mean), and `target_error` stops a still
render when the estimate reaches it, in the Python API and the CLI (the Blender add-on's Target Error:
tests/blender/test_blender_render.py).

The estimate compares two half buffers. Measured (2026-12-06, 64x36 / 48x48, seeds 100-102, estimate / true relMSE
at 64 and 256 samples; docs/measurements/error-vs-time.md): many_lights ris 0.84-1.30 / 0.45-1.44, restir 1.13-1.65
/ 1.42-2.06, restir_spatial 1.20-1.47 / 1.33-1.94, restir_temporal 1.01-1.45 / 1.15-1.59; cornell_box ris 1.04-1.38
/ 0.87-1.26, restir 0.96-1.06 / 0.85-1.40, restir_spatial 0.67-0.80 / 1.01-1.15, restir_temporal 0.84-0.98 /
0.91-1.12. Where the error is fireflies (`uniform` and `light_array` on many_lights, a random light per sample or
per pixel) a pixel's r^2 must not come from its own mean, which the firefly inflates: so weighed, the estimate read
0.03-0.13 of uniform's error and 0.5-0.65 of light_array's. Their ratio varies much between seeds, so they have a
test of their own, calibrated on 24 seeds. Not tracked: the bias of the biased ReSTIR modes (the halves share it;
on cornell_box the estimate was 0.3x the true relMSE at 256 samples, where the bias dominates).
"""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Settings, scenes
from restircl.eval.metrics import rel_mse
from restircl.eval.report.methods import METHODS
from restircl.eval.report.reference import Reference, get_reference
from restircl.render.half_error import R2_FLOOR, R2Rule, rel_mse_from_halves, robust_r2
from restircl.render.still import HALF_BLOCK
from restircl.render.still import half_of as _half_of

CHECKS = (64, 256)
SEEDS = 3
# Reference frames: a fixed count, so the check is the same at any load (a time hint of 30 s rendered 60 s of the
# suite on an idle machine, and fewer frames under load). Their own relMSE, estimated from their half buffers, is
# taken out of the measured error (true_rel_mse); measured: many_lights 2.7e-3 at 1024 frames, 14 % of the smallest
# true relMSE checked (ris at 256 samples, 0.019); cornell_box 1.4e-4 at 1024 frames, a quarter of that at 4096.
REF_FRAMES = {"many_lights": 1024, "cornell_box": 4096}


@pytest.fixture(scope="module")
def refs(tmp_path_factory, device):
    cache = tmp_path_factory.mktemp("refs")
    out = {}
    for name, (w, h) in (("many_lights", (64, 36)), ("cornell_box", (48, 48))):
        scene = scenes.builtin(name, width=w, height=h)
        out[name] = (scene, get_reference(scene, 0, frames=REF_FRAMES[name], device=device, cache_dir=cache,
                                          log=lambda s: None))
    return out


def true_rel_mse(img: np.ndarray, ref: Reference) -> float:
    """relMSE of `img` against the converged image. The reference r = mu + e_r is itself noisy, independent of
    the render x = mu + e_x, so E[(x - r)^2] = E[e_x^2] + E[e_r^2]: its own relMSE (from its half buffers) is
    subtracted rather than counted as the render's error."""
    return rel_mse(img, ref.image) - float(ref.est_rel_mse or 0.0)


def test_halves_are_blocks_of_equal_size():
    halves = [_half_of(k) for k in range(64 * HALF_BLOCK)]
    for start in range(0, len(halves), HALF_BLOCK):  # whole blocks go to one half
        assert len(set(halves[start:start + HALF_BLOCK])) == 1
    for start in range(0, len(halves), 2 * HALF_BLOCK):  # each pair of blocks feeds both halves
        assert sum(halves[start:start + 2 * HALF_BLOCK]) == HALF_BLOCK
    firsts = [halves[s] for s in range(0, len(halves), 2 * HALF_BLOCK)]
    assert 0 < sum(firsts) < len(firsts)  # which block of a pair comes first is not always the same


def test_a_firefly_on_a_flat_image_is_weighed_by_its_neighbours():
    """Halves of 64 samples of a flat image r = 0.25, one sample of one pixel 1000x brighter in half a: the
    estimate is exactly the mean's relMSE (the other pixels' halves agree), where r^2 from the pixel's own mean reads
    it 17x low (the control)."""
    r = np.full((9, 9, 3), 0.25)
    a, b = r.copy(), r.copy()
    a[4, 4] += 250.0 / 64
    mean = (a + b) / 2
    true = rel_mse(mean, r)
    assert rel_mse_from_halves(a, b, 64, 64) == pytest.approx(true, rel=1e-9)
    assert rel_mse_from_halves(a, b, 64, 64, own_mean_r2) < true / 10


def test_a_lamp_seen_in_one_half_only_keeps_the_floor():
    """A pixel met by a small lamp in half a only, over black (many_lights' sub-pixel lamps at 16 samples): nothing
    tells it from a firefly over black, so its term stays near 1 / R2_FLOOR (r^2 = R2_FLOOR x mean^2), not
    mean^2 / 0.01 as the neighbours' cap alone would make it (many_lights ris then read 16x at 16 samples)."""
    a, b = np.zeros((5, 6, 3)), np.zeros((5, 6, 3))
    a[2, 3] = 10.0  # mean 5, variance of the mean (10 / 2)^2
    est = rel_mse_from_halves(a, b, 32, 32)
    assert est * a[..., 0].size == pytest.approx(5.0**2 / (R2_FLOOR * 5.0**2 + 0.01), rel=1e-9)


# Every method on cornell_box, and RIS and full ReSTIR (temporal and spatial reuse both) on many_lights; the two
# single-reuse modes on many_lights repeat what cornell_box and full ReSTIR check and run behind `slow`
@pytest.mark.parametrize(
    "scene_name,method",
    [
        ("many_lights", "ris"),
        pytest.param("many_lights", "restir_spatial", marks=pytest.mark.slow),
        pytest.param("many_lights", "restir_temporal", marks=pytest.mark.slow),
        ("many_lights", "restir"),
        ("cornell_box", "ris"),
        ("cornell_box", "restir_spatial"),
        ("cornell_box", "restir_temporal"),
        ("cornell_box", "restir"),
    ],
)
def test_estimate_tracks_true_relmse(refs, device, scene_name, method, record_property):
    """Median over seeds of estimate / true relMSE within a factor of two, at 64 and 256 samples. ReSTIR's
    temporal reuse correlates frames; render_still gives each half its own chain so the halves stay independent."""
    scene, ref = refs[scene_name]
    ratios: dict[int, list[float]] = {n: [] for n in CHECKS}
    for seed in range(SEEDS):
        r = Renderer(scene, Settings(**METHODS[method], seed=100 + seed), device)

        def checkpoint(done: int, _secs: float, r=r) -> None:
            if done in ratios:
                est = r.error_estimate(*r.still_counts)
                true = true_rel_mse(r.mean_image(), ref)
                ratios[done].append(est / true)

        r.render_still(0, max(CHECKS), checkpoint=checkpoint)
    med = {n: float(np.median(v)) for n, v in ratios.items()}
    record_property("median_ratio", med)
    print(scene_name, method, {n: [round(x, 2) for x in v] for n, v in ratios.items()})
    for n, m in med.items():
        assert 0.5 <= m <= 2.0, f"{scene_name} {method}: estimate / true relMSE {m:.2f} at {n} samples"


def own_mean_r2(a: np.ndarray, b: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """The negative control: r^2 from the pixel's own halves (their harmonic mean, floored at R2_FLOOR x mean^2), so
    that a firefly inflates the very r^2 that should weigh it."""
    s = a + b
    hm = np.divide(2 * a * b, s, out=np.zeros_like(s), where=s > 0)
    return np.maximum(hm * hm, R2_FLOOR * mean * mean)


RULES: dict[str, R2Rule] = {"robust": robust_r2, "own_mean": own_mean_r2}

# log(estimate / true relMSE) on many_lights (64x36) over seeds 100-123 (tools/experiments/error_estimate_halves.py,
# docs/measurements/error-vs-time.md "Error while rendering, without a reference"): mean, standard deviation. Both
# methods' error is fireflies: a random light per pixel (light_array) or per sample (uniform).
FIREFLY_LOG_RATIO = {
    "uniform": {64: (0.154, 0.789), 256: (0.006, 0.442)},
    "light_array": {64: (-0.142, 0.949), 256: (-0.250, 0.478)},
}
FIREFLY_SEEDS = range(200, 206)  # not the seeds of the measurement


@pytest.mark.parametrize("method", list(FIREFLY_LOG_RATIO))
def test_estimate_weighs_fireflies_by_their_neighbourhood(refs, device, method):
    """Where the error is fireflies, the geometric mean of estimate / true relMSE over 6 seeds is within 4 standard
    errors (sd / sqrt(6)) of the measured one, at 64 and 256 samples. The control, r^2 from the pixel's own halves
    and mean, must fail on `uniform` (measured on seeds 200-205: 2.6 bounds away; it reads 0.03-0.13 of the error
    there). On light_array the control is within the bounds (it reads 0.5-0.65 of the error, the rule 0.75-0.9)."""
    scene, ref = refs["many_lights"]
    logs: dict[str, dict[int, list[float]]] = {rule: {n: [] for n in CHECKS} for rule in RULES}
    for seed in FIREFLY_SEEDS:
        r = Renderer(scene, Settings(**METHODS[method], seed=seed), device)

        def checkpoint(done: int, _secs: float, r=r) -> None:
            if done in CHECKS:
                true = true_rel_mse(r.mean_image(), ref)
                n_half = r.still_counts[1]
                a, b = r.still.halves(done, n_half)
                for rule, r2 in RULES.items():
                    logs[rule][done].append(float(np.log(rel_mse_from_halves(a, b, n_half, done - n_half, r2) / true)))

        r.render_still(0, max(CHECKS), checkpoint=checkpoint)
    for n, (mu, sd) in FIREFLY_LOG_RATIO[method].items():
        bound = 4 * sd / np.sqrt(len(FIREFLY_SEEDS))
        got, control = float(np.mean(logs["robust"][n])), float(np.mean(logs["own_mean"][n]))
        print(f"{method} at {n}: geometric mean ratio {np.exp(got):.3f} (control {np.exp(control):.3f}), allowed "
              f"{np.exp(mu - bound):.3f}-{np.exp(mu + bound):.3f}")
        assert abs(got - mu) <= bound, (method, n, np.exp(got))
        if method == "uniform":
            assert abs(control - mu) > bound, (n, np.exp(control))


def test_target_error_stops_a_still_render(refs, device):
    scene, ref = refs["cornell_box"]
    target = 2e-3
    r = Renderer(scene, Settings(method="ris", seed=7), device)
    out = r.render_still(0, 100_000, target_error=target)
    assert HALF_BLOCK * 2 <= out.samples < 100_000
    assert out.error_estimate is not None and out.error_estimate <= target
    # the check runs every 4 samples: 4 samples earlier the estimate was still above the target, so it
    # stopped near it (the estimate falls like 1/n), and the true error is within the estimate's factor two
    assert out.error_estimate > target * (out.samples - 4) / out.samples / 1.5
    true = true_rel_mse(out.color, ref)
    assert target / 2 <= true <= 2 * target, f"true relMSE {true:.2e} for a target of {target:.0e}"
    # an unreachable target renders every sample
    r2 = Renderer(scene, Settings(method="ris", seed=7), device)
    assert r2.render_still(0, 24, target_error=1e-12).samples == 24


def test_still_restir_keeps_its_history_after_two_chains(refs, device):
    """After a still render that ran a second reservoir chain, the renderer goes on with the first chain's
    buffers: another still render and animation frames work and stay finite."""
    scene, ref = refs["cornell_box"]
    r = Renderer(scene, Settings(method="restir", seed=3), device)
    a = r.render_still(0, 3 * HALF_BLOCK + 3)
    b = r.render_still(0, 2 * HALF_BLOCK)
    f = r.render_frame(0)
    for img in (a.color, b.color, f.color):
        assert np.all(np.isfinite(img))
    assert rel_mse(b.color, ref.image) < 4 * max(b.error_estimate, 1e-6)


def test_cli_render_target_error(tmp_path, capsys, device):
    from restircl.cli.main import main

    rc = main(["render", "cornell_box", "--width", "32", "--height", "32", "--frames", "50000", "--method",
               "ris", "--target-error", "3e-3", "--out", str(tmp_path)])
    assert rc == 0
    out = capsys.readouterr().out
    assert "stopped after" in out and "reached the target 0.003" in out
    samples = int(out.split("stopped after ")[1].split()[0])
    assert samples < 50000
    assert (tmp_path / "cornell_box_ris.exr").exists()
