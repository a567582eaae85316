"""What the restircl RenderEngine does for a render job (F12 or an animation): export, render with restircl.Renderer,
hand the frame to render_result.py.

Blender creates a new RenderEngine for every frame of an animation, so the renderer (its uploaded scene,
compiled kernels and ReSTIR/TAA history) lives in a module-level session per view layer: the first frame of an
animation exports the geometry once with the motion of every frame, later frames only render. The session is
dropped when the render job completes or is cancelled. A still render (F12) accumulates `samples` frames; its
renderer is kept and reused by the next still render of an identical scene.

Nothing here lets an exception escape into Blender: failures are reported with RenderEngine.report.
"""

from __future__ import annotations

import math
import traceback
import warnings
from dataclasses import dataclass

from . import compat, export, light_paths, motion_blur, preview, render_result
from .export.frame_deformation import read_frame_deformation
from .properties import make_settings, render_kwargs
from .region import region_camera, render_region

MAX_REPORTED_WARNINGS = 8


@dataclass
class _Session:
    renderer: object
    export: export.Export
    fingerprint: str
    settings_key: tuple
    device: str
    animation: bool
    deforming: bool = False  # geometry changes between frames: export each frame anew
    last_frame: int | None = None


_SESSIONS: dict[tuple[str, str], _Session] = {}


def clear_sessions(*_args) -> None:
    """Drop every renderer (handler of render_complete / render_cancel / load_pre)."""
    _SESSIONS.clear()


def clear_animation_sessions(*_args) -> None:
    for key in [k for k, s in _SESSIONS.items() if s.animation]:
        del _SESSIONS[key]


def render(engine, depsgraph) -> None:
    """RenderEngine.render: never raises."""
    try:
        _render(engine, depsgraph)
    except Exception as exc:  # a bug of ours: tell the user, never crash Blender
        traceback.print_exc()
        engine.report({"ERROR"}, f"restircl: unexpected {type(exc).__name__}: {exc}")
        clear_sessions()


def _report_warnings(engine, messages) -> None:
    for msg in messages[:MAX_REPORTED_WARNINGS]:
        engine.report({"WARNING"}, f"restircl: {msg}")
    if len(messages) > MAX_REPORTED_WARNINGS:
        engine.report({"WARNING"}, f"restircl: {len(messages) - MAX_REPORTED_WARNINGS} more warnings")


def _frames_to_sample(scene, frame: int, animation: bool, warmup: int, use_vector: bool,
                      deforming: bool) -> list[int]:
    """Blender frames whose motion is exported. An animation samples the rest of the frame range and, before
    it, the warm-up frames (at least one when the Vector pass is on: motion needs a previous frame); with motion
    blur, also the frames its first and last frames' shutters reach into."""
    if not animation:
        return motion_blur.still_motion(scene, frame).frames
    step = max(1, int(scene.frame_step))
    a, b = motion_blur.shutter(scene)
    before = max(int(warmup), 1 if use_vector else 0, math.ceil(-a / step))
    last = frame if deforming else max(frame, int(scene.frame_end))
    frames = list(range(frame, last + 1, step))
    return ([frame - k * step for k in range(before, 0, -1)] + frames
            + [frames[-1] + k * step for k in range(1, math.ceil(b / step) + 1)])


@dataclass
class _Job:
    """One call of RenderEngine.render: a still (F12) or one frame of an animation, and the restircl package."""

    engine: object
    depsgraph: object
    restircl: object
    known: tuple  # the exceptions that are the user's to fix: reported, never raised
    frame: int
    animation: bool
    key: tuple[str, str]  # the session's: scene and view layer
    device_spec: str | None
    settings_key: tuple

    @property
    def props(self):
        return self.depsgraph.scene.restircl

    def error(self, exc: Exception) -> None:
        self.engine.report({"ERROR"}, f"restircl: {exc}")


