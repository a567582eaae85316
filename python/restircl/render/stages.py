"""The stages of a frame (DESIGN section 2), one class each: what it launches, with which buffers and parameters.

A stage reads the frame's state (FrameState: which frames, what history may be reused, how lights are sampled),
packs its own parameter struct (types.h, core/layouts.py) and launches its kernel with every argument named
(core/kernels.py). Which stages run is the frame's plan (render/plan.py); their order is Renderer.run_frame's
(render/pipeline.py).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import pyopencl as cl

from ..core import layouts as L
from ..core.buffers import FrameBuffers, alloc
from ..core.kernels import Kernels
from ..scene.camera import Camera
from ..settings.table import BOILING_MODES, TAA_FILTERS
from ..upload.device_scene import DeviceScene
from .camera import camera_record, camera_sequence
from .history import History
from .plan import FramePlan

if TYPE_CHECKING:
    from ..settings.table import Settings


@dataclass
class FrameState:
    """What one frame's stages share: its plan (render/plan.py) and the records packed from it at its start
    (Renderer.run_frame)."""

    plan: FramePlan
    frame_params: np.void  # FrameParams
    sampler: np.void  # SamplerParams
    jitter: tuple[float, float] = (0.0, 0.0)
    sweep: tuple[float, float] = (0.0, 0.0)  # motion blur: the shutter, in frames from the frame's time (TAA)


def sampler_params(plan: FramePlan, scene: DeviceScene, settings: Settings) -> np.void:
    """SamplerParams of a frame: where its light candidates come from and what its BSDF rays look for, as its plan
    says."""
    tree = scene.light_tree if plan.light_tree else None
    return L.pack(L.SAMPLER_PARAMS, light_count=scene.sampled_light_count, slot_count=scene.light_array.slot_count,
                  light_tree=int(tree is not None), tree_leaves=tree.leaves if tree else 0,
                  tree_distant=tree.distant_count if tree else 0, tree_p_local=tree.p_local if tree else 1.0,
                  tile_count=settings.light_tile_count if plan.tiles else 0,
                  tile_size=settings.light_tile_size if plan.tiles else 0, bsdf_candidates=plan.bsdf_candidates,
                  bsdf_analytic=plan.bsdf_analytic, bsdf_triangles=int(plan.bsdf_triangles),
                  bsdf_glossy_only=int(plan.bsdf_glossy_only), pick_table=int(plan.pick_table))


def permutation_key(settings: Settings, state: FrameState, gi: bool = False) -> int:
    """The frame's permutation-sampling key of temporal reuse (camera/reproject.h): one of the 16, from the frame's
    random stream; 0 with temporal_permutation (gi: gi_temporal_permutation) off."""
    if not (settings.gi_temporal_permutation if gi else settings.temporal_permutation):
        return 0
    key = int(state.frame_params["sample"]) * 0x9E3779B1 + int(state.frame_params["seed"]) * 0x85EBCA6B
    return 16 | ((key & 0xFFFFFFFF) >> 28)


def pixel_count(state: FrameState) -> tuple[int]:
    """The 1D launch size of a per-pixel kernel."""
    return (int(state.frame_params["pixels"]),)


def image_size(state: FrameState) -> tuple[int, int]:
    """The 2D launch size of a per-pixel kernel."""
    return (int(state.frame_params["width"]), int(state.frame_params["height"]))


class Untimed:
    """A StageTimer that marks nothing (and waits for nothing)."""

    def mark(self, name: str) -> None:
        pass


@dataclass
class StageTimer:
    """Milliseconds per stage; with `wait` each mark waits for the queue, so a stage's time is its own. Without it
    (the frames of a still render, render/still.py) a mark records only that the stage ran and the host's time to
    enqueue it: the device then runs the stages back to back instead of idling while the host prepares each next
    one (docs/measurements/benchmarks.md, "Still frames without a wait per stage"); the frame's first upload still
    waits for the frame before."""

    queue: cl.CommandQueue
    ms: dict[str, float] = field(default_factory=dict)
    t: float = field(default_factory=time.perf_counter)
    wait: bool = True

    def mark(self, name: str) -> None:
        if self.wait:
            self.queue.finish()
        t1 = time.perf_counter()
        self.ms[name] = self.ms.get(name, 0.0) + (t1 - self.t) * 1e3
        self.t = t1


class Stage:
    """The device-side state every stage reaches: kernels, the scene's buffers, the frame's and the history's."""

    def __init__(self, kernels: Kernels, scene: DeviceScene, buffers: FrameBuffers, history: History,
                 settings: Settings) -> None:
        self.kernels = kernels
        self.scene = scene
        self.buffers = buffers
        self.history = history
        self.settings = settings

    def _similarity(self) -> np.void:
        """How far a history or neighbour surface may differ from the pixel's (temporal, spatial, taa)."""
        s = self.settings
        return L.pack(L.SIMILARITY_PARAMS, depth_tolerance=s.depth_tolerance,
                      normal_cos=math.cos(math.radians(s.normal_angle)))


