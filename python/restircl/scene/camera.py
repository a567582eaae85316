"""The scene's camera as Blender describes it: transforms per frame, lens and sensor, shift, perspective or
orthographic, and the frames at which the animation cuts."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .errors import SceneError
from .transforms import as_transforms, check_basis

MAX_RESOLUTION = 16384


SENSOR_FITS = ("AUTO", "HORIZONTAL", "VERTICAL")


CAMERA_TYPES = ("PERSP", "ORTHO")  # Blender's camera types; Camera.kind on the device is the index (CAMERA_*)


@dataclass
class Camera:
    transforms: np.ndarray | None = None  # (4, 4) or (F, 4, 4) camera-to-world; looks along -Z
    width: int = 640
    height: int = 360
    lens: float = 50.0  # focal length (mm)
    sensor_width: float = 36.0
    sensor_height: float = 24.0
    sensor_fit: str = "AUTO"
    shift_x: float = 0.0
    shift_y: float = 0.0
    cuts: tuple[int, ...] = ()  # frames at which the camera cuts (history is reset)
    type: str = "PERSP"  # Blender's camera type: PERSP or ORTHO
    ortho_scale: float = 6.0  # ORTHO: the view's extent (world units) along the fitted axis, as in Blender
    # depth of field, a thin lens (opencl/camera/lens.h): 0 is a pinhole
    aperture_radius: float = 0.0  # world units; Blender's F-stop gives focal length / (2 F-stop)
    focus_distance: float = 10.0  # from the camera to the plane in focus, along its view axis (world units)
    aperture_blades: int = 0  # a regular polygon of this many corners; below 3 a disc
    aperture_rotation: float = 0.0  # radians: the polygon's turn
    aperture_ratio: float = 1.0  # anamorphic: the aperture's height over its width
    # motion blur (render/shutter.py): the shutter is open from shutter[0] to shutter[1] frames (the scene's
    # frames) after the rendered frame; equal: no blur
    shutter: tuple[float, float] = (0.0, 0.0)
    focus_per_frame: np.ndarray | None = None  # optional (F,) focus distance per frame (a focus pull)

    def __post_init__(self) -> None:
        self.transforms = as_transforms(self.transforms, "camera")
        self.cuts = tuple(int(c) for c in self.cuts)
        self.shutter = (float(self.shutter[0]), float(self.shutter[1]))

    def set_fov(self, fov: float, axis: str = "horizontal") -> None:
        """Set the field of view (radians) along an axis by choosing the focal length; sensor fit follows."""
        if axis == "horizontal":
            self.sensor_fit = "HORIZONTAL"
            self.lens = self.sensor_width / (2.0 * math.tan(fov / 2.0))
        else:
            self.sensor_fit = "VERTICAL"
            self.lens = self.sensor_height / (2.0 * math.tan(fov / 2.0))

    def tan_half_fov(self) -> tuple[float, float, float, float]:
        """(tan half horizontal fov, tan half vertical fov, shift x, shift y in tan units), Blender's rules; an
        orthographic camera's view plane instead (view_plane)."""
        return self.view_plane()

    def view_plane(self) -> tuple[float, float, float, float]:
        """Half the view plane (x, y) and its shift (x, y), Blender's rules: in tan units at unit distance for a
        perspective camera, in world units for an orthographic one."""
        w, h = float(self.width), float(self.height)
        fit = self.sensor_fit
        if fit == "AUTO":
            fit = "HORIZONTAL" if w >= h else "VERTICAL"
            sensor = self.sensor_width
        else:
            sensor = self.sensor_width if fit == "HORIZONTAL" else self.sensor_height
        # half the fitted dimension: the tan of half its fov, or half the orthographic scale
        half = 0.5 * self.ortho_scale if self.type == "ORTHO" else 0.5 * sensor / self.lens
        if fit == "HORIZONTAL":
            tx, ty = half, half * h / w
        else:
            tx, ty = half * w / h, half
        # Blender's shift is a fraction of the fitted dimension of the view plane (checked against Blender's
        # own projection by tests/test_blender_camera.py).
        return tx, ty, 2.0 * self.shift_x * half, 2.0 * self.shift_y * half

    def region(self, x0: int, y0: int, x1: int, y1: int) -> Camera:
        """The camera that sees exactly pixels [x0, x1) x [y0, y1) of this one (rows from the top), at the same
        pixel size: a render region. Its view plane is that part of this camera's, expressed by Blender's own
        parameters (fit to its width, a focal length or orthographic scale, a shift), so nothing downstream knows
        it is a part: the rays of its pixels are this camera's rays of the same pixels."""
        w, h = int(self.width), int(self.height)
        if not (0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h):
            raise SceneError(f"camera: region [{x0}, {x1}) x [{y0}, {y1}) is empty or outside {w} x {h}")
        tx, ty, sx, sy = self.view_plane()
        half = tx * (x1 - x0) / w  # the region's half width on the plane
        cx = sx + tx * ((x0 + x1) / w - 1.0)  # its centre, from this camera's axis
        cy = sy + ty * (1.0 - (y0 + y1) / h)
        out = replace(self, width=x1 - x0, height=y1 - y0, sensor_fit="HORIZONTAL", shift_x=cx / (2.0 * half),
                      shift_y=cy / (2.0 * half))
        if self.type == "ORTHO":
            out.ortho_scale = 2.0 * half
        else:
            out.lens = 0.5 * self.sensor_width / half
        return out

    def validate(self) -> None:
        """Raise SceneError naming the bad field."""
        # attributes may have been replaced after construction: normalise their shapes again
        self.transforms = as_transforms(self.transforms, "camera")
        for what, v in (("width", self.width), ("height", self.height)):
            if not isinstance(v, (int, np.integer)) or not 1 <= int(v) <= MAX_RESOLUTION:
                raise SceneError(f"camera: {what} must be an integer in 1..{MAX_RESOLUTION}, got {v!r}")
        if not np.all(np.isfinite(self.transforms)):
            raise SceneError("camera: transform contains NaN or Inf")
        for what, v in (("lens", self.lens), ("sensor_width", self.sensor_width),
                        ("sensor_height", self.sensor_height)):
            if not math.isfinite(v) or v <= 0:
                raise SceneError(f"camera: {what} must be finite and positive, got {v!r}")
        if not (math.isfinite(self.shift_x) and math.isfinite(self.shift_y)):
            raise SceneError("camera: shift is not finite")
        if self.type not in CAMERA_TYPES:
            raise SceneError(f"camera: type must be one of {CAMERA_TYPES}, got {self.type!r}")
        if self.type == "ORTHO" and not (math.isfinite(self.ortho_scale) and self.ortho_scale > 0):
            raise SceneError(f"camera: ortho_scale must be finite and positive, got {self.ortho_scale!r}")
        if self.sensor_fit not in SENSOR_FITS:
            raise SceneError(f"camera: sensor_fit must be one of {SENSOR_FITS}, got {self.sensor_fit!r}")
        check_basis(self.transforms, "camera")
        self._validate_lens()

    def focus_at(self, frame: float) -> float:
        """The focus distance at `frame` (a time between frames: its frame's)."""
        if self.focus_per_frame is None or len(self.focus_per_frame) == 0:
            return float(self.focus_distance)
        return float(self.focus_per_frame[min(max(int(frame), 0), len(self.focus_per_frame) - 1)])

    @property
    def has_dof(self) -> bool:
        """Whether the camera has an aperture (depth of field); a pinhole compiles no lens code."""
        return self.aperture_radius > 0.0

    def _validate_lens(self) -> None:
        r = self.aperture_radius
        if not (math.isfinite(r) and r >= 0):
            raise SceneError(f"camera: aperture_radius must be finite and >= 0, got {r!r}")
        focus = [] if self.focus_per_frame is None else [float(f) for f in np.asarray(self.focus_per_frame).ravel()]
        for what, v in (("focus_distance", self.focus_distance), ("aperture_ratio", self.aperture_ratio),
                        *(("focus_per_frame", f) for f in focus)):
            if not (math.isfinite(v) and v > 0):
                raise SceneError(f"camera: {what} must be finite and positive, got {v!r}")
        if not isinstance(self.aperture_blades, (int, np.integer)) or not 0 <= int(self.aperture_blades) <= 64:
            raise SceneError(f"camera: aperture_blades must be an integer in 0..64, got {self.aperture_blades!r}")
        if not math.isfinite(self.aperture_rotation):
            raise SceneError("camera: aperture_rotation is not finite")
        a, b = self.shutter
        if not (math.isfinite(a) and math.isfinite(b) and a <= b):
            raise SceneError(f"camera: shutter must be finite (open, close) with open <= close, got {self.shutter!r}")