def _render(engine, depsgraph) -> None:
    scene = depsgraph.scene
    view_layer = depsgraph.view_layer
    restircl = _import_restircl(engine)
    if restircl is None:
        return
    known = tuple(getattr(restircl, n) for n in ("DeviceError", "KernelBuildError", "SceneError", "SettingError")
                  if hasattr(restircl, n)) + (export.ExportError,)
    if engine.is_preview:
        preview.render_preview(engine, depsgraph, restircl, known)
        return
    region = render_region(scene, *export.render_resolution(scene))
    width, height = (region.width, region.height) if region is not None else export.render_resolution(scene)
    device_spec = scene.restircl.device.strip() or None
    job = _Job(engine, depsgraph, restircl, known, int(scene.frame_current), bool(engine.is_animation),
               (scene.name, view_layer.name), device_spec,
               (tuple(sorted(render_kwargs(scene.restircl, view_layer=view_layer).items())), device_spec))

    session = _SESSIONS.get(job.key)
    new_sequence = not _continues(job, session)
    if new_sequence:
        session = _start_session(job, session)
        if session is None:
            return
    try:
        result = _render_frame(job, session, new_sequence) if job.animation else _render_still(job, session)
    except known as exc:
        job.error(exc)
        _SESSIONS.pop(job.key, None)
        return
    if result is None:
        return
    guards = getattr(result, "guards", None) or {}
    bad = {k: int(v) for k, v in guards.items() if v}
    if bad:
        engine.report({"WARNING"}, "restircl: NaN/Inf values replaced by 0: "
                      + ", ".join(f"{k} {v}" for k, v in sorted(bad.items())))
    # a region's result is the region's size: Blender places it in the frame (or crops to it) itself
    render_result.write_result(engine, result, width, height, view_layer, scene.render.film_transparent)


def _import_restircl(engine):
    """The restircl package, or None after reporting why it cannot render."""
    try:
        import restircl
    except ImportError as exc:
        engine.report({"ERROR"}, f"restircl: the restircl package cannot be imported ({exc}); "
                      f"{compat.import_error_hint(compat.blender_version())}")
        return None
    if not hasattr(restircl, "Renderer"):
        engine.report({"ERROR"}, "restircl: this restircl package has no Renderer (too old)")
        return None
    return restircl


def _continues(job: _Job, session: _Session | None) -> bool:
    """Whether this animation frame continues the session's sequence: same settings, exported motion that reaches
    the frame, the frames after the last one rendered (so its ReSTIR/TAA history is the previous frame's)."""
    return (job.animation and session is not None and session.animation and session.settings_key == job.settings_key
            and not session.deforming and session.last_frame is not None
            and session.last_frame < job.frame <= session.export.frames[-1])


def _start_session(job: _Job, session: _Session | None) -> _Session | None:
    """Export the scene and make the renderer of a new still or sequence; a still render of an identical scene
    with identical settings keeps the previous renderer (its uploaded scene and kernels). None: reported, or
    cancelled."""
    engine, depsgraph = job.engine, job.depsgraph
    engine.update_stats("", "restircl | exporting the scene")
    camera = engine.camera_override
    if camera is not None:
        camera = camera.evaluated_get(depsgraph)
    deforming = job.animation and session is not None and session.animation and session.deforming
    frames = _frames_to_sample(depsgraph.scene, job.frame, job.animation, job.props.warmup_frames,
                               depsgraph.view_layer.use_pass_vector, deforming)
    # a still's frames stand for the times within its shutter (motion_blur.still_motion); an animation's are
    # frame_step apart, each frame rendered at a time of its shutter (render/shutter.py)
    step = (float(max(1, int(depsgraph.scene.frame_step))) if job.animation
            else motion_blur.still_motion(depsgraph.scene, job.frame).step)
    try:
        exp = export.export_scene(depsgraph, frames, camera=camera, frame_set=lambda f: engine.frame_set(
            *((f, 0.0) if job.animation else motion_blur.subframe(f, job.frame, step))),
            deform=None if job.animation else motion_blur.deform_frames(depsgraph.scene, job.frame))
        exp.scene.camera = region_camera(exp.scene.camera,
                                         render_region(depsgraph.scene, *export.render_resolution(depsgraph.scene)))
        exp.scene.camera.shutter = motion_blur.scene_shutter(depsgraph.scene, step)
        if job.animation:  # each frame's deformation over its shutter (and the warm-up frames')
            read_frame_deformation(depsgraph, exp, job.frame, step, lambda ob: motion_blur.animation_deform_times(
                depsgraph.scene, exp.frames, job.frame, motion_blur.deform_steps(ob)), engine.frame_set,
                exp.warnings.append)
        if not job.animation:
            motion_blur.hold_unblurred(exp.scene, depsgraph.scene.objects,
                                       exp.index_of(motion_blur.shutter_middle(depsgraph.scene, job.frame)))
        motion_blur.warn_unblurred(depsgraph.scene, job.animation,
                                   [n for n in exp.deforming if n not in exp.deform_handled], exp.warnings.append,
                                   depsgraph.scene.objects)
        exp.scene.validate()
    except job.known as exc:
        job.error(exc)
        _SESSIONS.pop(job.key, None)
        return None
    _report_warnings(engine, exp.warnings)
    _report_warnings(engine, light_paths.read(depsgraph.scene)[1])  # every still, each sequence once
    fingerprint = exp.fingerprint()
    if (session is not None and not job.animation and not session.animation
            and session.fingerprint == fingerprint and session.settings_key == job.settings_key):
        session.renderer.reset()  # identical scene and settings: keep the uploaded scene and kernels
        return session
    _SESSIONS.pop(job.key, None)
    if engine.test_break():
        return None
    engine.update_stats("", "restircl | building the renderer")
    restircl = job.restircl
    try:
        device_label = restircl.choose_device(job.device_spec)[0].label
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            settings = make_settings(restircl, job.props, view_layer=job.depsgraph.view_layer)
            if not job.animation and hasattr(restircl, "still_settings"):  # F12: the still estimator
                settings = restircl.still_settings(settings, exp.scene)
            renderer = restircl.Renderer(exp.scene, settings, device=job.device_spec)
    except job.known as exc:
        job.error(exc)
        return None
    _report_warnings(engine, [str(w.message) for w in caught])
    session = _Session(renderer, exp, fingerprint, job.settings_key, device_label, job.animation,
                       deforming=job.animation and (deforming or bool(exp.deforming)))
    _SESSIONS[job.key] = session
    return session