class Primary(Stage):
    """1: camera rays -> this frame's G-buffer and the Vector pass."""

    def run(self, state: FrameState, camera: Camera, prev_camera: Camera | None, layer_args: dict) -> None:
        """prev_camera: the previous frame's camera where it is another one (an interactive view); layer_args: the
        layer arguments (render/layers.py CameraLayers.arguments: layer -1 where the frame has no weighted layers)."""
        q, b, h = self.kernels.device.queue, self.buffers, self.history
        if layer_args["layer"] <= 0:  # a frame's later layers see through the same cameras
            cl.enqueue_copy(q, b.cameras[0], camera_record(camera, state.plan.frame, state.jitter,
                                                             state.plan.texture_full,
                                                             camera_sequence(int(state.frame_params["sample"]),
                                                                             int(state.frame_params["seed"]))))
            cl.enqueue_copy(q, b.cameras[1], camera_record(prev_camera or camera, state.plan.prev_frame))
            cl.enqueue_copy(q, b.cameras[2], camera_record(camera, state.plan.next_frame))
        self.kernels.launch("primary", image_size(state), cam=b.cameras[0],
                            prev_cam=b.cameras[1], next_cam=b.cameras[2], **self.scene.geometry,
                            **self.scene.surface, ggx_tables=self.scene.ggx_tables_buf or b.none,
                            object_motion=self.scene.motion_buf, lights=self.scene.lights_buf,
                            camera_lights=self.scene.camera_lights_buf, gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                            vector=b.vector, light_passes=b.light_passes, frame_params=state.frame_params,
                            **layer_args)


class LightTiles(Stage):
    """Presampled light tiles (many lights): this frame's RIS candidates are drawn from them."""

    def __init__(self, *args, info_bytes: int) -> None:
        super().__init__(*args)
        self.info_bytes = info_bytes
        self.tile_rec: cl.Buffer | None = None  # allocated when first used
        self.tile_info: cl.Buffer | None = None

    def run(self, state: FrameState) -> None:
        s = self.settings
        entries = s.light_tile_count * s.light_tile_size
        if self.tile_rec is None or self.tile_rec.size < entries * L.LIGHT.itemsize:
            context = self.kernels.device.context
            self.tile_rec = alloc(context, entries * L.LIGHT.itemsize)
            self.tile_info = alloc(context, entries * self.info_bytes)
        self.kernels.launch("light_tiles_fill", (entries,), **self.scene.light_sampling, tile_rec=self.tile_rec,
                            tile_info=self.tile_info, frame_params=state.frame_params, sampler=state.sampler)

    def arguments(self, state: FrameState) -> dict[str, cl.Buffer]:
        """The tile arguments of the RIS kernels (a placeholder buffer when this frame uses no tiles)."""
        if not state.plan.tiles:
            return {"tile_rec": self.buffers.none, "tile_info": self.buffers.none}
        return {"tile_rec": self.tile_rec, "tile_info": self.tile_info}


class Initial(Stage):
    """2-3: RIS over the light candidates into a reservoir; with visibility reuse, the chosen sample's shadow ray."""

    def run(self, state: FrameState, tiles: dict[str, cl.Buffer]) -> cl.Buffer:
        s, h = self.settings, self.history
        params = L.pack(L.INITIAL_PARAMS, sampler=state.sampler, candidates=s.candidates,
                        visibility_reuse=int(s.visibility_reuse))
        out = self.buffers.res_initial
        self.kernels.launch("restir_initial", pixel_count(state), gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                            **self.scene.geometry, **self.scene.light_sampling, **self.scene.light_tree_args,
                            **tiles, tri_light=self.scene.tri_light_buf, out=out, frame_params=state.frame_params,
                            params=params)
        return out


