"""The interactive viewport's session: frames of the current 3D view rendered continuously on a worker thread.

Blender calls view_update and view_draw on its main thread; they hand this session the view (a restircl.Camera
made by `view_camera` from the 3D view's matrices) and scene edits (`SceneEdit`), and take the newest frame
(`latest`). Everything else, the OpenCL work and the Python around it, runs on the worker, so the UI never waits
for a frame. Nothing here imports bpy: tests drive the session with the matrices a 3D view would give.

The policy, the lecture's real-time case: every view change is a new camera transform of one animation, so the
ReSTIR reservoirs and the TAA colour history are reprojected through the motion (Renderer.render_view) instead of
restarting as Cycles' viewport does; a cut-like jump (a numpad view, a teleport) drops them. While the view stays
still the frames are averaged (the TAA blend becomes 1/n, as in a still render) until `samples` frames, then the
worker sleeps until the view or the scene changes.
"""

from __future__ import annotations

import math
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np
from restircl import Camera, DeviceError, KernelBuildError, Renderer, Scene, Settings
from restircl.render.camera import views_differ

from .viewport_edit import SceneEdit, apply_edit


def view_camera(view_matrix, window_matrix, width: int, height: int, ortho_back: float = 0.0,
                thin_lens: dict | None = None) -> Camera:
    """The restircl.Camera of a 3D view: `view_matrix` (world to view) and `window_matrix` (the projection, as
    Blender's RegionView3D has them; they already hold the camera view's zoom and offset) for an image of
    width x height. An orthographic view sees in front of and behind its origin (Blender clips it at
    +-clip_end / 2): its rays start `ortho_back` behind it. `thin_lens`: the Camera fields of a thin lens
    (aperture_radius, focus_distance, ...; viewport_lens.view_lens), none for a pinhole."""
    thin = dict(thin_lens or {})
    v = np.asarray(view_matrix, np.float64).reshape(4, 4)
    p = np.asarray(window_matrix, np.float64).reshape(4, 4)
    to_world = np.linalg.inv(v)
    half_x = 1.0 / p[0, 0]
    if p[3, 3] == 0.0:  # perspective: x_ndc = p00 x / -z + p02 at z = -1, so the plane's x = (x_ndc + p02) / p00
        return Camera(to_world, int(width), int(height), lens=18.0 / half_x, sensor_width=36.0,
                      sensor_fit="HORIZONTAL", shift_x=0.5 * p[0, 2],
                      shift_y=0.5 * p[1, 2] / p[1, 1] / half_x, **thin)
    scale = 2.0 * half_x  # orthographic: x_ndc = p00 x + p03
    to_world[:3, 3] += to_world[:3, 2] * ortho_back  # the view looks along -Z: back is +Z
    return Camera(to_world, int(width), int(height), type="ORTHO", ortho_scale=scale, sensor_fit="HORIZONTAL",
                  shift_x=-p[0, 3] / p[0, 0] / scale, shift_y=-p[1, 3] / p[1, 1] / scale, **thin)


def scaled_size(width: int, height: int, pixel_size: int) -> tuple[int, int]:
    """The render size of a region of width x height at a pixel size (Cycles' Pixel Size: 2 renders a quarter
    of the pixels)."""
    ps = max(1, int(pixel_size))
    return max(1, round(width / ps)), max(1, round(height / ps))


def is_jump(a: Camera, b: Camera, scene_size: float, max_angle: float = 30.0, max_move: float = 0.25) -> bool:
    """A cut-like view change, after which the history is of no use: the view turned by more than `max_angle`
    degrees or moved by more than `max_move` times the scene's size in one frame (numpad views, view-all). An
    orbit or a walk at interactive frame rates turns by a few degrees a frame."""
    ma, mb = a.transforms[0], b.transforms[0]
    ra = ma[:3, :3] / np.linalg.norm(ma[:3, :3], axis=0)
    rb = mb[:3, :3] / np.linalg.norm(mb[:3, :3], axis=0)
    cos = np.clip((np.trace(ra.T @ rb) - 1.0) / 2.0, -1.0, 1.0)
    moved = float(np.linalg.norm(ma[:3, 3] - mb[:3, 3]))
    return math.degrees(math.acos(cos)) > max_angle or moved > max_move * max(scene_size, 1e-6)


