"""What the restircl RenderEngine does: export, render with restircl.Renderer, write the Render Result.

Blender creates a new RenderEngine for every frame of an animation, so the renderer (its uploaded scene,
compiled kernels and ReSTIR/TAA history) lives in a module-level session per view layer: the first frame of an
animation exports the geometry once with the motion of every frame, later frames only render. The session is
dropped when the render job completes or is cancelled. A still render (F12) accumulates `samples` frames; its
renderer is kept and reused by the next still render of an identical scene.

Nothing here lets an exception escape into Blender: failures are reported with RenderEngine.report.
"""

from __future__ import annotations

import traceback
import warnings
from dataclasses import dataclass

import numpy as np
from restircl.render.passes import PASSES, blender_name

from . import compat, export, preview

MAX_REPORTED_WARNINGS = 8


def toggle_owner(view_layer, toggle: str):
    """The object and property name of a pass's toggle: 'use_pass_z' on the view layer, 'restircl.x' on ours."""
    owner_path, _, name = toggle.rpartition(".")
    owner = view_layer
    for part in filter(None, owner_path.split(".")):
        owner = getattr(owner, part, None)
    return owner, name


def _pass_on(view_layer, p) -> bool:
    if p.blender_toggle is None:
        return True
    owner, name = toggle_owner(view_layer, p.blender_toggle)
    return owner is None or bool(getattr(owner, name, True))  # the add-on's own toggles: on when unregistered


def register_passes(engine, scene, view_layer) -> None:
    """RenderEngine.update_render_passes: the passes of restircl.render.passes.PASSES the view layer has turned on."""
    props = getattr(scene, "restircl", None)
    for p in PASSES:
        if p.requires is not None and not getattr(props, p.requires, False):
            continue
        if _pass_on(view_layer, p):
            engine.register_pass(scene, view_layer, blender_name(p, _version()), len(p.channels), p.channels,
                                 p.blender_type)


def _version() -> tuple[int, ...]:
    import bpy

    return tuple(bpy.app.version)


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


def make_settings(restircl, props):
    """restircl.Settings from scene.restircl (its properties are generated from the same table)."""
    return restircl.Settings(**props.settings_kwargs())


def _frames_to_sample(scene, frame: int, animation: bool, warmup: int, use_vector: bool,
                      deforming: bool) -> list[int]:
    """Blender frames whose motion is exported. An animation samples the rest of the frame range and, before
    it, the warm-up frames (at least one when the Vector pass is on: motion needs a previous frame)."""
    if not animation:
        return [frame]
    step = max(1, int(scene.frame_step))
    before = max(int(warmup), 1 if use_vector else 0)
    last = frame if deforming else max(frame, int(scene.frame_end))
    return [frame - k * step for k in range(before, 0, -1)] + list(range(frame, last + 1, step))


