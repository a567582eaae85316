"""Blender values (mathutils matrices, colour properties) as numpy arrays and plain tuples."""

from __future__ import annotations

import numpy as np


def matrix(m) -> np.ndarray:
    return np.array([list(row) for row in m], dtype=np.float64)


def rgb(v) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))
