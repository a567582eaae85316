"""Judging a method on a stress case (eval/stress/suite.py): the runs it renders, the statistics it is judged by, the
table and the files the results are written to."""

from __future__ import annotations

import csv
import json
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np
import pyopencl as cl

from ...core import layouts as L
from ...render.frame import Frame
from ...render.pipeline import Renderer
from ...settings.table import Settings
from ..report.flicker import stats as flicker_stats
from .cases import Case
from .convergence import CONVERGING, convergence_runs
from .references import Reference, luminance

# name -> Settings overrides
METHODS: dict[str, dict] = {
    "uniform": dict(method="uniform"),
    "light_array": dict(method="light_array"),
    "ris": dict(method="ris"),
    "restir_biased": dict(method="restir", bias_correction="none"),
    "restir_unbiased": dict(method="restir", bias_correction="pairwise"),
}
Z = 4.0  # standard errors
BIASED_DARKENING = 0.15  # the bound tests/render/test_restir.py puts on the biased mode's darkening
F32_EPS = 2.0**-24

# ReSTIR's temporal and spatial reuse with a history cap of 20 x candidates make run means heavy-tailed (a lucky
# sample persists for tens of frames, tests/render/test_restir.py); the still cases use the cap 4x so that a few dozen
# runs can judge them. The long animation keeps the default cap: that is where the cap itself is under test.
STILL_SETTINGS = dict(jitter=False, taa=False, m_cap=4.0)

# A 4-standard-error test of a mean needs the mean to be close to normal. One-sample estimates of the many-light
# cases are strongly skewed where a light is picked rarely but contributes much: computed from the per-light
# contributions of million_lights, the per-sample skewness is 4.1 for uniform picks and 1.6 for the light array
# (median over pixels); in power_span, uniform picks of its 1e6 W light alone (p = 1/13) give about 3. The skewness
# of a mean of n samples falls as 1/sqrt(n): uniform and light_array get 4x and 2x the frames (they are also the
# cheapest), so that their run means are about as close to normal as RIS's. (With 2.5 m between the lights and the
# floor and strengths over four decades, million_lights had 14 and 5, and uniform failed 3 of 7 seed sweeps.)
FRAMES_FACTOR = {"uniform": 4, "light_array": 2}


@dataclass
class Result:
    case: str
    method: str
    nonfinite: int  # guard counts + NaN/Inf found in returned arrays
    max_value: float
    rel_mse: float
    expected_rel_mse: float  # what the measured variances alone predict
    outliers: int  # pixels beyond Z standard errors
    allowed: int
    z_image: float  # image mean against the reference, in standard errors
    rel_bias: float  # image mean / reference image mean - 1
    passed: bool
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0
    samples: int = 0  # frames rendered for the statistics
    # temporal stability (eval/report/flicker.py) of FLICKER_FRAMES consecutive outputs (the run's TAA output; long
    # animations: their last ones): flicker = mean temporal std of the relative error, flicker_error = its RMS,
    # flicker_ratio = their ratio, boiling = blotch pixels per frame; NaN where not measured
    flicker: float = math.nan
    flicker_error: float = math.nan
    flicker_ratio: float = math.nan
    boiling: float = math.nan
    # cases with Case.convergence: the slope of log relMSE on log frames (eval/stress/convergence.py); NaN elsewhere
    slope: float = math.nan

    def row(self) -> list[str]:
        def g(v: float) -> str:
            return "-" if not math.isfinite(v) else f"{v:.3g}"

        return [self.case, self.method, str(self.nonfinite), g(self.max_value), g(self.rel_mse),
                g(self.expected_rel_mse), f"{self.outliers}/{self.allowed}", g(self.z_image), g(self.rel_bias),
                "pass" if self.passed else "FAIL", f"{self.seconds:.1f}", g(self.flicker), g(self.flicker_ratio),
                g(self.boiling), g(self.slope), "; ".join(self.notes)]


HEADER = ["case", "method", "NaN/Inf", "max", "relMSE", "expected", "z>4 px", "z image", "bias", "result", "s",
          "flicker", "flk/err", "boil px", "slope", "notes"]
FLICKER_FRAMES = 16  # consecutive outputs the flicker statistics are taken over
FLICKER_WARMUP = 16  # still and sequence cases: frames of the held camera before them (history fills)


def _nonfinite(frame: Frame) -> int:
    """NaN/Inf in what the renderer returned (depth is +inf where a camera ray missed: only NaN counts there)."""
    bad = sum(int((~np.isfinite(a)).sum()) for a in (frame.color, frame.noisy, frame.normal, frame.vector,
                                                     frame.albedo))
    return bad + int(np.isnan(frame.depth).sum())


