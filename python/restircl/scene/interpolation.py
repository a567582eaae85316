"""A transform between two of its frames: translation and the stretch (polar decomposition M = R S) linearly,
rotation by quaternion slerp along the shorter arc, so that an object that turns or moves steadily from frame to
frame is where it is at that time; motion that bends within a frame is followed only at the frames. Retiming
(scene/retime.py) and motion blur's times within the shutter (Scene.at, render/shutter.py) both use it."""

from __future__ import annotations

import math

import numpy as np


def _quat(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method: the largest component first)."""
    t = np.trace(r)
    d = np.array([t, r[0, 0], r[1, 1], r[2, 2]])
    i = int(np.argmax(d))
    if i == 0:
        w = np.sqrt(max(1.0 + t, 0.0)) / 2.0
        q = np.array([w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)])
    else:
        j, k = (i % 3) + 1, ((i + 1) % 3) + 1
        a, b, c = i - 1, j - 1, k - 1
        s = np.sqrt(max(1.0 + r[a, a] - r[b, b] - r[c, c], 0.0)) * 2.0
        q = np.empty(4)
        q[0] = (r[c, b] - r[b, c]) / s
        q[i] = s / 4.0
        q[j] = (r[b, a] + r[a, b]) / s
        q[k] = (r[c, a] + r[a, c]) / s
    return q / np.linalg.norm(q)


def _matrix(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def _slerp(a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
    d = float(np.dot(a, b))
    if d < 0.0:  # the shorter way round
        b, d = -b, -d
    if d > 0.9995:
        q = a + t * (b - a)
        return q / np.linalg.norm(q)
    th = np.arccos(min(d, 1.0))
    return (np.sin((1 - t) * th) * a + np.sin(t * th) * b) / np.sin(th)


def _polar(m3: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """M = R S with R a rotation (det +1) and S symmetric (the stretch, a reflection folded into it)."""
    u, s, vt = np.linalg.svd(m3)
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] = -u[:, -1]
        s = s.copy()
        s[-1] = -s[-1]
        r = u @ vt
    return r, vt.T @ np.diag(s) @ vt


def interpolate_transform(a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
    """The 4x4 affine transform a fraction t of the way from a to b."""
    if np.array_equal(a, b):
        return a.copy()
    ra, sa = _polar(a[:3, :3].astype(np.float64))
    rb, sb = _polar(b[:3, :3].astype(np.float64))
    out = np.eye(4)
    out[:3, :3] = _matrix(_slerp(_quat(ra), _quat(rb), t)) @ ((1 - t) * sa + t * sb)
    out[:3, 3] = (1 - t) * a[:3, 3].astype(np.float64) + t * b[:3, 3].astype(np.float64)
    return out.astype(a.dtype)


def transform_at(transforms: np.ndarray, frame: float) -> np.ndarray:
    """The (4, 4) transform of (F, 4, 4) `transforms` at `frame`, clamped to the frames there are; a whole frame
    is that frame's matrix itself."""
    last = transforms.shape[0] - 1
    if float(frame) == int(frame):
        return transforms[min(max(int(frame), 0), last)]
    lo = math.floor(frame)
    a = transforms[min(max(lo, 0), last)]
    b = transforms[min(max(lo + 1, 0), last)]
    if lo < 0 or lo >= last or np.array_equal(a, b):
        return a
    return interpolate_transform(a, b, float(frame) - lo)
