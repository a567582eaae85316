"""The Blender camera -> restircl.Camera: a perspective or orthographic projection with Blender's sensor fit and
shift, its depth of field (a thin lens), its motion per sampled frame, and cuts where timeline markers switch to
another camera."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .convert import matrix
from .motion import Frames, fill_gaps, transforms
from .report import ExportError


def render_resolution(scene) -> tuple[int, int]:
    r = scene.render
    return (max(1, int(r.resolution_x * r.resolution_percentage / 100)),
            max(1, int(r.resolution_y * r.resolution_percentage / 100)))


class CameraReader:
    """The render camera at the current frame (`read`), then at the other frames (`sample`). `override` (an
    evaluated camera object) replaces the scene camera at every frame."""

    def __init__(self, frames: Frames, override=None):
        self.frames = frames
        self.override = override
        self._params: dict = {}
        self._track: list = []  # camera-to-world matrix per sampled frame
        self._names: list = []  # the camera object seen at each sampled frame
        self._focus: list = []  # the focus distance at each sampled frame (depth of field)

    def read(self, scene, warn: Callable[[str], None]) -> None:
        cam_obj = self.override if self.override is not None else scene.camera
        if cam_obj is None:
            raise ExportError("the scene has no camera; add one and make it the active camera")
        self._params = _camera_params(cam_obj, scene, warn)
        self._track = self.frames.track(_orthonormal(matrix(cam_obj.matrix_world)))
        self._names = self.frames.track(cam_obj.name)
        self._focus = self.frames.track(self._params.get("focus_distance"))

    def sample(self, scene, k: int) -> None:
        cam = self.override if self.override is not None else scene.camera
        if cam is not None:
            self._track[k] = _orthonormal(matrix(cam.matrix_world))
            self._names[k] = cam.name
            if self._focus[self.frames.current_index] is not None:
                self._focus[k] = _focus_distance(cam)

    def build(self):
        import restircl

        fill_gaps(self._track)
        fill_gaps(self._names)
        cuts = tuple(i for i in range(1, self.frames.count) if self._names[i] != self._names[i - 1])
        params = dict(self._params)
        if self._focus[self.frames.current_index] is not None:
            fill_gaps(self._focus)
            if any(f != self._focus[0] for f in self._focus):  # a focus pull
                params["focus_per_frame"] = np.asarray(self._focus, np.float64)
        return restircl.Camera(transforms=transforms(self._track), cuts=cuts, **params)


def _orthonormal(m: np.ndarray) -> np.ndarray:
    """Drop scale (and shear) from an object matrix, keeping its rotation, mirroring and position."""
    out = np.array(m, dtype=np.float64)
    for i in range(3):
        n = np.linalg.norm(out[:3, i])
        if n > 0 and np.isfinite(n):
            out[:3, i] /= n
    return out


def _camera_params(cam_obj, scene, warn: Callable[[str], None]) -> dict:
    cd = cam_obj.data
    if cd.type not in ("PERSP", "ORTHO"):
        kind = {"PANO": "panoramic"}.get(cd.type, cd.type.lower())
        raise ExportError(f"camera {cam_obj.name!r}: {kind} cameras are not supported; use a perspective or "
                          "orthographic camera")
    w, h = render_resolution(scene)
    r = scene.render
    if abs(r.pixel_aspect_x - r.pixel_aspect_y) > 1e-6:
        warn("non-square pixel aspect is rendered with square pixels")
    return {**lens_params(cam_obj, warn),
        "width": w, "height": h, "lens": float(cd.lens), "sensor_width": float(cd.sensor_width),
        "sensor_height": float(cd.sensor_height), "sensor_fit": cd.sensor_fit,
        "shift_x": float(cd.shift_x), "shift_y": float(cd.shift_y), "type": cd.type,
        "ortho_scale": float(cd.ortho_scale),
    }


def lens_params(cam_obj, warn: Callable[[str], None]) -> dict:
    """Depth of field as Cycles reads Blender's camera: an aperture of radius focal length / (2 F-stop) (metres:
    the focal length is in mm; 1 / (2 F-stop) for an orthographic camera), focused at the distance along the view
    axis to the focus object's origin, else at Focus Distance."""
    dof = getattr(cam_obj.data, "dof", None)
    if dof is None or not dof.use_dof:
        return {}
    cd = cam_obj.data
    fstop = max(float(dof.aperture_fstop), 1e-5)
    radius = 1.0 / (2.0 * fstop) if cd.type == "ORTHO" else float(cd.lens) * 1e-3 / (2.0 * fstop)
    if dof.focus_object is not None and getattr(dof, "focus_subtarget", ""):
        warn(f"camera {cam_obj.name!r}: the focus bone {dof.focus_subtarget!r} is not read; focusing on the "
             "object's origin")
    return {"aperture_radius": radius, "focus_distance": _focus_distance(cam_obj),
            "aperture_blades": int(dof.aperture_blades), "aperture_rotation": float(dof.aperture_rotation),
            "aperture_ratio": max(float(dof.aperture_ratio), 1e-5)}


def _focus_distance(cam_obj) -> float:
    """The distance along the camera's view axis to its focus object's origin, else its Focus Distance."""
    dof = cam_obj.data.dof
    focus = float(dof.focus_distance)
    if dof.focus_object is not None:
        m = np.asarray(cam_obj.matrix_world, dtype=np.float64)
        target = np.asarray(dof.focus_object.matrix_world.translation, dtype=np.float64)
        axis = m[:3, 2] / max(float(np.linalg.norm(m[:3, 2])), 1e-30)
        focus = abs(float(np.dot(axis, m[:3, 3] - target)))
    return max(focus, 1e-5)