class Temporal(Stage):
    """4: merge with last frame's reservoir of the same surface, found by reprojection."""

    def __init__(self, *args, bias_code: int) -> None:
        super().__init__(*args)
        self.bias_code = bias_code

    def _static(self) -> bool:
        """Whether last frame's shadow tests hold in this frame: no object or light moved or was edited."""
        ds = self.scene
        return not (ds.lights_changed or ds.moving_objects or ds.moving_lights or ds.edited)

    def run(self, state: FrameState, current: cl.Buffer) -> cl.Buffer:
        s, h = self.settings, self.history
        per_frame = s.candidates + int(state.sampler["bsdf_candidates"])  # the M of an initial reservoir
        params = L.pack(L.TEMPORAL_PARAMS, m_cap=s.m_cap * per_frame, similar=self._similarity(),
                        bias_correction=self.bias_code, visibility_reuse=int(s.visibility_reuse),
                        lights_static=int(not self.scene.lights_changed),
                        permutation=permutation_key(s, state), vis_static=int(self._static()),
                        vis_max_age=s.visibility_max_age, vis_max_distance=s.visibility_max_distance)
        out = self.buffers.res_temp
        self.kernels.launch("restir_temporal", image_size(state), cam=self.buffers.cameras[0], gbuf=h.gbuf(h.cur),
                            prev_gbuf=h.gbuf(h.prev),
                            glossy=h.glossy(h.cur), prev_glossy=h.glossy(h.prev),
                            **self.scene.geometry, lights=self.scene.lights_buf, current=current,
                            previous=h.reservoirs(h.prev), out=out, guards=self.buffers.guards,
                            frame_params=state.frame_params, params=params)
        return out