def scene_bounds(scene: Scene) -> np.ndarray | None:
    """(2, 3) corners of the bounding box of the scene's triangles at frame 0 (None for an empty scene)."""
    tris = scene.world_triangles(0)
    if len(tris) == 0:
        return None
    pts = np.concatenate([tris.v0, tris.v1, tris.v2])
    return np.stack([pts.min(0), pts.max(0)])


def fit_ortho(camera: Camera, bounds: np.ndarray | None) -> Camera:
    """An orthographic view whose rays start just before the scene's bounding box instead of far behind it (never
    further forward than that): the same image, but view depths measured from near the scene, so that the
    relative depth test of reprojection keeps its meaning."""
    if camera.type != "ORTHO" or bounds is None:
        return camera
    m = np.array(camera.transforms[0])
    forward = -m[:3, 2] / np.linalg.norm(m[:3, 2])
    corners = np.array([[bounds[i, 0], bounds[j, 1], bounds[k, 2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    ahead = float(((corners - m[:3, 3]) @ forward).min())
    margin = 1e-3 * float(np.linalg.norm(bounds[1] - bounds[0])) + 1e-3
    if ahead - margin <= 0.0:
        return camera
    m[:3, 3] += forward * (ahead - margin)
    return replace(camera, transforms=m)


@dataclass
class ViewFrame:
    """The newest frame for view_draw."""

    rgba: np.ndarray  # (H, W, 4) float32, row 0 at the bottom (a GPU texture's order), finite
    samples: int  # frames since the view or the scene last changed
    ms: float  # the frame's time on the worker (render and read-back)
    index: int  # frames rendered by this session
    cut: bool  # this frame started without history
    history: float | None = None  # mean TAA history length (track_history only)


@dataclass
class SessionStats:
    frames: int = 0
    cuts: int = 0
    rebuilds: int = 0
    edits: dict[str, int] = field(default_factory=dict)  # apply_edit's outcome -> count


class ViewportSession:
    """Renders the current view of `scene` continuously on a worker thread (start(), then set_view / edit from
    the main thread, latest() to draw, stop() to end). on_frame() is called from the worker after each frame
    (the add-on's tag_redraw); it must not touch bpy data."""

    def __init__(self, scene: Scene, settings: Settings | None = None, device=None, *, samples: int = 128,
                 on_frame: Callable[[], None] | None = None, jump_angle: float = 30.0, jump_move: float = 0.25,
                 track_history: bool = False) -> None:
        self.scene = scene
        self.settings = replace(settings or Settings())  # our own copy: a still view changes its TAA blend
        self._alpha_min = self.settings.alpha_min
        self.device = device
        self.sample_limit = max(1, int(samples))
        self.on_frame = on_frame or (lambda: None)
        self.jump_angle, self.jump_move = jump_angle, jump_move
        self.track_history = track_history
        self.renderer: Renderer | None = None
        self.device_label = ""
        self.stats = SessionStats()
        self.error: str | None = None
        self._bounds: np.ndarray | None = None
        self._scene_size = 1.0
        self._view: Camera | None = None
        self._shown: Camera | None = None  # the last rendered view as it was asked for
        self._shown_fitted: Camera | None = None  # ... and as it was rendered (fit_ortho)
        self._edits: list[SceneEdit] = []
        self._samples = 0
        self._latest: ViewFrame | None = None
        self._stop = False
        self._cond = threading.Condition()
        self._thread = threading.Thread(target=self._run, name="restircl-viewport", daemon=True)

    # ---- the main thread's side ------------------------------------------------------------------------

    def start(self) -> ViewportSession:
        self._thread.start()
        return self

    def set_view(self, camera: Camera) -> None:
        with self._cond:
            self._view = camera
            self._cond.notify_all()

    def edit(self, edit: SceneEdit) -> None:
        with self._cond:
            self._edits.append(edit)
            self._cond.notify_all()

    def latest(self) -> ViewFrame | None:
        with self._cond:
            return self._latest

    def wait(self, index: int, timeout: float = 120.0) -> ViewFrame | None:
        """Block until frame `index` (ViewFrame.index) or a later one is out, the worker failed or stopped, or
        `timeout` seconds passed; the newest frame (for tests and tools, never for the UI thread)."""
        end = time.monotonic() + timeout
        with self._cond:
            while ((self._latest is None or self._latest.index < index) and self.error is None
                   and self._thread.is_alive()):
                left = end - time.monotonic()
                if left <= 0:
                    break
                self._cond.wait(left)
            return self._latest

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    def status_text(self) -> str:
        """The viewport header's text: samples, ms per frame, device."""
        if self.error is not None:
            return f"restircl | error: {self.error}"
        f = self.latest()
        if f is None:
            return "restircl | starting"
        state = "done" if f.samples >= self.sample_limit else "rendering"
        return (f"restircl | sample {f.samples}/{self.sample_limit} ({state}) | {f.ms:.0f} ms/frame | "
                f"{f.rgba.shape[1]}x{f.rgba.shape[0]} | {self.device_label}")

    def stop(self, timeout: float = 30.0) -> bool:
        """End the worker (after its frame in flight) and wait for it; True when it has stopped."""
        with self._cond:
            self._stop = True
            self._cond.notify_all()
        if self._thread.is_alive() and threading.current_thread() is not self._thread:
            self._thread.join(timeout)
        return not self._thread.is_alive()

    # ---- the worker ----------------------------------------------------------------------------------

    def _pending(self) -> bool:
        if self._view is None:
            return False
        if self._edits or self._shown is None or self._samples < self.sample_limit:
            return True
        return views_differ(self._shown, self._view)

    def _run(self) -> None:
        try:
            while True:
                with self._cond:
                    while not self._stop and not self._pending():
                        self._cond.wait()
                    if self._stop:
                        return
                    view, edits, self._edits = self._view, self._edits, []
                assert view is not None
                self._frame(view, edits)
                self.on_frame()
        except Exception as exc:  # shown in the header; the session stops
            if not isinstance(exc, (DeviceError, KernelBuildError)):  # the user's to fix: the message says it all
                traceback.print_exc()
            with self._cond:
                self.error = f"{type(exc).__name__}: {exc}"
                self._cond.notify_all()
            self.on_frame()

    def build(self, view: Camera) -> None:
        """A new renderer for the scene and the view's size (the first frame, a resize, an edit the compiled
        kernels cannot show): the history starts over."""
        self.scene.camera = view
        self.renderer = Renderer(self.scene, self.settings, self.device, interactive=True)
        self.device_label = getattr(self.renderer.device, "label", "")
        self._measure_scene()
        self.stats.rebuilds += 1

    def _measure_scene(self) -> None:
        self._bounds = scene_bounds(self.scene)
        self._scene_size = 1.0 if self._bounds is None else float(np.linalg.norm(self._bounds[1] - self._bounds[0]))

    def _frame(self, view: Camera, edits: list[SceneEdit]) -> None:
        t0 = time.perf_counter()
        cut = False
        r = self.renderer
        if r is None or (r.width, r.height) != (int(view.width), int(view.height)):
            self.build(view)
            cut = True
        edited = False
        for e in edits:
            assert self.renderer is not None
            outcome, scene = apply_edit(self.scene, self.renderer, e, view)
            if outcome == "rebuilt":
                self.scene = scene
                self.build(view)
            self.stats.edits[outcome] = self.stats.edits.get(outcome, 0) + 1
            cut |= outcome in ("reset", "rebuilt")
            edited |= outcome != "none"
        if edited:
            self._measure_scene()
        r = self.renderer
        assert r is not None
        changed = self._shown is None or views_differ(self._shown, view)
        fitted = fit_ortho(view, self._bounds)  # an orthographic view's origin is far behind: measure from here
        if changed and self._shown_fitted is not None and not cut:
            cut = is_jump(self._shown_fitted, fitted, self._scene_size, self.jump_angle, self.jump_move)
        if changed or edited or cut:
            self._samples = 0
        # a still view averages its frames (a = 1/n); a moving one keeps TAA's floor
        self.settings.alpha_min = self._alpha_min if (changed or edited) else 0.0
        frame = r.render_view(fitted, cut=cut)
        self._shown, self._shown_fitted = view, fitted
        self._samples += 1
        rgba = np.ascontiguousarray(frame.color[::-1], dtype=np.float32)
        rgba[..., 3] = 1.0
        history = float(r.history_length().mean()) if self.track_history else None
        self.stats.frames += 1
        self.stats.cuts += int(cut)
        latest = ViewFrame(rgba=rgba, samples=self._samples, ms=(time.perf_counter() - t0) * 1e3,
                           index=self.stats.frames, cut=cut, history=history)
        with self._cond:
            self._latest = latest
            self._cond.notify_all()