def _render(engine, depsgraph) -> None:
    scene = depsgraph.scene
    view_layer = depsgraph.view_layer
    props = scene.restircl
    try:
        import restircl
    except ImportError as exc:
        engine.report({"ERROR"}, f"restircl: the restircl package cannot be imported ({exc}); "
                      f"{compat.import_error_hint(_version())}")
        return
    if not hasattr(restircl, "Renderer"):
        engine.report({"ERROR"}, "restircl: this restircl package has no Renderer (too old)")
        return
    known = tuple(getattr(restircl, n) for n in ("DeviceError", "KernelBuildError", "SceneError", "SettingError")
                  if hasattr(restircl, n)) + (export.ExportError,)

    if engine.is_preview:
        preview.render_preview(engine, depsgraph, restircl, known)
        return
    frame = int(scene.frame_current)
    animation = bool(engine.is_animation)
    key = (scene.name, view_layer.name)
    width, height = export.render_resolution(scene)
    if scene.render.use_border:
        engine.report({"WARNING"}, "restircl: render region (border) is ignored; the full frame is rendered")
    device_spec = props.device.strip() or None
    settings_key = (tuple(sorted(props.settings_kwargs().items())), device_spec)

    session = _SESSIONS.get(key)
    new_sequence = True
    if (animation and session is not None and session.animation and session.settings_key == settings_key
            and not session.deforming and session.last_frame is not None
            and session.last_frame < frame <= session.export.frames[-1]):
        new_sequence = False
    if new_sequence:
        engine.update_stats("", "restircl | exporting the scene")
        camera = engine.camera_override
        if camera is not None:
            camera = camera.evaluated_get(depsgraph)
        deforming = animation and session is not None and session.animation and session.deforming
        frames = _frames_to_sample(scene, frame, animation, props.warmup_frames, view_layer.use_pass_vector,
                                   deforming)
        try:
            exp = export.export_scene(depsgraph, frames, frame_set=lambda f: engine.frame_set(f, 0.0),
                                      camera=camera)
            exp.scene.validate()
        except known as exc:
            engine.report({"ERROR"}, f"restircl: {exc}")
            _SESSIONS.pop(key, None)
            return
        _report_warnings(engine, exp.warnings)
        fingerprint = exp.fingerprint()
        if (session is not None and not animation and not session.animation
                and session.fingerprint == fingerprint and session.settings_key == settings_key):
            session.renderer.reset()  # identical scene and settings: keep the uploaded scene and kernels
        else:
            _SESSIONS.pop(key, None)
            session = None
            if engine.test_break():
                return
            engine.update_stats("", "restircl | building the renderer")
            try:
                device_label = restircl.choose_device(device_spec)[0].label
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    settings = make_settings(restircl, props)
                    if not animation and hasattr(restircl, "still_settings"):  # F12: the still estimator
                        settings = restircl.still_settings(settings, exp.scene)
                    renderer = restircl.Renderer(exp.scene, settings, device=device_spec)
            except known as exc:
                engine.report({"ERROR"}, f"restircl: {exc}")
                return
            _report_warnings(engine, [str(w.message) for w in caught])
            session = _Session(renderer, exp, fingerprint, settings_key, device_label, animation,
                               deforming=animation and (deforming or bool(exp.deforming)))
            _SESSIONS[key] = session

    exp = session.export
    renderer = session.renderer
    index = exp.index_of(frame)
    stats = exp.stats

    features = getattr(renderer, "features", None)
    compiled = f" | compiled: {', '.join(features) or 'none'}" if features is not None else ""
    estimate: list[float | None] = [None]

    def show(done: int, total: int, ms: float | None) -> None:
        engine.update_progress(done / total if total else 1.0)
        timing = f" | {ms:.1f} ms/frame" if ms is not None else ""
        err = f" | est. relMSE {estimate[0]:.2e}" if estimate[0] is not None else ""
        engine.update_stats("", f"restircl | {session.device} | frame {frame} | sample {done}/{total}{timing}{err} | "
                                f"{stats['lights']} lights | {stats['triangles']} triangles{compiled}")

    try:
        if animation:
            # every frame's random stream is keyed by its Blender frame number, so a frame range split into
            # chunks (Flamenco: -s A -e B per chunk, docs/farm.md) draws the same noise as one render of it
            if new_sequence:  # warm-up: the frames before the first, with their motion
                for warm in range(index):
                    if engine.test_break():
                        return
                    renderer.render_frame(warm, aovs=False, sample=exp.frames[warm])  # discarded: no read-back
            if engine.test_break():
                return
            result = renderer.render_frame(index, aovs=_aovs_needed(view_layer, scene.render.film_transparent),
                                           sample=frame)
            session.last_frame = frame
            show(1, 1, getattr(result, "ms", None))
        else:
            total = int(props.samples)
            show(0, total, None)

            def progress(done: int, total_: int) -> None:
                if done % 8 == 0 and hasattr(renderer, "error_estimate"):
                    estimate[0] = renderer.error_estimate(*renderer.still_counts)
                show(done, total_, None)

            kwargs = {}
            if props.target_error > 0:
                kwargs["target_error"] = float(props.target_error)
            result = renderer.render_still(index, total, progress=progress, should_stop=engine.test_break, **kwargs)
            estimate[0] = getattr(result, "error_estimate", None)
            done = int(getattr(result, "samples", total))
            show(done, total, getattr(result, "ms", None))
            if done < total and kwargs and not engine.test_break():
                engine.report({"INFO"}, f"restircl: stopped after {done} of {total} samples, the estimated relMSE "
                              f"{estimate[0]:.2e} reached the target {props.target_error:g}")
    except known as exc:
        engine.report({"ERROR"}, f"restircl: {exc}")
        _SESSIONS.pop(key, None)
        return
    if result is None:
        return
    guards = getattr(result, "guards", None) or {}
    bad = {k: int(v) for k, v in guards.items() if v}
    if bad:
        engine.report({"WARNING"}, "restircl: NaN/Inf values replaced by 0: "
                      + ", ".join(f"{k} {v}" for k, v in sorted(bad.items())))
    write_result(engine, result, width, height, view_layer, scene.render.film_transparent)


