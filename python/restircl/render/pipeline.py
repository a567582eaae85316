"""The frame pipeline: Renderer.run_frame runs one frame's stages top to bottom (DESIGN section 2), one call each.

    1 primary    camera rays -> G-buffer (position, normals, albedo, emission, motion)
    2 initial    RIS over `candidates` light-array samples -> reservoir        (restir)
    3 visibility shadow ray for the initial sample, inside restir_initial        (restir, visibility_reuse)
    4 temporal   merge with last frame's reservoir found by reprojection        (restir, temporal, history)
    5 spatial    merge neighbours' reservoirs, `spatial_passes` times           (restir, spatial)
    6 shade      one shadow ray to the chosen sample -> noisy direct light s_n  (every method)
    6b bounces   paths from the visible point (max_bounces > 0), or ReSTIR GI reusing them (render/restir_gi.py)
    7 taa        f_n = a s_n + (1 - a) clip(history)                            (taa, animation frames)
    8 output     numpy arrays: colour and AOVs (render/frame.py, Renderer.read_frame)

What a frame runs and reuses is decided before it starts, by plan_frame (render/plan.py, pure: no device) from the
settings and the frame's situation that the renderer describes; run_frame follows the plan. The parts: the scene's
device buffers (upload/device_scene.py), the stages (render/stages.py), the history they ping-pong
(render/history.py), still renders (render/still.py: they drive run_frame like any caller), kernel launches by
argument name (core/kernels.py). Code a scene or a setting does not need is not compiled (render/features.py)."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
import pyopencl as cl

from ..core import layouts as L
from ..core.buffers import FrameBuffers, alloc
from ..core.device import Device, get_device
from ..core.kernels import LOCAL_ITEMS, Kernels, local_size
from ..core.program import build_program
from ..lights.array import LightArray
from ..lights.device_lights import DeviceLights
from ..lights.pick_table import PickTable
from ..lights.tree import light_trees
from ..scene.camera import Camera
from ..scene.errors import SceneError
from ..scene.scene import Scene
from ..settings.table import BIAS_CORRECTIONS, SHADE_METHODS, TILE_INFO_BYTES, Settings
from ..upload.device_scene import DeviceScene
from . import qmc
from .camera import jitter
from .denoise import denoise_by_gbuffer
from .features import describe, renderer_flags
from .frame import DeviceFrame, Frame, read_aovs, read_colour, read_gbuffer, read_guards, read_image
from .history import History
from .layers import CameraLayers
from .light_passes import fill_planes, light_group_settings
from .plan import FramePlan, light_source, plan_frame
from .restir_gi import RestirGI
from .shutter import at_phase, frame_phase, shifted, sweep
from .situation import frame_situation
from .stages import (
    BoilingFilter,
    FrameState,
    Initial,
    LightTiles,
    Paths,
    Primary,
    RealtimeFilter,
    Shade,
    Spatial,
    StageTimer,
    Taa,
    Temporal,
    sampler_params,
)
from .still import StillAccumulation, render_still

__all__ = ["LOCAL_ITEMS", "Frame", "Renderer", "Settings", "local_size"]

_METHOD_CODE = {m: i for i, m in enumerate(SHADE_METHODS)}  # METHOD_* (opencl/codes.h)


class Renderer:
    """Renders a Scene frame by frame on one OpenCL device, keeping ReSTIR and TAA history between frames. The scene
    (with all its frames of animation) is taken as it is at construction: for an edited scene, make a new Renderer,
    or (an interactive session) edit it in place and say what changed with device_scene.edit."""

    def __init__(self, scene: Scene, settings: Settings | None = None, device: Device | str | None = None, *,
                 interactive: bool = False) -> None:
        """interactive: the view may change every frame (render_view) and objects may be moved by edits
        (device_scene.edit), so motion vectors and object motion are always compiled."""
        self.scene = scene.validate()
        self.interactive = interactive
        self._prev_view: Camera | None = None  # render_view: the view of the last frame
        self.settings = s = light_group_settings(scene, (settings or Settings()).validate())
        self.device = device if isinstance(device, Device) else get_device(device)
        cam = scene.camera
        assert cam is not None
        self.width, self.height = int(cam.width), int(cam.height)
        self.pixels = self.width * self.height
        self._sample = 0  # frames rendered so far: the random seed of the next one
        self.qmc: tuple[int, int, int] | None = None  # FrameParams (qmc, qmc_index, qmc_key) set by a still render
        self._last_frame: int | None = None
        self.last_plan: FramePlan | None = None  # what the last frame ran and reused (render/plan.py)
        self.guard_totals = dict.fromkeys(L.GUARD_NAMES[: L.GUARD_COUNT], 0)
        context, queue = self.device.context, self.device.queue
        self.buffers = FrameBuffers(context, queue, self.pixels)
        self.device_scene = DeviceScene(context, scene, s.slots_per_light, s.light_change_ratio, s.area_sampling,
                                        qmc.environment_table(s))
        self.device_scene.upload(0, None)
        self._build()
        glossy = self.flags.get("HAS_GLOSSY", False)
        if glossy:
            self.device_scene.upload_ggx_tables()
        self.history = History(lambda nbytes: alloc(context, nbytes), self.pixels, glossy=glossy)
        stage = (self.kernels, self.device_scene, self.buffers, self.history, s)
        bias = BIAS_CORRECTIONS.index(s.bias_correction)
        self.primary = Primary(*stage)
        self.light_tiles = LightTiles(*stage, info_bytes=TILE_INFO_BYTES)
        self.initial = Initial(*stage)
        self.temporal = Temporal(*stage, bias_code=bias)
        self.spatial = Spatial(*stage, bias_code=bias)
        self.boiling = BoilingFilter(*stage)
        self.realtime_filter = RealtimeFilter(*stage)
        self.shade = Shade(*stage, method_codes=_METHOD_CODE)
        self.paths = Paths(*stage)
        self.restir_gi = RestirGI(*stage, paths=self.paths)
        self.taa = Taa(*stage)
        self.layers = CameraLayers(*stage)
        self.still = StillAccumulation(self.kernels, self.pixels, (self.height, self.width))
        if self.flags.get("HAS_LIGHT_PASSES"):  # the planes of the light passes (general builds write them too)
            self.buffers.light_passes = self.still.use_light_passes(int(self.flags.get("HAS_LIGHT_GROUPS", 0)))
        self.pick_table = PickTable(self.kernels, self.pixels)

    def _build(self) -> None:
        """Compile the program with the features this scene and settings need (render/features.py)."""
        s, ds = self.settings, self.device_scene
        self.uses_light_tree, self.path_light_tree = light_trees(s, ds.lights.types)
        if self.uses_light_tree or self.path_light_tree:
            ds.use_light_tree()
        self.flags = flags = renderer_flags(self.scene, ds, s, interactive=self.interactive,
                                            light_tree=self.uses_light_tree, path_light_tree=self.path_light_tree)
        self.features = describe(flags)
        t0 = time.perf_counter()
        self.program = build_program(self.device, flags)
        self.build_seconds = time.perf_counter() - t0
        self.kernels = Kernels(self.device, self.program, flags=flags)

    def reset(self) -> None:  # drop all history (ReSTIR reservoirs, TAA, accumulation)
        self.history.invalidate()
        self._last_frame = None

    # ---- the frame -------------------------------------------------------------------------------------

    def render_frame(self, frame: int, *, still: bool = False, aovs: bool = True, sample: int | None = None) -> Frame:
        """Render animation frame `frame`, carrying history from the previous call (reset on a camera cut).
        aovs=False reads back the colour and the noisy sample only (no other pass): a real-time viewer needs no
        more, and the G-buffer read-back cost ~20 ms per 640x360 frame on a 2-core CPU. `sample` is this frame's
        random stream key (and jitter index), by default the frames rendered so far: a render split into chunks
        (farm/cluster.py) keys every frame by its number, so that its noise does not depend on where one began."""
        if sample is not None:
            self._sample = int(sample) % (1 << 32)  # FrameParams.sample is a uint
        t0 = time.perf_counter()
        stage, color_buf, gbuf = self.run_frame(frame, still=still)
        out = self.read_frame(color_buf, gbuf, frame, aovs=aovs)
        if self.settings.denoise:
            denoise_by_gbuffer(out, self.read_gbuffer(gbuf))
        out.stage_ms, out.ms = stage, (time.perf_counter() - t0) * 1e3
        return out

    def render_view(self, camera: Camera, *, cut: bool = False, aovs: bool = False) -> Frame:
        """A frame of an interactive view (the viewport): frame 0 of the scene seen by `camera` (of the renderer's
        size), whose view may differ from the last call's. The history is reprojected from the last call's view as
        in an animation, or dropped when `cut`; the renderer's scene takes `camera` as its camera."""
        if (int(camera.width), int(camera.height)) != (self.width, self.height):
            raise SceneError(f"camera: the view is {camera.width}x{camera.height}, the renderer "
                             f"{self.width}x{self.height}; make a new Renderer for another size")
        if cut or self._prev_view is None:
            self.reset()
        self._prev_view = self.scene.camera if self._last_frame is not None else camera
        self.scene.camera = camera
        return self.render_frame(0, aovs=aovs)

    def run_frame(self, frame: int, *, still: bool = False, jitter_px: tuple[float, float] | None = None,
                  wait: bool = True) -> DeviceFrame:
        """Run the stages of frame `frame` (DESIGN section 2) and leave it on the device, read back by nothing:
        render_frame and render_still read what they need (read_frame), and timing tools measure the frame alone.
        `still`: a frame of a still render (averaged by its caller: no TAA, no boiling filter); jitter_px: the
        pixel jitter, by default the renderer's own Halton sequence; `wait`: the stage timer waits for the device
        after each stage (render/stages.py StageTimer; a still render's frames do not)."""
        h = self.history
        timer = StageTimer(self.device.queue, wait=wait)
        state = self._begin_frame(frame, still, jitter_px)
        plan = state.plan
        timer.mark("upload")
        # stages 1-6b once, or per weighted layer of a still (render/layers.py)
        self.layers.run(state, timer, self._shade_layer, self.layers.wanted(self.flags, plan, still))
        color_buf = self.buffers.sample
        if plan.taa:  # 7 temporal accumulation (animation frames; a still render averages instead)
            color_buf = self.taa.run(state, plan.taa_moving)
            timer.mark("taa")
            if plan.filter:  # 8 edge-aware a-trous filter of what is shown (the history stays as it is)
                color_buf = self.realtime_filter.run(state, color_buf)
                timer.mark("filter")
        gbuf = h.gbuf(h.cur)
        self._last_frame = frame
        self._sample += 1
        h.swap()
        return DeviceFrame(timer.ms, color_buf, gbuf)

    def _shade_layer(self, state: FrameState, timer: StageTimer, layer: int) -> None:
        """Stages 1-6b of a frame: the G-buffer and this frame's sample; of one weighted layer where layer >= 0."""
        h, plan = self.history, state.plan
        # 1 camera rays -> G-buffer
        self.primary.run(state, self.scene.camera, self._prev_view, self.layers.arguments(layer))
        timer.mark("primary")
        if plan.tiles and layer <= 0:  # presampled light tiles (many lights): this frame's RIS candidates
            self.light_tiles.run(state)
            timer.mark("tiles")
        tiles = self.light_tiles.arguments(state)
        if plan.pick_table and not self.pick_table.ready:  # once per still render, from its first G-buffer
            self.pick_table.build(h.gbuf(h.cur), h.glossy(h.cur), self.device_scene.lights_buf,
                                  self.device_scene.light_pdf_buf, self.device_scene.sampled_light_count,
                                  state.frame_params)
            timer.mark("pick_table")
        if plan.method == "restir":
            res = self.initial.run(state, tiles)  # 2-3 RIS -> reservoir, visibility of the chosen sample
            timer.mark("initial")
            if plan.temporal:  # 4 merge last frame's reservoir
                res = self.temporal.run(state, res)
                timer.mark("temporal")
            if plan.boiling:  # 4b biased: the animation path only
                self.boiling.run(state, res)
                timer.mark("boiling")
            if plan.spatial:  # 5 merge the neighbours'
                res = self.spatial.run(state, res, tiles)
                timer.mark("spatial")
            h.keep_reservoirs(self.device.queue, res)
            self.shade.restir(state)  # 6 one shadow ray to the final sample
        elif plan.method == "reference":
            self.shade.reference(state)
        else:
            self.shade.direct(state, tiles, self.pick_table.buf if plan.pick_table else None)
        timer.mark("shade")
        if plan.paths:  # 6b light that bounced, added to the sample
            self.paths.run(state)
            timer.mark("paths")
        if plan.gi:  # 6b ... as ReSTIR GI's samples, reused (beside the path pass where a scene refracts: plan.py)
            self.restir_gi.run(state, timer)

    def frame_params(self) -> np.void:
        """FrameParams of the next frame: the image and its random stream key."""
        s = self.settings
        on, index, key = self.qmc if self.qmc is not None else (
            (1, self._sample, s.seed) if qmc.frames_use_sobol(s) else qmc.OFF)
        return L.pack(L.FRAME_PARAMS, width=self.width, height=self.height, pixels=self.pixels, sample=self._sample,
                      seed=s.seed, qmc=on, qmc_index=index % (1 << 32), qmc_key=key)

    def _begin_frame(self, frame: int, still: bool, jitter_px: tuple[float, float] | None) -> FrameState:
        """Upload the scene at `frame`, plan the frame (render/plan.py) and pack the records its stages share."""
        s, ds = self.settings, self.device_scene
        phase = 0.0 if still else frame_phase(self.scene.camera, frame, self._sample, s.seed)  # motion blur
        ds.upload(shifted(frame, phase), shifted(self._last_frame, phase))
        params = self.frame_params()
        situation = frame_situation(self, frame, still, bool(params["qmc"]), self._last_frame, self._prev_view)
        self.last_plan = plan = at_phase(plan_frame(s, situation), phase)
        if plan.drop_history:
            self.history.invalidate()
        jit = jitter_px if jitter_px is not None else jitter(self._sample) if s.jitter else (0.0, 0.0)
        return FrameState(plan, params, sampler_params(plan, ds, s), jit, sweep(self.scene.camera, phase, still))

    @property
    def light_tiles_used(self) -> bool:
        """Whether the last frame drew its RIS candidates from the tiles."""
        return self.last_plan is not None and self.last_plan.tiles

    def will_use_light_tiles(self) -> bool:
        """Whether the frames of this scene and settings (with its current lights) draw their RIS candidates from
        light tiles (never with the light tree's candidates)."""
        s = self.settings
        return light_source(s, s.method, self.device_scene.sampled_light_count, self.uses_light_tree, False)[1]

    # ---- output -----------------------------------------------------------------------------------------

    def read_frame(self, color_buf: cl.Buffer, gbuf: cl.Buffer, frame: int, scale: float = 1.0,
                   aovs: bool = True) -> Frame:
        """Read back a frame rendered by run_frame: its colour from `color_buf` times `scale` (a still render's
        sum), the noisy sample, the guard counters and (aovs) the passes of G-buffer `gbuf` and the light passes."""
        q = self.device.queue
        color, noisy, bad = read_colour(q, color_buf, self.buffers.sample, (self.height, self.width), scale)
        self.guard_totals["nonfinite_sample"] += bad
        out = Frame(color=color, noisy=noisy, depth=None, normal=None, vector=None, albedo=None,
                    frame=frame, guards=read_guards(q, self.buffers.guards, self.guard_totals),
                    features=list(self.features))
        if aovs:
            read_aovs(q, out, gbuf, self.buffers.vector, self.scene, self.settings.cryptomatte_levels)
            # this frame's light passes and groups (a still's means replace them: render/still.py)
            fill_planes(out, q, self.buffers.light_passes, self.settings.light_passes, self.scene.light_groups)
        return out

    def read_gbuffer(self, gbuf: cl.Buffer | None = None) -> np.ndarray:
        """(H, W) GSample records of G-buffer `gbuf`, by default the last rendered frame's."""
        return read_gbuffer(self.device.queue, self.gbuf[self.last_slot] if gbuf is None else gbuf,
                            (self.height, self.width))

    def history_length(self) -> np.ndarray:
        """(H, W) TAA history length n of the last rendered frame (1: the pixel restarted from its new sample)."""
        return read_image(self.device.queue, self.history.taa[self.last_slot], (self.height, self.width))[..., 3]

    # ---- still renders (render/still.py) ---------------------------------------------------------------------

    def render_still(
        self,
        frame: int = 0,
        samples: int = 16,
        progress: Callable[[int, int], None] | None = None,
        should_stop: Callable[[], bool] | None = None,
        target_error: float | None = None,
        checkpoint: Callable[[int, float], None] | None = None,
    ) -> Frame:
        """Average up to `samples` frames of a still camera at `frame` (ReSTIR keeps reusing between them).

        progress(done, samples) is called after each sample; should_stop() before each (a cancel keeps what is
        done); target_error stops once the reference-free error estimate (relMSE) reaches it; checkpoint(done,
        seconds) lets a caller look at the running mean (mean_image) while it accumulates."""
        try:
            self.pick_table.start(bool(self.flags.get("HAS_PICK_TABLE")))
            return render_still(self, frame, samples, progress, should_stop, target_error, checkpoint)
        finally:
            self.qmc = None  # the frames after it draw random numbers again, also when it raised
            self.pick_table.start(False)

    @property
    def still_counts(self) -> tuple[int, int]:
        """(samples accumulated, of which in half buffer 1) of the still render in progress."""
        return self.still.counts

    def mean_image(self) -> np.ndarray:
        """(H, W, 3) running mean of the still render in progress (for checkpoint callbacks)."""
        return self.still.mean_image()

    def error_estimate(self, done: int, n_half: int) -> float | None:
        """relMSE of the running mean from the two half buffers (StillAccumulation.error_estimate)."""
        return self.still.error_estimate(done, n_half)

    # ---- views of the parts, for tools and tests -------------------------------------------------------

    @property
    def lights(self) -> DeviceLights:
        return self.device_scene.lights

    @property
    def light_array(self) -> LightArray:
        return self.device_scene.light_array

    @property
    def bvh_seconds(self) -> float:
        return self.device_scene.bvh_seconds

    @property
    def triangle_count(self) -> int:
        return self.device_scene.triangle_count

    @property
    def sample_buf(self) -> cl.Buffer:  # this frame's noisy estimate s_n
        return self.buffers.sample

    @property
    def last_slot(self) -> int:
        """The history slot of the last rendered frame: its G-buffer gbuf[last_slot], reservoirs
        res_history[last_slot] and TAA colour taa_history[last_slot] (the next frame writes the other slot)."""
        return self.history.prev

    @property
    def gbuf(self) -> list[cl.Buffer]:
        """The active chain's G-buffers (last_slot: the last rendered frame's)."""
        return self.history.chain.gbuf

    @property
    def res_history(self) -> list[cl.Buffer]:
        return self.history.chain.reservoirs

    @property
    def taa_history(self) -> list[cl.Buffer]:
        return self.history.taa

    @property
    def tile_rec(self) -> cl.Buffer | None:
        return self.light_tiles.tile_rec

    @property
    def tile_info(self) -> cl.Buffer | None:
        return self.light_tiles.tile_info

    @property
    def k(self) -> dict[str, cl.Kernel]:
        return self.kernels.k

    @property
    def max_local(self) -> dict[str, int | None]:
        return self.kernels.max_local

    @max_local.setter
    def max_local(self, value: dict[str, int | None]) -> None:
        self.kernels.max_local = value
