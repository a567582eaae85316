"""Stability on stiff and extreme cases (`restircl stress`, DESIGN section 5): the suite runner.

Every case is a built-in scene (eval/stress/cases.py), in a small version (the tests) and a full one (the CLI, --full).
Each is rendered with every method -- uniform, light_array, ris, restir biased (bias_correction "none") and
unbiased ("pairwise") -- and checked against its reference (eval/stress/references.py):

    analytic    direct light computed on the host in float64 at the renderer's own G-buffer points: point and
                spot lights, spheres and soft-falloff disks, suns, quads and triangles (Lambert's polygon formula)
                fully above or below each point's horizon; only for scenes where nothing occludes a light
    exhaustive  the `reference` method (every light, one sample each), averaged over batches of frames; a
                scene of delta lights only needs one frame
    zero        the image must be exactly 0 (every light behind the surfaces)

A case is judged by its statistics, never by a tuned threshold (eval/stress/judging.py). Independent runs (fresh
history, own seed) give run means whose spread is the standard error; an unbiased method passes when at most
`allowed_outliers` pixels are more than 4 standard errors from the reference (t with runs - 1 degrees of freedom;
pixels where both sides are exact must agree to float32 rounding) and the image mean is within 4 standard errors.
The biased ReSTIR mode must not be brighter than the reference beyond 4 standard errors and not darker than the
15% that tests/render/test_restir.py bounds its darkening by. Every case requires zero NaN/Inf: the renderer's guard
counters (Frame.guards) plus a scan of every array it returned. relMSE = mean (x - r)^2 / (r^2 + 0.01) of the mean
image; `expected` is what the measured variances alone predict for it (a ratio near 1 means no visible bias).
Cases that list frame counts in `convergence` (eval/stress/contact.py: receivers touching emitters) also judge
every method whose error must vanish by how its relMSE falls with the frames: the slope of log relMSE on log N,
-1 for an estimator of finite variance, must lie in [-1.3, -0.7] (eval/stress/convergence.py).

Kinds of case: `still` (runs of a still camera, render_still), `sequence` (per run: a few frames, then the frame
under test; its 1-sample image is the run's value, the mean of 8 samples of that frame for methods without
history) and `long` (one very long animation with TAA and ReSTIR, compared by batch means of its 1-sample
estimates over its second part: TAA's output of a still camera averages over up to max_history frames, more than
a batch, so its batch means are not independent; the ReSTIR M and the TAA history length are checked to stay
capped).

Every case and method also reports the temporal stability of what a viewer of its frame under test would see
(eval/report/flicker.py): 16 consecutive TAA outputs of that frame held after 16 warm-up frames (the case's settings
with TAA on and no jitter; sequence cases first render their frames before it; the long animation: its last 16 outputs),
against the reference: `flicker` (the mean temporal standard deviation of each pixel's relative error), `flk/err`
(flicker over the RMS relative error: near 1 the error is frame-to-frame noise, near 0 a steady offset) and
`boil px` (blotch pixels per frame). The JSON has the RMS as `flicker_error`.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

from .catalog import cases
from .judging import METHODS, Result, run_method
from .references import compute_reference


def run(full: bool = False, methods: list[str] | None = None, names: list[str] | None = None, device=None,
        log: Callable[[str], None] | None = None, seed: int = 0) -> list[Result]:
    """Every case with every method. `seed` shifts every random seed (the tests use 0; other values give
    independent repetitions, to see how often a correct renderer fails a 4-standard-error test)."""
    methods = methods or list(METHODS)
    unknown = [m for m in methods if m not in METHODS]
    if unknown:
        raise ValueError(f"unknown methods {unknown}; methods: {', '.join(METHODS)}")
    results = []
    for case in cases(full, names):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ref = compute_reference(case, device, seed=seed)
        if log:
            log(f"{case.name}: {case.description}; {case.reference} reference ({ref.seconds:.1f} s)")
        for m in methods:
            res = run_method(case, m, ref, device, seed)
            results.append(res)
            if log:
                log("  " + " | ".join(res.row()))
    return results