class _Status:
    """Blender's progress bar and status line while a frame of a session renders."""

    def __init__(self, job: _Job, session: _Session) -> None:
        self.engine, self.session, self.frame = job.engine, session, job.frame
        features = getattr(session.renderer, "features", None)
        self.compiled = f" | compiled: {', '.join(features) or 'none'}" if features is not None else ""
        self.estimate: float | None = None

    def show(self, done: int, total: int, ms: float | None) -> None:
        self.engine.update_progress(done / total if total else 1.0)
        stats = self.session.export.stats
        timing = f" | {ms:.1f} ms/frame" if ms is not None else ""
        err = f" | est. relMSE {self.estimate:.2e}" if self.estimate is not None else ""
        self.engine.update_stats("", f"restircl | {self.session.device} | frame {self.frame} | sample {done}/{total}"
                                     f"{timing}{err} | {stats['lights']} lights | {stats['triangles']} triangles"
                                     f"{self.compiled}")


def _render_frame(job: _Job, session: _Session, new_sequence: bool):
    """One frame of an animation (after the warm-up frames of a new sequence); None when cancelled."""
    engine, exp, renderer = job.engine, session.export, session.renderer
    index = exp.index_of(job.frame)
    # every frame's random stream is keyed by its Blender frame number, so a frame range split into
    # chunks (Flamenco: -s A -e B per chunk, docs/farm.md) draws the same noise as one render of it
    if new_sequence:  # warm-up: the frames before the first, with their motion
        for warm in range(index):
            if engine.test_break():
                return None
            renderer.render_frame(warm, aovs=False, sample=exp.frames[warm])  # discarded: no read-back
    if engine.test_break():
        return None
    scene = job.depsgraph.scene
    aovs = (render_result.aovs_needed(job.depsgraph.view_layer, scene.render.film_transparent)
            or any(m.holdout for m in exp.scene.meshes))  # a holdout's alpha comes from the G-buffer
    result = renderer.render_frame(index, aovs=aovs, sample=job.frame)
    session.last_frame = job.frame
    _Status(job, session).show(1, 1, getattr(result, "ms", None))
    return result


def _render_still(job: _Job, session: _Session):
    """A still: `samples` frames accumulated, or fewer when the target error is reached or the user cancels."""
    engine, props, renderer = job.engine, job.props, session.renderer
    status = _Status(job, session)
    total = int(props.samples)
    status.show(0, total, None)

    def progress(done: int, total_: int) -> None:
        if done % 8 == 0 and hasattr(renderer, "error_estimate"):
            status.estimate = renderer.error_estimate(*renderer.still_counts)
        status.show(done, total_, None)

    kwargs = {}
    if props.target_error > 0:
        kwargs["target_error"] = float(props.target_error)
    result = renderer.render_still(session.export.index_of(job.frame), total, progress=progress,
                                   should_stop=engine.test_break, **kwargs)
    status.estimate = getattr(result, "error_estimate", None)
    done = int(getattr(result, "samples", total))
    status.show(done, total, getattr(result, "ms", None))
    if done < total and kwargs and not engine.test_break():
        engine.report({"INFO"}, f"restircl: stopped after {done} of {total} samples, the estimated relMSE "
                      f"{status.estimate:.2e} reached the target {props.target_error:g}")
    return result


def device_list() -> list[str]:
    """Labels of the OpenCL devices, for the panel (never raises)."""
    try:
        import restircl

        return [info.label for info, _dev in restircl.list_devices()]
    except Exception as exc:  # no restircl, no pyopencl, no ICD: show why
        return [f"(no OpenCL device: {exc})"]