def _aovs_needed(view_layer, film_transparent: bool) -> bool:
    """Whether a frame must read back its G-buffer passes (depth, normal, vector, albedo): only for a pass the
    view layer has on, or for the alpha of a transparent film (from the depth)."""
    gbuffer = [p for p in PASSES[1:] if p.attr in ("depth", "normal", "vector", "albedo")]
    return film_transparent or any(_pass_on(view_layer, p) for p in gbuffer)


def _pass_data(frame, p, height: int, width: int) -> np.ndarray | None:
    """A pass of a restircl.Frame as (H, W, C) float32, with Blender's value where nothing is hit."""
    arr = getattr(frame, p.attr, None)
    if arr is None:
        return None
    arr = np.asarray(arr, dtype=np.float32)
    if arr.ndim == 2:
        arr = arr[..., None]
    if arr.shape[:2] != (height, width):
        return None
    if p.miss is not None:
        arr = np.where(np.isfinite(arr), arr, np.float32(p.miss)).astype(np.float32)
    return arr


def _combined(frame, height: int, width: int, film_transparent: bool) -> np.ndarray | None:
    """RGBA of the image; with a transparent film, alpha 0 where the camera ray hits nothing."""
    colour = _pass_data(frame, PASSES[0], height, width)
    if colour is None:
        return None
    colour = colour.copy()
    if colour.shape[2] == 3:
        colour = np.concatenate([colour, np.ones_like(colour[..., :1])], axis=2)
    depth = getattr(frame, "depth", None)
    if depth is not None and np.shape(depth)[:2] != (height, width):
        depth = None
    if film_transparent and depth is not None:
        colour[..., 3] = np.isfinite(np.asarray(depth, dtype=np.float32)).reshape(height, width)
    elif not film_transparent:
        colour[..., 3] = 1.0
    return colour


def write_result(engine, frame, width: int, height: int, view_layer, film_transparent: bool) -> None:
    """Copy a restircl.Frame (rows top first) into the Render Result (rows bottom first): only the passes the
    result has, each converted once."""
    result = engine.begin_result(0, 0, width, height, layer=view_layer.name)
    try:
        version = _version()
        by_name = {blender_name(p, version): p for p in PASSES}
        for rp in result.layers[0].passes:
            p = by_name.get(rp.name)
            if p is None:
                continue
            data = _combined(frame, height, width, film_transparent) if p is PASSES[0] else \
                _pass_data(frame, p, height, width)
            if data is None or data.shape[2] != rp.channels:
                continue
            flipped = np.ascontiguousarray(data[::-1].reshape(width * height, rp.channels))
            if not np.all(np.isfinite(flipped)):
                flipped = np.nan_to_num(flipped, nan=0.0, posinf=0.0, neginf=0.0)
            _set_rect(rp, flipped)
    finally:
        engine.end_result(result)


def _set_rect(render_pass, pixels: np.ndarray) -> None:
    """RenderPass.rect from (pixels, channels) float32. foreach_set takes the buffer whole; assigning the array
    (`rect = pixels`) took 80-150 ms per pass of 192x108 against 0.1 ms (tools/experiments/bench_write_result.py,
    docs/measurements/benchmarks.md)."""
    try:
        render_pass.rect.foreach_set(pixels.reshape(-1))
    except (AttributeError, TypeError):  # a Blender without foreach_set on this array
        render_pass.rect = pixels


def device_list() -> list[str]:
    """Labels of the OpenCL devices, for the panel (never raises)."""
    try:
        import restircl

        return [info.label for info, _dev in restircl.list_devices()]
    except Exception as exc:  # no restircl, no pyopencl, no ICD: show why
        return [f"(no OpenCL device: {exc})"]
