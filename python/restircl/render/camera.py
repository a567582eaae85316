"""Scene camera -> device Camera record (opencl/types.h), the Halton (2, 3) sub-pixel jitter sequence, and whether
the camera moved between two frames."""

from __future__ import annotations

import numpy as np

from ..core import layouts as L
from ..scene.camera import CAMERA_TYPES, Camera
from ..scene.scene import Scene


def halton(index: int, base: int) -> float:
    f, r, i = 1.0, 0.0, index
    while i > 0:
        f /= base
        r += f * (i % base)
        i //= base
    return r


def jitter(frame: int) -> tuple[float, float]:
    """Sub-pixel offset in [-0.5, 0.5)^2 for `frame` (Halton 2, 3; cycles every 1024 frames)."""
    k = frame % 1024 + 1
    return halton(k, 2) - 0.5, halton(k, 3) - 0.5


GOLDEN = 0.6180339887498949  # frac of the golden ratio: the most even 1D sequence over consecutive indices


def camera_sequence(sample: int, seed: int) -> float:
    """The frame's point in [0, 1) of a golden-ratio sequence over the sample index, shifted by the seed: it
    stratifies the camera rays' choice at the first transparent surface over the frames of animations and of the
    random sampler's stills (camera/coverage_number.h; stills from the Sobol sequence take the pixel's own)."""
    v = (sample * GOLDEN + (seed * 0.41421356237309503) % 1.0) % 1.0
    return float(np.nextafter(np.float32(1.0), np.float32(0.0))) if np.float32(v) >= 1.0 else v


def camera_record(cam: Camera, frame: int, jitter_px: tuple[float, float] = (0.0, 0.0),
                  texture_full: bool = False, sequence: float = 0.0) -> np.ndarray:
    """texture_full: the camera's rays read images at full resolution (render/plan.py texture_full). sequence: the
    frame's point of camera_sequence (jitter.z)."""
    m = Scene.at(cam.transforms, frame)
    right = m[:3, 0] / np.linalg.norm(m[:3, 0])
    fwd = -m[:3, 2] / np.linalg.norm(m[:3, 2])
    up = np.cross(right, fwd)
    up /= np.linalg.norm(up)
    right = np.cross(fwd, up)
    rec = np.zeros(1, L.CAMERA)
    rec["origin"][0, :3] = m[:3, 3]
    rec["right"][0, :3] = right
    rec["up"][0, :3] = up
    rec["forward"][0, :3] = fwd
    rec["lens"][0] = cam.view_plane()
    rec["kind"] = CAMERA_TYPES.index(cam.type)
    rec["jitter"][0, :2] = jitter_px
    rec["jitter"][0, 2] = sequence
    rec["width"] = cam.width
    rec["height"] = cam.height
    rec["texture_full"] = int(texture_full)
    rec["aperture"][0] = (cam.aperture_radius, cam.aperture_ratio, float(cam.aperture_blades), cam.aperture_rotation)
    rec["focus"][0, 0] = cam.focus_at(frame)
    return rec


def views_differ(a: Camera, b: Camera, frame: int = 0) -> bool:
    """Whether two cameras see the scene differently at `frame` (transform, lens, shift, kind or size)."""
    return camera_record(a, frame).tobytes() != camera_record(b, frame).tobytes()


def camera_moved(cam: Camera, frame: int, last_frame: int | None, last_view: Camera | None = None) -> bool:
    """Whether `cam` at `frame` sees the scene from elsewhere than the last frame did: `last_view` (an interactive
    view's last camera) against `cam`, else `cam`'s transform at `last_frame` against the one at `frame`."""
    if last_view is not None:
        return views_differ(last_view, cam)
    return last_frame is not None and not np.array_equal(Scene.at(cam.transforms, last_frame),
                                                         Scene.at(cam.transforms, frame))
