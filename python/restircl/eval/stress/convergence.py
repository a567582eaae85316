"""The fall of a method's error with the number of frames (eval/stress/suite.py), for the still cases that list frame
counts in `Case.convergence` (eval/stress/contact.py).

For an unbiased Monte Carlo estimator whose samples have a finite variance sigma^2 at each pixel, the expected relMSE
of the mean of N independent frames is the mean over pixels of sigma^2 / (N (r^2 + 0.01)): exactly proportional to
1 / N, so log relMSE against log N has the slope -1, whatever the scene. An estimator of infinite variance has no
such expectation: its error is made by rare, huge samples (an area-sampled light next to a receiver that touches
it), and over a range of N its measured relMSE falls slower (typically as N^(2 / alpha - 2): -2/3 for the tail
index 3/2 of a contact line), jumps up where the first huge sample falls (issue 37's neon: relMSE 0.03, 6.0 and
0.38 at 64, 256 and 1024 frames), or falls faster where one fell among the first frames. So the case is judged by
the least-squares slope of log relMSE on log N, the relMSE at each N being the mean over `convergence_runs`
independent runs (the nested prefixes of each run's frames), against the case's exact reference.

Bound: SLOPE_RANGE = [-1.3, -0.7]. With the renderer as it is, the quick version of `contact` (then 8 runs at 16, 64
and 256 frames) gave slopes of -0.97 .. -1.02 for every method over three sets of seeds: the bound is ten times that
spread. Before the fix of the contact fireflies (area sampling next to the light) the same runs gave +0.91 .. -0.40
or, where a huge sample fell early, -1.24 .. -1.63: outside it for two to four of the four methods in each set. The
quick version now renders 8 runs at 8, 32 and 128 frames (half the frames): over two sets of seeds -0.87 .. -1.02
(ReSTIR's the flattest: its first frames share history), as at 16, 64 and 256 on the same renderer (-0.85 .. -1.04);
with every light sampled uniformly in area (the estimator of infinite variance; the negative control in
tests/eval/test_stress.py) -1.50 .. +0.83, outside the bound for two or three of the four methods in each set
(docs/measurements/benchmarks.md, "Test suite time").
The biased ReSTIR mode converges to its bias, not to the reference: it is not judged by the slope.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...render.frame import Frame
from ...render.pipeline import Renderer
from ..metrics import rel_mse
from .cases import Case

SLOPE_RANGE = (-1.3, -0.7)
#: the methods (eval/stress/judging.py METHODS) whose error must vanish as N grows
CONVERGING = ("uniform", "light_array", "ris", "restir_unbiased")


@dataclass
class Convergence:
    frames: tuple[int, ...]
    rel_mse: tuple[float, ...]  # at each frame count, the mean over the runs
    slope: float  # of log relMSE on log frames

    @property
    def passed(self) -> bool:
        return SLOPE_RANGE[0] <= self.slope <= SLOPE_RANGE[1]

    def note(self) -> str:
        pairs = ", ".join(f"{e:.2e} at {n}" for n, e in zip(self.frames, self.rel_mse, strict=True))
        return f"relMSE {pairs}: slope {self.slope:+.2f} outside [{SLOPE_RANGE[0]:g}, {SLOPE_RANGE[1]:g}]"


def slope(frames: tuple[int, ...], errors: tuple[float, ...]) -> float:
    """Least-squares slope of log error on log frames (-inf where an error is 0: it cannot fall further)."""
    if min(errors) <= 0.0:
        return -math.inf
    return float(np.polyfit(np.log(frames), np.log(errors), 1)[0])


def convergence_runs(case: Case, r: Renderer, seed0: int, reference: np.ndarray,
                     seen: Callable[[Frame], None]) -> Convergence:
    """`case.convergence_runs` still renders of case.convergence[-1] frames with renderer r (fresh history, seeds
    from seed0 + 100 on, apart from the case's other runs), the relMSE of each at every count in case.convergence."""
    frames = tuple(case.convergence)
    errors: dict[int, list[float]] = {n: [] for n in frames}
    for k in range(case.convergence_runs):
        r.reset()
        r.settings.seed = seed0 + 100 + k

        def at(done: int, _seconds: float) -> None:
            if done in errors:
                errors[done].append(rel_mse(r.still.mean_image(), reference))

        seen(r.render_still(case.eval_frame, frames[-1], checkpoint=at))
    means = tuple(float(np.mean(errors[n])) for n in frames)
    return Convergence(frames, means, slope(frames, means))
