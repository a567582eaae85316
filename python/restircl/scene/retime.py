"""A scene's animation cut into more frames along the same motion: `retime(scene, k)` has frame j at time j/k of the
original frames (frame f of the original is frame f*k), so a renderer that is k times faster per frame can be
compared at equal wall time along the same camera path (a higher frame rate), as a real-time renderer would use it.

Transforms are interpolated per component: translation linearly, rotation by quaternion slerp, the remaining
stretch (polar decomposition M = R S) linearly; per-frame light powers and world strengths linearly; camera cuts
move to their new frame numbers.
"""

from __future__ import annotations

import copy

import numpy as np

from .scene import Scene


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


def retime_transforms(transforms: np.ndarray, k: int, frames: int, cuts: tuple[int, ...] = ()) -> np.ndarray:
    """(F, 4, 4) per-frame transforms (the last held beyond F) at k sub-frames per frame: (frames-1)*k+1 of them.
    Before a cut (a frame in `cuts`) the sub-frames hold the previous frame's transform: a cut is no motion."""
    if transforms.shape[0] == 1:
        return transforms
    n = (frames - 1) * k + 1
    out = np.empty((n, 4, 4), transforms.dtype)
    last = transforms.shape[0] - 1
    for j in range(n):
        f, r = divmod(j, k)
        a, b = transforms[min(f, last)], transforms[min(f + 1, last)]
        out[j] = a if r == 0 or f + 1 in cuts else interpolate_transform(a, b, r / k)
    return out


def retime_values(values: np.ndarray, k: int, frames: int) -> np.ndarray:
    """(F,) per-frame values (the last held beyond F), linearly interpolated at k sub-frames per frame."""
    t = np.arange((frames - 1) * k + 1) / k
    return np.interp(t, np.arange(len(values)), values).astype(values.dtype)


def retime(scene: Scene, k: int) -> Scene:
    """A copy of `scene` whose animation has k frames for each of the original's (frame f there is f*k here)."""
    if k < 1:
        raise ValueError(f"retime: k must be at least 1, got {k}")
    out = copy.deepcopy(scene)
    if k == 1:
        return out
    n = scene.frames
    cam = out.camera
    assert cam is not None
    cam.transforms = retime_transforms(cam.transforms, k, n, cam.cuts)
    cam.cuts = tuple(c * k for c in cam.cuts)
    for obj in [*out.meshes, *out.lights]:
        obj.transforms = retime_transforms(obj.transforms, k, n)
    for lt in out.lights:
        if lt.power_per_frame is not None and len(lt.power_per_frame) > 1:
            lt.power_per_frame = retime_values(lt.power_per_frame, k, n)
    env = out.environment
    if env is not None and env.strength_per_frame is not None and len(env.strength_per_frame) > 1:
        env.strength_per_frame = retime_values(np.asarray(env.strength_per_frame, np.float64), k, n)
    if out.frame_count is not None:
        out.frame_count = (int(out.frame_count) - 1) * k + 1
    return out.validate()