class BoilingFilter(Stage):
    """4b (animation path): empty (or make the history forget) the reservoirs whose weight or contribution stands far
    above their tile's (restir/boiling.cl, Settings.boiling_mode)."""

    TILE = 8

    def __init__(self, *args, kernels: str = "", strength: str = "boiling_filter") -> None:
        """kernels: the prefix of the kernels' names, strength: the setting of the filter's strength (ReSTIR GI's
        reservoirs: "gi_" and gi_boiling_filter, restir_gi/boiling.cl)."""
        super().__init__(*args)
        self._stats: cl.Buffer | None = None
        self.prefix = kernels
        self.strength = strength

    def run(self, state: FrameState, res: cl.Buffer) -> None:
        w, h = image_size(state)
        tiles_x = -(-w // self.TILE)
        tiles = tiles_x * -(-h // self.TILE)
        if self._stats is None:
            self._stats = alloc(self.kernels.device.context, tiles * 8)
        strength = min(max(float(getattr(self.settings, self.strength)), 1e-6), 1.0)
        mode = np.int32(BOILING_MODES.index(self.settings.boiling_mode))
        self.kernels.launch(self.prefix + "boiling_tiles", (tiles,), res=res, tile_stats=self._stats,
                            frame_params=state.frame_params, tiles_x=np.int32(tiles_x), mode=mode)
        self.kernels.launch(self.prefix + "boiling_filter", image_size(state), res=res, tile_stats=self._stats,
                            frame_params=state.frame_params, tiles_x=np.int32(tiles_x),
                            threshold=np.float32(10.0 / strength - 9.0), mode=mode)


class Spatial(Stage):
    """5: merge neighbours' reservoirs, `spatial_passes` times, ping-pong between this frame's history slot and
    whichever scratch buffer does not hold the input."""

    def __init__(self, *args, bias_code: int) -> None:
        super().__init__(*args)
        self.bias_code = bias_code

    def run(self, state: FrameState, res: cl.Buffer, tiles: dict[str, cl.Buffer]) -> cl.Buffer:
        s, h, b = self.settings, self.history, self.buffers
        bufs = [h.reservoirs(h.cur), b.res_temp if res is not b.res_temp else b.res_initial]
        for p in range(s.spatial_passes):
            dst = bufs[p % 2]
            params = L.pack(L.SPATIAL_PARAMS, spatial_neighbours=s.spatial_neighbours,
                            spatial_radius=s.spatial_radius, similar=self._similarity(), bias_correction=self.bias_code,
                            visibility_reuse=int(s.visibility_reuse), pass_index=p,
                            boost_neighbours=s.disocclusion_boost,
                            fresh_m=s.candidates + int(state.sampler["bsdf_candidates"]),
                            fresh_candidates=s.fresh_candidates, sampler=state.sampler)
            self.kernels.launch("restir_spatial", image_size(state), gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                                **self.scene.geometry, **self.scene.light_sampling, **self.scene.light_tree_args,
                                **tiles, tri_light=self.scene.tri_light_buf, input=res, out=dst,
                                frame_params=state.frame_params, params=params)
            res = dst
        return res


class Shade(Stage):
    """6: one shadow ray to the pixel's sample -> the noisy direct light s_n (ReSTIR's reservoir, a sampler
    without reuse, or the exhaustive reference)."""

    def __init__(self, *args, method_codes: dict[str, int]) -> None:
        super().__init__(*args)
        self.method_codes = method_codes

    def _common(self, state: FrameState) -> dict:
        h = self.history
        return {"gbuf": h.gbuf(h.cur), "glossy": h.glossy(h.cur), **self.scene.geometry,
                "lights": self.scene.lights_buf, "guards": self.buffers.guards, "out": self.buffers.sample,
                "light_passes": self.buffers.light_passes, "frame_params": state.frame_params}

    def restir(self, state: FrameState) -> None:
        """Shade the reservoir this frame leaves as history."""
        s, h = self.settings, self.history
        known = s.visibility_reuse and s.bias_correction != "none"
        params = L.pack(L.SHADE_PARAMS, sampler=state.sampler, visible_known=int(known), clamp_direct=s.clamp_direct)
        self.kernels.launch("restir_shade", pixel_count(state), **self._common(state), res=h.reservoirs(h.cur),
                            params=params)

    def direct(self, state: FrameState, tiles: dict[str, cl.Buffer], pick_table: cl.Buffer | None = None) -> None:
        """pick_table: the still render's per-pixel light pick, where state.plan.pick_table says the frame uses it."""
        params = L.pack(L.SHADE_PARAMS, sampler=state.sampler, method=self.method_codes[state.plan.method],
                        candidates=self.settings.candidates,
                        bsdf_mis_sample=int(state.plan.mis_sample), clamp_direct=self.settings.clamp_direct)
        self.kernels.launch("shade_direct", pixel_count(state), **self._common(state), slots=self.scene.slots_buf,
                            light_pdf=self.scene.light_pdf_buf, **self.scene.light_tree_args, **tiles,
                            tri_light=self.scene.tri_light_buf, pick_table=pick_table or self.buffers.none,
                            params=params)

    def reference(self, state: FrameState) -> None:
        params = L.pack(L.SHADE_PARAMS, sampler=state.sampler, clamp_direct=self.settings.clamp_direct)
        self.kernels.launch("shade_reference", pixel_count(state), **self._common(state), params=params)


class Paths(Stage):
    """6b (max_bounces > 0): light that bounced after the primary hit (path/path.cl), added to this frame's sample
    and kept in its own buffer (the indirect light of the frame)."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.indirect: cl.Buffer | None = None

    def run(self, state: FrameState) -> None:
        h = self.history
        self.kernels.launch("path_trace", pixel_count(state), gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                            **self.arguments(state), sample=self.buffers.sample, indirect=self.indirect_buffer(state),
                            light_passes=self.buffers.light_passes,
                            params=path_params(self.scene, self.settings, state.plan))

    def indirect_buffer(self, state: FrameState) -> cl.Buffer:
        """The frame's indirect light (allocated at the first frame with bounces)."""
        if self.indirect is None:
            self.indirect = alloc(self.kernels.device.context, int(state.frame_params["pixels"]) * 16)
        return self.indirect

    def arguments(self, state: FrameState) -> dict:
        """What a path's walk reads (path/walk.h): the scene's geometry, surfaces and lights, the guards."""
        ggx = self.scene.ggx_tables_buf or self.buffers.none
        return {**self.scene.geometry, **self.scene.surface, "ggx_tables": ggx, **self.scene.light_sampling,
                **self.scene.light_tree_args, "tri_light": self.scene.tri_light_buf,
                "guards": self.buffers.guards, "frame_params": state.frame_params}


def path_params(scene: DeviceScene, settings: Settings, plan: FramePlan) -> np.void:
    """PathParams of a frame: NEE's light pick at path vertices, what their rays look for, Cycles' Light Paths."""
    s, tree = settings, scene.light_tree if plan.path_light_tree else None
    sampler = L.pack(L.SAMPLER_PARAMS, light_count=scene.sampled_light_count, slot_count=scene.light_array.slot_count,
                     light_tree=int(tree is not None), tree_leaves=tree.leaves if tree else 0,
                     tree_distant=tree.distant_count if tree else 0, tree_p_local=tree.p_local if tree else 1.0,
                     bsdf_analytic=plan.path_analytic, bsdf_triangles=int(plan.path_triangles),
                     # the direct estimator's BSDF candidates: the walk counts the first ray's emitters at smooth
                     # glass where it drew none (path/walk.h); paths read no other use of them
                     bsdf_candidates=plan.bsdf_candidates, bsdf_glossy_only=int(plan.bsdf_glossy_only))
    return L.pack(L.PATH_PARAMS, sampler=sampler, max_bounces=s.max_bounces, max_diffuse=s.diffuse_bounces,
                  max_glossy=s.glossy_bounces, min_bounces=s.min_light_bounces, clamp_indirect=s.clamp_indirect,
                  light_threshold=s.light_threshold, max_transmission=s.transmission_bounces,
                  split_glass=int(plan.gi and plan.paths))


class RealtimeFilter(Stage):
    """8 (animation path, realtime_filter): the edge-aware a-trous filter of the TAA output (filter/atrous.cl), into its
    own buffers: the TAA history stays unfiltered."""

    SIGMA_L = 4.0  # SVGF's luminance edge stop
    SIGMA_Z = 0.02  # relative depth per pixel of tap spacing

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self._bufs: list[cl.Buffer] = []

    def run(self, state: FrameState, taa: cl.Buffer) -> cl.Buffer:
        w, hgt = image_size(state)
        if not self._bufs:
            self._bufs = [alloc(self.kernels.device.context, w * hgt * 16) for _ in range(2)]
        gbuf = self.history.gbuf(self.history.cur)
        self.kernels.launch("filter_variance", (w, hgt), sample=self.buffers.sample, taa=taa, out=self._bufs[0],
                            frame_params=state.frame_params)
        for k in range(self.settings.filter_iterations):
            src, dst = self._bufs[k % 2], self._bufs[(k + 1) % 2]
            params = L.pack(L.ATROUS_PARAMS, step=1 << k, sigma_l=self.SIGMA_L, sigma_z=self.SIGMA_Z)
            self.kernels.launch("atrous", (w, hgt), input=src, out=dst, gbuf=gbuf,
                                frame_params=state.frame_params, params=params)
        return self._bufs[self.settings.filter_iterations % 2]


class Taa(Stage):
    """7: f_n = a s_n + (1 - a) clip(history): blends into this frame's TAA slot, which it returns."""

    def run(self, state: FrameState, moving: bool) -> cl.Buffer:
        s, h = self.settings, self.history
        params = L.pack(L.TAA_PARAMS, alpha_min=s.alpha_min, gamma=s.gamma, similar=self._similarity(),
                        moving=int(moving), max_history=s.max_history, reset=int(not state.plan.history),
                        filter=TAA_FILTERS.index(s.taa_filter), dilate=int(s.taa_dilation),
                        fresh_fill=int(s.taa_fresh_fill), clip_surface=int(s.taa_clip_surface),
                        sweep_open=state.sweep[0], sweep_close=state.sweep[1])
        self.kernels.launch("taa", image_size(state), sample=self.buffers.sample, gbuf=h.gbuf(h.cur),
                            glossy=h.glossy(h.cur),
                            prev_gbuf=h.gbuf(h.prev), history_in=h.taa[h.prev], history_out=h.taa[h.cur],
                            guards=self.buffers.guards, frame_params=state.frame_params, params=params)
        return h.taa[h.cur]

