"""4x4 object-to-world transforms: their shapes normalised to (F, 4, 4), the helpers that build them, and the
singular-basis check."""

from __future__ import annotations

import numpy as np

from .errors import SceneError


def as_transforms(value: np.ndarray | None, what: str) -> np.ndarray:
    if value is None:
        return np.eye(4, dtype=np.float64)[None]
    m = np.asarray(value, dtype=np.float64)
    if m.shape == (4, 4):
        m = m[None]
    if m.ndim != 3 or m.shape[1:] != (4, 4) or m.shape[0] < 1:
        raise SceneError(f"{what}: transforms must have shape (4, 4) or (F, 4, 4), got {m.shape}")
    return m


def translation(x: float, y: float, z: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def look_at(eye: np.ndarray | tuple, target: np.ndarray | tuple, up: tuple = (0.0, 0.0, 1.0)) -> np.ndarray:
    """A Blender-style object matrix at `eye` whose -Z axis points at `target` (for cameras and lights)."""
    eye = np.asarray(eye, dtype=np.float64)
    fwd = np.asarray(target, dtype=np.float64) - eye
    n = np.linalg.norm(fwd)
    if not np.isfinite(n) or n == 0:
        raise SceneError("look_at: eye and target coincide or are not finite")
    fwd /= n
    upv = np.asarray(up, dtype=np.float64)
    right = np.cross(fwd, upv)
    if np.linalg.norm(right) < 1e-9:
        right = np.cross(fwd, np.array([0.0, 1.0, 0.0]) if abs(fwd[1]) < 0.9 else np.array([1.0, 0.0, 0.0]))
    right /= np.linalg.norm(right)
    true_up = np.cross(right, fwd)
    m = np.eye(4)
    m[:3, 0] = right
    m[:3, 1] = true_up
    m[:3, 2] = -fwd
    m[:3, 3] = eye
    return m


def check_basis(transforms: np.ndarray, label: str) -> None:
    det = np.linalg.det(transforms[:, :3, :3])
    if np.any(~np.isfinite(det)) or np.any(np.abs(det) < 1e-30):
        raise SceneError(f"{label}: transform is singular (zero scale)")
