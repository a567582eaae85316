"""The frame pipeline: one frame reads top to bottom in Renderer._render (DESIGN section 2), one call per stage.

    1 primary    camera rays -> G-buffer (position, normals, albedo, emission, motion)
    2 initial    RIS over `candidates` light-array samples -> reservoir        (restir)
    3 visibility shadow ray for the initial sample, inside restir_initial        (restir, visibility_reuse)
    4 temporal   merge with last frame's reservoir found by reprojection        (restir, temporal, history)
    5 spatial    merge neighbours' reservoirs, `spatial_passes` times           (restir, spatial)
    6 shade      one shadow ray to the chosen sample -> noisy direct light s_n  (every method)
    7 taa        f_n = a s_n + (1 - a) clip(history)                            (taa, animation frames)
    8 output     numpy arrays: colour and AOVs (render/frame.py)

The parts: the scene's device buffers (upload/device_scene.py), the stages (render/stages.py), the history they
ping-pong (render/history.py), still accumulation and its error estimate (render/still.py), kernel launches by
argument name (core/kernels.py). Steps a scene or a setting does not need are not run, and their code is not compiled
(render/features.py).
"""

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
from ..lights.pick_table import PickTable, uses_table
from ..lights.tree import tree_proposal
from ..scene.camera import Camera
from ..scene.errors import SceneError
from ..scene.scene import Scene
from ..settings.table import (  # noqa: F401  (restircl.settings.table.Settings etc. are public)
    BIAS_CORRECTIONS,
    BSDF_ANALYTIC_MAX,
    LIGHT_TILES,
    LIGHT_TILES_AUTO,
    MAX_LIGHT_TILE_ENTRIES,
    METHODS,
    SHADE_METHODS,
    TILE_INFO_BYTES,
    Settings,
)
from ..upload.device_scene import DeviceScene
from . import qmc
from .camera import jitter, views_differ
from .denoise import denoise_frame
from .features import derive_flags, describe, general_flags
from .frame import Frame, read_aovs, read_colour, read_gbuffer, read_guards, read_image, surface_images
from .history import History
from .stages import (
    BoilingFilter,
    FrameState,
    Initial,
    LightTiles,
    Primary,
    RealtimeFilter,
    Shade,
    Spatial,
    StageTimer,
    Taa,
    Temporal,
)
from .still import StillAccumulation, render_still

__all__ = ["LOCAL_ITEMS", "Frame", "Renderer", "Settings", "local_size"]

_METHOD_CODE = {m: i for i, m in enumerate(SHADE_METHODS)}  # METHOD_* (opencl/codes.h)


