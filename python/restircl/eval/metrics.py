"""Error metrics of an image against its reference, shared by the report and the benchmarks."""

from __future__ import annotations

import warnings

import numpy as np


def _rel_se(x: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """(x - r)^2 / (r^2 + 0.01) per pixel and colour channel (alpha left out), in float64."""
    x = np.asarray(x, dtype=np.float64)[..., :3]
    ref = np.asarray(ref, dtype=np.float64)[..., :3]
    return (x - ref) ** 2 / (ref * ref + 0.01)


def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    """mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)."""
    return float(np.mean(_rel_se(x, ref)))


def rel_mse_map(x: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """(H, W) relMSE term of each pixel: (x - r)^2 / (r^2 + 0.01) averaged over the colour channels; rel_mse is the
    mean of this map, which says where an image's error lies."""
    return np.mean(_rel_se(x, ref), axis=-1)


def rmse(x: np.ndarray, ref: np.ndarray) -> float:
    x = np.asarray(x, dtype=np.float64)[..., :3]
    ref = np.asarray(ref, dtype=np.float64)[..., :3]
    return float(np.sqrt(np.mean((x - ref) ** 2)))


FLIP_MISSING = ("FLIP not measured: flip-evaluator is not installed (pip install flip-evaluator, or restircl's "
                "'bench' or 'test' extra)")


def flip_available() -> bool:
    """Whether flip-evaluator imports (the FLIP columns of the reports are empty without it)."""
    try:
        import flip_evaluator  # type: ignore[import-not-found]  # noqa: F401
    except ImportError:
        return False
    return True


def flip(x: np.ndarray, ref: np.ndarray) -> float | None:
    """Mean FLIP (HDR) when `flip-evaluator` is installed, else None (the reports then say FLIP_MISSING)."""
    try:
        import flip_evaluator as flip_mod  # type: ignore[import-not-found]
    except ImportError:
        return None
    try:
        _, mean, _ = flip_mod.evaluate(ref[..., :3].astype(np.float32), x[..., :3].astype(np.float32), "HDR")
        return float(mean)
    except Exception as e:  # a FLIP failure must not lose a report's other figures
        warnings.warn(f"FLIP failed on a {x.shape} image: {e}", stacklevel=2)
        return None