def _reservoir_m(r: Renderer) -> np.ndarray:
    """M of the reservoirs the last frame left as history."""
    res = np.empty(r.pixels, L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, res, r.res_history[r.last_slot])
    return res["M"]



def _allowed_outliers(n: int, dof: int, z: float = Z) -> int:
    """How many of n independent t statistics (dof degrees of freedom) may exceed z: the expected count plus four
    of its binomial standard deviations, plus one (as tests/helpers.py)."""
    from scipy import stats

    p = 2 * stats.t.sf(z, dof)
    return int(math.ceil(n * p + 4 * math.sqrt(n * p * (1 - p)) + 1))



def _settings(case: Case, method: str, seed: int) -> Settings:
    base = dict(STILL_SETTINGS)
    base.update(METHODS[method])
    base.update(case.settings)
    base["seed"] = seed
    return Settings(**base)



def _judge(case: Case, method: str, values: np.ndarray, ref: Reference, nonfinite: int, max_value: float,
           seconds: float, samples: int, notes: list[str]) -> Result:
    """values: (runs or batches, H, W, 3) independent estimates of the reference."""
    k = values.shape[0]
    dof = k - 1
    mean = values.mean(axis=0)
    se = values.std(axis=0, ddof=1) / math.sqrt(k)
    rel = float(np.mean((mean - ref.mean) ** 2 / (ref.mean**2 + 0.01)))
    expected = float(np.mean((se**2 + ref.se**2) / (ref.mean**2 + 0.01)))
    lum = luminance(values)
    lm = lum.mean(axis=0)
    lse = lum.std(axis=0, ddof=1) / math.sqrt(k)
    lref = luminance(ref.mean)
    sigma = np.sqrt(lse**2 + ref.lum_se**2)
    # exact pixels: both sides have no spread beyond rounding (identical float32 values give a standard deviation
    # of 1e-17 in float64, not 0); they must agree to the rounding of float32 sums of `terms` terms, and of the
    # float32 running sum of a run's frames (each addition rounds: the error grows with the frame count)
    scale = np.maximum(np.abs(lref), np.abs(lm))
    live = sigma > 16 * F32_EPS * scale + 1e-30
    z = np.abs(lm - lref)[live] / sigma[live]
    outliers = int((z > Z).sum())
    allowed = _allowed_outliers(int(live.sum()), dof)
    exact = ~live
    tol = (16 + ref.terms + samples // max(k, 1)) * F32_EPS * scale[exact] + 1e-30
    bad_exact = int((np.abs(lm - lref)[exact] > tol).sum())
    img = lum.mean(axis=(1, 2))
    img_se = math.hypot(float(img.std(ddof=1)) / math.sqrt(k), ref.image_se)
    ref_img = float(lref.mean())
    diff = float(img.mean()) - ref_img
    z_img = abs(diff) / img_se if img_se > 0 else (0.0 if abs(diff) <= 1e-6 * abs(ref_img) + 1e-30 else math.inf)
    rel_bias = diff / ref_img if ref_img != 0 else (0.0 if diff == 0 else math.inf)
    passed = nonfinite == 0
    if nonfinite:
        notes.append(f"{nonfinite} NaN/Inf")
    if case.reference == "zero":
        ok = bool(np.all(values == 0.0))
        if not ok:
            notes.append("image not exactly 0")
        passed &= ok
    elif METHODS[method].get("bias_correction") == "none":
        # biased mode: no brighter than the reference beyond noise, darker by at most BIASED_DARKENING
        rb_se = img_se / abs(ref_img) if ref_img else 0.0
        ok = -(case.biased_darkening or BIASED_DARKENING) - Z * rb_se <= rel_bias <= Z * rb_se
        if not ok:
            notes.append(f"biased mode off by {rel_bias:+.3f} (+-{rb_se:.3f})")
        passed &= ok
    else:
        if outliers > allowed:
            notes.append(f"{outliers} pixels beyond {Z:g} se (allowed {allowed})")
        if bad_exact:
            notes.append(f"{bad_exact} exact pixels differ")
        if z_img > Z:
            notes.append(f"image mean {z_img:.1f} se off ({rel_bias:+.2e})")
        passed &= outliers <= allowed and bad_exact == 0 and z_img <= Z
    return Result(case.name, method, nonfinite, max_value, rel, expected, outliers, allowed, z_img, rel_bias,
                  passed, notes, seconds, samples)


def run_method(case: Case, method: str, ref: Reference, device=None, seed: int = 0) -> Result:
    t0 = time.perf_counter()
    notes: list[str] = []
    seed0 = 1000 * (list(METHODS).index(method) + 1) + 100_000 * seed
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # degenerate triangles are dropped with a warning: expected here
        r = Renderer(case.scene, _settings(case, method, seed0), device)
    seen = _Seen()
    conv = None
    if case.kind == "still":
        values, samples = _still_runs(case, method, r, seed0, seen)
        if case.convergence and method in CONVERGING:
            conv = convergence_runs(case, r, seed0, ref.mean, seen)
    elif case.kind == "sequence":
        values, samples = _sequence_runs(case, r, seed0, seen, notes)
        if case.no_ghost:
            _check_no_ghost(case, r.settings, device, seen, notes)
    else:
        values, samples, last = _long_run(case, r, seen, notes)
    if case.kind != "long":
        last, guards = _flicker_outputs(case, r.settings, device, seen)
        seen.nonfinite += guards
    seen.nonfinite += sum(r.guard_totals.values())
    res = _judge(case, method, np.stack(values), ref, seen.nonfinite, seen.max_value, time.perf_counter() - t0,
                 samples, notes)
    st = flicker_stats(method, "still", last, [ref.mean] * len(last))
    res.flicker, res.flicker_error, res.flicker_ratio, res.boiling = st.flicker, st.error, st.ratio, st.boiling
    if conv is not None:
        res.slope = conv.slope
        if not conv.passed:
            res.notes.append(conv.note())
    bad = [n for n in notes if not n.startswith("max ")]
    if bad and res.passed:
        res.passed = False
    return res


class _Seen:
    """What every frame a case renders adds to its verdict: NaN/Inf values and the largest value."""

    def __init__(self) -> None:
        self.nonfinite = 0
        self.max_value = 0.0

    def __call__(self, f: Frame) -> None:
        self.nonfinite += _nonfinite(f)
        self.max_value = max(self.max_value, float(np.nanmax(f.color[..., :3])), float(np.nanmax(f.noisy)))


def _still_runs(case: Case, method: str, r: Renderer, seed0: int, seen: _Seen) -> tuple[list[np.ndarray], int]:
    """A still case: `runs` independent still renders of the frame under test; the images and the sample count."""
    values = []
    samples = 0
    for k in range(case.runs):
        r.reset()
        r.settings.seed = seed0 + k
        f = r.render_still(case.eval_frame, case.frames * FRAMES_FACTOR.get(method, 1))
        seen(f)
        values.append(f.color[..., :3].astype(np.float64))
        samples += f.samples
    return values, samples


def _sequence_runs(case: Case, r: Renderer, seed0: int, seen: _Seen,
                   notes: list[str]) -> tuple[list[np.ndarray], int]:
    """A sequence case, `runs` times from a fresh history: the frames before, the frame under test (its 1-sample
    image), then the frames that must be exactly 0; the images and the sample count."""
    values = []
    samples = 0
    for k in range(case.runs):
        r.reset()
        r.settings.seed = seed0 + k
        for fr in case.before:
            seen(r.render_frame(fr))
        f = r.render_frame(case.eval_frame)
        seen(f)
        if case.cut_expected and "temporal" in f.stage_ms:
            notes.append("temporal reuse across a cut")
        value = f.noisy.astype(np.float64)
        # a method without history gives independent samples of the frame under test: average a few
        repeats = 1 if r.settings.method == "restir" else case.eval_repeats
        for _ in range(repeats - 1):
            f = r.render_frame(case.eval_frame)
            seen(f)
            value += f.noisy
        values.append(value / repeats)
        samples += len(case.before) + repeats
        for fr in case.zero_after:
            fz = r.render_frame(fr)
            seen(fz)
            if not (np.all(fz.noisy == 0) and np.all(fz.color[..., :3] == 0)):
                notes.append(f"frame {fr} not exactly 0")
    return values, samples


def _check_no_ghost(case: Case, settings: Settings, device, seen: _Seen, notes: list[str]) -> None:
    """With TAA, the frame under test after the case's jump must be its own sample everywhere. The fresh-pixel fill
    is off for this check: it shows a pixel without history the mean of its own surface's samples of this frame
    (taa/fresh_fill.h), no history, and would hide a kept one among the filled pixels."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rt = Renderer(case.scene, Settings(**{**settings.__dict__, "taa": True, "taa_fresh_fill": False}), device)
    for fr in case.before:
        seen(rt.render_frame(fr))
    f = rt.render_frame(case.eval_frame)
    seen(f)
    if not np.array_equal(f.color[..., :3], f.noisy):
        notes.append(f"TAA kept history after the jump ({int((f.color[..., :3] != f.noisy).any(-1).sum())} px)")
    seen.nonfinite += sum(rt.guard_totals.values())


def _long_run(case: Case, r: Renderer, seen: _Seen, notes: list[str]) -> tuple[list[np.ndarray], int, list]:
    """A long case: `frames` frames of one history; the batch means of the 1-sample images after the warm-up, the
    sample count and the last FLICKER_FRAMES TAA outputs. Notes the largest ReSTIR M and TAA history length."""
    b = case.long_batch
    n_batches = (case.frames - case.long_warmup) // b
    start = case.frames - n_batches * b
    m_bound = _m_bound(r.settings)
    acc = np.zeros((r.height, r.width, 3))
    values: list[np.ndarray] = []
    last: list[np.ndarray] = []
    max_m = 0.0
    max_n = 0.0
    for fr in range(case.frames):
        f = r.render_frame(fr)
        seen(f)
        if fr >= case.frames - FLICKER_FRAMES:
            last.append(f.color[..., :3].copy())
        if fr >= start:  # ReSTIR's estimate: TAA's 1/n blend of a still camera spans more than a batch
            acc += f.noisy
            if (fr - start + 1) % b == 0:
                values.append(acc / b)
                acc = np.zeros_like(acc)
        if fr % 50 == 49 or fr == case.frames - 1:
            if r.settings.method == "restir":
                max_m = max(max_m, float(_reservoir_m(r).max()))
            max_n = max(max_n, float(r.history_length().max()))
    if max_m > m_bound:
        notes.append(f"ReSTIR M reached {max_m:g} > bound {m_bound:g}")
    if max_n > r.settings.max_history:
        notes.append(f"TAA history length reached {max_n:g} > {r.settings.max_history}")
    if case.frames > r.settings.max_history and max_n < r.settings.max_history:
        notes.append(f"TAA history length only reached {max_n:g}")
    if r.settings.method == "restir":
        notes.append(f"max M {max_m:g} (bound {m_bound:g})")
    notes.append(f"max TAA n {max_n:g}")
    return values, case.frames, last


def _flicker_outputs(case: Case, settings: Settings, device,
                     seen: Callable[[Frame], None]) -> tuple[list[np.ndarray], int]:
    """What a viewer of the case's frame under test sees: the case's frames before it (sequence cases), then that
    frame held for FLICKER_WARMUP + FLICKER_FRAMES frames with history carried and TAA on (no jitter: the
    reference is at the pixel centres): the last FLICKER_FRAMES TAA outputs, and the renderer's guard count."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = Renderer(case.scene, replace(settings, taa=True, jitter=False), device)
    for fr in case.before if case.kind == "sequence" else ():
        seen(r.render_frame(fr))
    out = []
    for k in range(FLICKER_WARMUP + FLICKER_FRAMES):
        f = r.render_frame(case.eval_frame)
        seen(f)
        if k >= FLICKER_WARMUP:
            out.append(f.color[..., :3].copy())
    return out, sum(r.guard_totals.values())


def _m_bound(s: Settings) -> float:
    """The largest M a stored reservoir can have: the temporal pass caps last frame's M at m_cap * candidates
    and adds this frame's candidates (a pixel without history: its candidates and the lonely pixel's
    `fresh_candidates`); each spatial pass adds at most `spatial_neighbours` such reservoirs, or
    `disocclusion_boost` for a pixel without history (with permutation sampling a still camera has those too, where
    the permuted neighbour's surface differs)."""
    m = s.candidates + s.m_cap * s.candidates if s.temporal else s.candidates
    if s.spatial:
        m *= (1 + max(s.spatial_neighbours, s.disocclusion_boost)) ** s.spatial_passes
    return float(max(m, s.candidates + s.fresh_candidates))  # a lonely pixel merges no neighbour



def format_table(results: list[Result]) -> str:
    rows = [HEADER] + [r.row() for r in results]
    widths = [max(len(row[i]) for row in rows) for i in range(len(HEADER) - 1)]
    lines = []
    for k, row in enumerate(rows):
        lines.append("  ".join(c.ljust(w) for c, w in zip(row[:-1], widths, strict=True)) + "  " + row[-1])
        if k == 0:
            lines.append("-" * (sum(widths) + 2 * len(widths) + 5))
    return "\n".join(lines)


def write(results: list[Result], out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / "stress.csv", out / "stress.json"]
    with open(paths[0], "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(HEADER)
        w.writerows(r.row() for r in results)
    paths[1].write_text(json.dumps([asdict(r) for r in results], indent=1, default=float))
    return paths