KERNELS = ("primary", "light_tiles_fill", "light_pick_table", "shade_direct", "shade_reference", "accumulate",
           "accumulate_aux", "restir_initial", "restir_temporal", "boiling_tiles", "boiling_filter", "restir_spatial",
           "restir_shade", "taa", "filter_variance", "atrous")


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
        self.settings = s = (settings or Settings()).validate()
        self.device = device if isinstance(device, Device) else get_device(device)
        cam = scene.camera
        assert cam is not None
        self.width, self.height = int(cam.width), int(cam.height)
        self.pixels = self.width * self.height
        self._sample = 0  # frames rendered so far: the random seed of the next one
        self.qmc: tuple[int, int, int] | None = None  # FrameParams (qmc, qmc_index, qmc_key) set by a still render
        self._last_frame: int | None = None
        self.light_tiles_used = False  # whether the last frame drew its RIS candidates from the tiles
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
        self.taa = Taa(*stage)
        self.still = StillAccumulation(self.kernels, self.pixels, (self.height, self.width))
        self.pick_table = PickTable(self.kernels, self.pixels)

    def _build(self) -> None:
        s, ds = self.scene, self.device_scene
        # a camera animation whose transforms are all equal does not move: no motion vectors to compile
        moving_camera = self.interactive or (s.camera is not None
                                             and bool(np.any(s.camera.transforms != s.camera.transforms[:1])))
        self.uses_light_tree = tree_proposal(self.settings.method, self.settings.light_proposal, ds.lights.types)
        if self.uses_light_tree:
            ds.use_light_tree()
        if self.settings.specialise:
            # a light the camera sees that moves needs motion vectors of its own
            moving = moving_camera or ds.moving_objects or (ds.moving_lights and bool(ds.camera_lights))
            flags = derive_flags(ds.lights.type_set, moving, ds.moving_objects or self.interactive,
                                 ds.material_flags, self.uses_light_tree, camera_lights=bool(ds.camera_lights),
                                 pick_table=self._stills_use_pick_table())
        else:
            flags = general_flags()
        self.flags = flags
        self.features = describe(flags)
        t0 = time.perf_counter()
        self.program = build_program(self.device, flags)
        self.build_seconds = time.perf_counter() - t0
        self.kernels = Kernels(self.device, self.program, KERNELS)

    def reset(self) -> None:
        """Drop all history (ReSTIR reservoirs, TAA, accumulation)."""
        self.history.invalidate()
        self._last_frame = None

    # ---- the frame -------------------------------------------------------------------------------------

    def render_frame(self, frame: int, *, still: bool = False, aovs: bool = True, sample: int | None = None) -> Frame:
        """Render animation frame `frame`, carrying history from the previous call (reset on a camera cut).
        aovs=False reads back the colour and the noisy sample only (no depth, normal, vector, albedo): a real-time
        viewer needs no more, and the G-buffer read-back cost ~20 ms per 640x360 frame on a 2-core CPU.
        `sample` is this frame's random stream key (and jitter index), by default the frames rendered so far: a
        render split into chunks (farm/cluster.py) keys every frame by its number, so that its noise does not depend on
        where a chunk began."""
        if sample is not None:
            self._sample = int(sample) % (1 << 32)  # FrameParams.sample is a uint
        t0 = time.perf_counter()
        stage, color_buf, gbuf = self._render(frame, still)
        out = self._read(color_buf, gbuf, frame, aovs=aovs)
        if self.settings.denoise:
            self._denoise(out, gbuf)
        out.stage_ms = stage
        out.ms = (time.perf_counter() - t0) * 1e3
        return out

    def _denoise(self, out: Frame, gbuf: cl.Buffer) -> None:
        """Denoise an animation frame guided by its own G-buffer's albedo and normal (render/denoise.py)."""
        g = self._read_gbuffer(gbuf)
        albedo, normal = surface_images(g)
        emission = np.where(np.isfinite(g["emission"][..., :3]), g["emission"][..., :3], 0.0).astype(np.float32)
        # the TAA output's emission is antialiased over frames, this frame's is one jittered sample: at a lamp's
        # edge the difference is clamped at 0 and goes through the denoiser
        denoise_frame(out, albedo, normal, emission)

    def render_view(self, camera: Camera, *, cut: bool = False, aovs: bool = False) -> Frame:
        """A frame of an interactive view (the viewport): frame 0 of the scene seen by `camera`, which may differ
        from the last call's view in transform, lens, shift or kind (of the renderer's size). The history is
        reprojected from the last call's view as in an animation, or dropped when `cut`; calls with an unchanged
        view accumulate as a still camera's animation frames do. The renderer's scene takes `camera` as its camera."""
        if (int(camera.width), int(camera.height)) != (self.width, self.height):
            raise SceneError(f"camera: the view is {camera.width}x{camera.height}, the renderer "
                             f"{self.width}x{self.height}; make a new Renderer for another size")
        if cut or self._prev_view is None:
            self.reset()
        self._prev_view = self.scene.camera if self._last_frame is not None else camera
        self.scene.camera = camera
        return self.render_frame(0, aovs=aovs)

    def _render(self, frame: int, still: bool, jitter_px: tuple[float, float] | None = None
                ) -> tuple[dict[str, float], cl.Buffer, cl.Buffer]:
        """Run the stages of one frame (DESIGN section 2); returns the stage times (ms), the colour buffer and the
        G-buffer."""
        s, h = self.settings, self.history
        timer = StageTimer(self.device.queue)
        state = self._begin_frame(frame, jitter_px)
        timer.mark("upload")
        self.primary.run(state, self.scene.camera, self._prev_view)  # 1 camera rays -> G-buffer
        timer.mark("primary")
        if state.tiles:  # presampled light tiles (many lights): this frame's RIS candidates
            self.light_tiles.run(state)
            timer.mark("tiles")
        tiles = self.light_tiles.arguments(state)
        if state.pick_table and not self.pick_table.ready:  # once per still render, from its first G-buffer
            self.pick_table.build(h.gbuf(h.cur), h.glossy(h.cur), self.device_scene.lights_buf,
                                  self.device_scene.light_pdf_buf, self.device_scene.sampled_light_count,
                                  state.frame_params)
            timer.mark("pick_table")
        if state.method == "restir":
            res = self.initial.run(state, tiles)  # 2-3 RIS -> reservoir, visibility of the chosen sample
            timer.mark("initial")
            if s.temporal and state.restir_history:  # 4 merge last frame's reservoir
                res = self.temporal.run(state, res)
                timer.mark("temporal")
            if s.boiling_filter > 0 and not still:  # 4b biased: the animation path only
                self.boiling.run(state, res)
                timer.mark("boiling")
            if s.spatial and s.spatial_neighbours > 0:  # 5 merge the neighbours'
                res = self.spatial.run(state, res)
                timer.mark("spatial")
            h.keep_reservoirs(self.device.queue, res)
            self.shade.restir(state)  # 6 one shadow ray to the final sample
        elif state.method == "reference":
            self.shade.reference(state)
        else:
            self.shade.direct(state, tiles, self.pick_table.buf if state.pick_table else None)
        timer.mark("shade")
        color_buf = self.buffers.sample
        if s.taa and not still:  # 7 temporal accumulation (animation frames; a still render averages instead)
            color_buf = self.taa.run(state, self._moving(state))
            timer.mark("taa")
            if s.realtime_filter:  # 8 edge-aware a-trous filter of what is shown (the history stays as it is)
                color_buf = self.realtime_filter.run(state, color_buf)
                timer.mark("filter")
        gbuf = h.gbuf(h.cur)
        self._last_frame = frame
        self._sample += 1
        h.swap()
        return timer.ms, color_buf, gbuf

    def frame_params(self) -> np.void:
        """FrameParams of the next frame: the image and its random stream key."""
        s = self.settings
        on, index, key = self.qmc if self.qmc is not None else (
            (1, self._sample, s.seed) if qmc.frames_use_sobol(s) else qmc.OFF)
        return L.pack(L.FRAME_PARAMS, width=self.width, height=self.height, pixels=self.pixels, sample=self._sample,
                      seed=s.seed, qmc=on, qmc_index=index % (1 << 32), qmc_key=key)

    def _begin_frame(self, frame: int, jitter_px: tuple[float, float] | None) -> FrameState:
        """Upload the scene at `frame` and decide what history the frame may reuse."""
        s, ds, cam = self.settings, self.device_scene, self.scene.camera
        assert cam is not None
        ds.upload(frame, self._last_frame)
        if ds.light_indices_changed:
            self.history.invalidate()
        cut = frame in cam.cuts and frame != self._last_frame
        consecutive = self._last_frame is not None and frame in (self._last_frame, self._last_frame + 1)
        history = self.history.valid and consecutive and not cut
        light_count = ds.sampled_light_count
        method = s.method
        params = self.frame_params()
        if method == "ris" and light_count == 1 and ds.lights.environment is None and not params["qmc"]:
            # RIS over one light picks that light: leave the loop out (not for the environment, whose candidates
            # are directions that RIS and the BSDF candidates choose between; not for Sobol frames, still or
            # animation, whose points on the light only RIS's candidates draw from the sequence)
            method = "light_array"
        tree = ds.light_tree if self.uses_light_tree and method in ("ris", "restir") and light_count > 1 else None
        tiles = tree is None and self._use_light_tiles(method, light_count)
        self.light_tiles_used = tiles
        mis_sample = self.bsdf_mis_sample(method, light_count)
        pick_table = (self.pick_table.active and tree is None and not tiles
                      and uses_table(s.light_proposal, method, light_count, still=True))
        bsdf = 0 if mis_sample else self._bsdf_candidates(method, light_count)
        hit_tests = bool(bsdf) or mis_sample  # what BSDF rays look for: the candidates' or the MIS sample's
        sampler = L.pack(L.SAMPLER_PARAMS, light_count=light_count, slot_count=ds.light_array.slot_count,
                         light_tree=int(tree is not None), tree_leaves=tree.leaves if tree else 0,
                         tree_distant=tree.distant_count if tree else 0, tree_p_local=tree.p_local if tree else 1.0,
                         tile_count=s.light_tile_count if tiles else 0, tile_size=s.light_tile_size if tiles else 0,
                         bsdf_candidates=bsdf,
                         bsdf_analytic=ds.analytic_lights if hit_tests and ds.analytic_lights <= BSDF_ANALYTIC_MAX
                         else 0,
                         bsdf_triangles=int(hit_tests and ds.triangle_lights),
                         bsdf_glossy_only=int(s.bsdf_sampling == "auto"), pick_table=int(pick_table))
        jit = jitter_px if jitter_px is not None else jitter(self._sample) if s.jitter else (0.0, 0.0)
        # A light switched on or off (or its power jumped) makes last frame's reservoirs samples of another target:
        # kept, they would dilute this frame's estimate for many frames. The decision depends on the scene only, not
        # on any sample, so dropping them keeps the unbiased mode unbiased.
        return FrameState(frame=frame, prev_frame=self._last_frame if history else frame,
                          next_frame=min(frame + 1, ds.frame_count - 1), history=history,
                          restir_history=history and not ds.lights_switched, method=method, tiles=tiles,
                          frame_params=params, sampler=sampler, jitter=jit, mis_sample=mis_sample,
                          pick_table=pick_table)

    def _moving(self, state: FrameState) -> bool:
        """Whether TAA must validate and clip its history. Only a camera that moved between the two frames makes
        this a moving scene: an animation of a still camera (frame numbers advancing, transforms equal) used to clip
        its history to the noisy 3x3 neighbourhood every frame, a lasting bias: the stress case long_animation came
        out 0.7% (ReSTIR) to 16% (light_array) too dark."""
        cam, ds = self.scene.camera, self.device_scene
        assert cam is not None
        if self._prev_view is not None:  # render_view: the last frame's view against this one
            camera_moved = state.history and views_differ(self._prev_view, cam)
        else:
            camera_moved = not np.array_equal(Scene.at(cam.transforms, state.prev_frame),
                                              Scene.at(cam.transforms, state.frame))
        return camera_moved or ds.moving_lights or ds.moving_objects or ds.edited

    def _use_light_tiles(self, method: str, light_count: int) -> bool:
        """RIS candidates from presampled tiles: only for the RIS-based methods, and ("auto") only where the light
        array is too large to stay in cache (LIGHT_TILES_AUTO lights), since the tiles cost a pass per frame."""
        mode = self.settings.light_tiles
        if method not in ("ris", "restir") or light_count < 2 or mode == "off":
            return False
        return mode == "on" or light_count >= LIGHT_TILES_AUTO

    def bsdf_mis_sample(self, method: str, light_count: int) -> bool:
        """Whether `ris` frames add one BSDF sample with its own shadow ray, combined by MIS (direct/bsdf_mis.h); it
        replaces the BSDF candidates."""
        return self.settings.bsdf_mis_sample and method == "ris" and light_count > 0

    def _bsdf_candidates(self, method: str, light_count: int) -> int:
        """BSDF-sampled candidates per pixel this frame (direct/bsdf_candidates.h): for the RIS-based methods, where a
        material is glossy ("auto") or always ("on")."""
        s = self.settings
        if method not in ("ris", "restir") or light_count == 0 or s.bsdf_sampling == "off":
            return 0
        if s.bsdf_sampling == "auto" and not self.device_scene.material_flags.get("HAS_GLOSSY", False):
            return 0
        return s.bsdf_candidates

    def _stills_use_pick_table(self) -> bool:
        """Whether still renders of this scene and settings pick lights from the per-pixel table (compiled in)."""
        s = self.settings
        return (not self.uses_light_tree and not self._use_light_tiles(s.method, self.device_scene.sampled_light_count)
                and uses_table(s.light_proposal, s.method, self.device_scene.sampled_light_count, still=True))

    def will_use_light_tiles(self) -> bool:
        """Whether the frames of this scene and settings (with its current lights) draw their RIS candidates from
        light tiles (never with the light tree's candidates)."""
        return not self.uses_light_tree and self._use_light_tiles(self.settings.method,
                                                             self.device_scene.sampled_light_count)

    # ---- output -----------------------------------------------------------------------------------------

    def _read(self, color_buf: cl.Buffer, gbuf: cl.Buffer, frame: int, scale: float = 1.0, aovs: bool = True) -> Frame:
        q = self.device.queue
        color, noisy, bad = read_colour(q, color_buf, self.buffers.sample, (self.height, self.width), scale)
        self.guard_totals["nonfinite_sample"] += bad
        out = Frame(color=color, noisy=noisy, depth=None, normal=None, vector=None, albedo=None,
                    frame=frame, guards=read_guards(q, self.buffers.guards, self.guard_totals),
                    features=list(self.features))
        if aovs:
            read_aovs(q, out, gbuf, self.buffers.vector)
        return out

    def _read_gbuffer(self, gbuf: cl.Buffer) -> np.ndarray:
        return read_gbuffer(self.device.queue, gbuf, (self.height, self.width))

    def history_length(self) -> np.ndarray:
        """(H, W) TAA history length n of the last rendered frame (1: the pixel restarted from its new sample)."""
        return read_image(self.device.queue, self.history.taa[self.history.prev], (self.height, self.width))[..., 3]

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
    def sample_buf(self) -> cl.Buffer:
        """This frame's noisy estimate s_n."""
        return self.buffers.sample

    @property
    def gbuf(self) -> list[cl.Buffer]:
        """The active chain's G-buffers: slot 1 - _cur holds the last rendered frame's."""
        return self.history.chain.gbuf

    @property
    def res_history(self) -> list[cl.Buffer]:
        return self.history.chain.reservoirs

    @property
    def taa_history(self) -> list[cl.Buffer]:
        return self.history.taa

    @property
    def _cur(self) -> int:
        return self.history.cur

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
    def max_local(self) -> dict[str, int]:
        return self.kernels.max_local

    @max_local.setter
    def max_local(self, value: dict[str, int]) -> None:
        self.kernels.max_local = value
