"""Which frames draw their RIS samples from the scrambled Sobol sequence of opencl/sampling/qmc.h (Settings.sampler),
and the sequence's index and key for a frame: FrameParams.qmc, qmc_index, qmc_key.

A still render's frames are averaged, so the error of the mean falls faster than 1/n where the light-sample
dimensions are stratified across the frames; an animation's frames are not averaged (TAA blends a few, ReSTIR
reuses reservoirs), so `auto` keeps their independent random numbers. The two half buffers of a still render
(render/still.py) each get their own key and their own index count: two independent randomised QMC estimates, whose
difference is still an honest error estimate.
"""

from __future__ import annotations

from ..settings.table import Settings

#: FrameParams (qmc, qmc_index, qmc_key) of a frame that draws random numbers
OFF = (0, 0, 0)
#: bits of FrameParams.qmc (opencl/codes.h QMC_*): the RIS sample draws from the pixel's sequence; so does the camera
#: ray's place in its pixel (opencl/camera/jitter.h: still renders with pixel jitter, jointly with the first light
#: candidate, sampling/qmc.h QMC_CAMERA)
ON = 1
PIXEL_JITTER = 2


def still_uses_sobol(settings: Settings) -> bool:
    """Whether a still render with `settings` (as resolved by still_settings) draws from the Sobol sequence:
    `auto` and `sobol` do for RIS (the still method of every scene kind), `random` never."""
    return settings.sampler in ("auto", "sobol") and settings.method == "ris"


def environment_table(settings: Settings) -> str | None:
    """The environment's sampling table for a renderer with `settings` (lights/environment.py): the cumulative
    one where still renders draw from the Sobol sequence, since inverting it keeps the strata of the point's two
    dimensions, which an alias draw scatters (measured on F12's sky path: docs/measurements/error-vs-time.md, "A
    world alone: one candidate"); None, the default table, elsewhere."""
    return "cdf" if still_uses_sobol(settings) else None


def frames_use_sobol(settings: Settings) -> bool:
    """Whether animation and viewport frames draw from it: only with `sobol` and RIS (index: the frame count)."""
    return settings.sampler == "sobol" and settings.method == "ris"


def still_flags(settings: Settings) -> int:
    """FrameParams.qmc of a still render's frames with `settings` (where still_uses_sobol): the pixel jitter too
    where Settings.jitter is on."""
    return ON | (PIXEL_JITTER if settings.jitter else 0)


def still_key(seed: int, half: int) -> int:
    """The scramble key of half buffer `half` (0, 1) of a still render with Settings.seed `seed`."""
    return ((seed * 0x9E3779B1) ^ (0x68E31DA4 + half * 0x5BD1E995)) & 0xFFFFFFFF
