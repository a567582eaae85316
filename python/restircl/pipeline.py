"""The frame pipeline: one frame reads top to bottom in Renderer.render_frame (DESIGN section 2).

    1 primary    camera rays -> G-buffer (position, normals, albedo, emission, motion)
    2 initial    RIS over `candidates` light-array samples -> reservoir        (restir)
    3 visibility shadow ray for the initial sample, inside restir_initial        (restir, visibility_reuse)
    4 temporal   merge with last frame's reservoir found by reprojection        (restir, temporal, history)
    5 spatial    merge neighbours' reservoirs, `spatial_passes` times           (restir, spatial)
    6 shade      one shadow ray to the chosen sample -> noisy direct light s_n  (every method)
    7 taa        f_n = a s_n + (1 - a) clip(history)                            (taa, animation frames)
    8 output     numpy arrays: colour and AOVs

Steps a scene or a setting does not need are not run, and their code is not compiled (features.py).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pyopencl as cl

from . import layouts as L
from .bvh import build_bvh, make_tris
from .camera import camera_record, halton, jitter
from .device import Device, get_device
from .features import derive_flags, describe, general_flags
from .light_array import build_light_array
from .lights import scene_lights
from .program import build_program
from .scene import Scene
from .settings import (  # noqa: F401  (restircl.pipeline.Settings etc. are public)
    BIAS_CORRECTIONS,
    LIGHT_TILES,
    LIGHT_TILES_AUTO,
    MAX_LIGHT_TILE_ENTRIES,
    METHODS,
    TILE_INFO_BYTES,
    Settings,
)

_METHOD_CODE = {"uniform": 0, "light_array": 1, "ris": 2}


@dataclass
class Frame:
    """One rendered frame: (H, W, ...) float32 arrays, row 0 at the top."""

    color: np.ndarray  # (H, W, 4) RGBA: TAA output (animation) or the accumulated mean (still)
    noisy: np.ndarray  # (H, W, 3) the last 1-sample direct light estimate s_n (emission included)
    # the passes below are None when render_frame(..., aovs=False) left their read-back out
    depth: np.ndarray | None  # (H, W) view depth, inf where the camera ray missed
    normal: np.ndarray | None  # (H, W, 3) world shading normal
    vector: np.ndarray | None  # (H, W, 4) Blender-style Vector pass: xy to the previous frame, zw to the next
    albedo: np.ndarray | None  # (H, W, 3)
    frame: int = 0
    samples: int = 1
    ms: float = 0.0
    stage_ms: dict[str, float] = field(default_factory=dict)
    guards: dict[str, int] = field(default_factory=dict)
    features: list[str] = field(default_factory=list)
    error_estimate: float | None = None  # relMSE estimated from two half buffers (still renders)


def _lights_switched(old: np.ndarray, new: np.ndarray, ratio: float) -> bool:
    """Did any light switch on or off, or change its power by more than `ratio`?"""
    if ratio == 0 or len(old) != len(new):
        return False
    on_old, on_new = old > 0, new > 0
    if np.any(on_old != on_new):
        return True
    both = on_old & on_new
    r = new[both] / old[both]
    return bool(np.any((r > ratio) | (r < 1.0 / ratio)))


def _resolve_device(device: Device | str | None) -> Device:
    if isinstance(device, Device):
        return device
    return get_device(device)


LOCAL_ITEMS = 64  # work-items per work-group: 64 in 1D, 8x8 in 2D (docs/benchmarks.md: PoCL's own pick was slower)


def local_size(dims: int, max_items: int) -> tuple[int, ...]:
    """The local size of a launch: LOCAL_ITEMS work-items (8x8 in 2D), or the largest power of two within
    max_items, the kernel's limit on the device (CL_KERNEL_WORK_GROUP_SIZE: a GPU may allow fewer to a kernel that
    uses many registers or much private memory, as the BVH stacks do)."""
    n = LOCAL_ITEMS
    while n > 1 and n > max_items:
        n //= 2
    if dims == 1:
        return (n,)
    x = 1
    while x * x < n:
        x *= 2
    return (x, n // x)


HALF_BLOCK = 8  # frames per block of a still render's two half buffers (error_estimate)
R2_FLOOR = 0.25  # error_estimate: r^2 is taken as at least R2_FLOOR * mean^2


def _half_of(k: int) -> int:
    """Half buffer (0 or 1) of sample k of a still render: blocks of HALF_BLOCK consecutive frames, the two blocks
    of each pair in an order drawn from a hash of the pair. Any HALF_BLOCK consecutive frames cover the same
    Halton jitter strata, and the coin makes the finer strata exchangeable between the halves."""
    pair = k // (2 * HALF_BLOCK)
    flip = ((pair * 0x9E3779B1 + 0x7F4A7C15) & 0xFFFFFFFF) >> 31
    return ((k // HALF_BLOCK) & 1) ^ flip


class Renderer:
    """Renders a Scene frame by frame on one OpenCL device, keeping ReSTIR and TAA history between frames. The scene
    (with all its frames of animation) is taken as it is at construction: for an edited scene, make a new Renderer."""

    def __init__(self, scene: Scene, settings: Settings | None = None, device: Device | str | None = None) -> None:
        self.scene = scene.validate()
        self.settings = (settings or Settings()).validate()
        # what moves and how long the animation is, decided once: each scans every light, ~50 ms per frame at 1e5
        # explicit lights when asked every frame
        self.moving_objects = scene.has_moving_objects
        self.moving_lights = scene.has_moving_lights
        self.frame_count = scene.frames
        self.device = _resolve_device(device)
        cam = scene.camera
        assert cam is not None
        self.width, self.height = int(cam.width), int(cam.height)
        self.pixels = self.width * self.height
        self._geometry_key: int | None = None
        self._lights_key: int | None = None
        self._light_count: int | None = None
        self._sample = 0  # frames rendered so far: the random seed of the next one
        self._last_frame: int | None = None
        self._history_valid = False
        self._lights_switched = False
        self._lights_changed = True  # this frame's light records differ from (or may differ from) the last frame's
        self._still_counts = (0, 0)
        self.guard_totals = dict.fromkeys(L.GUARD_NAMES[: L.GUARD_COUNT], 0)
        self._alloc()
        self._upload_scene(0)
        self._build()

    # ---- set-up ------------------------------------------------------------------------------------

    def _buf(self, nbytes: int) -> cl.Buffer:
        return cl.Buffer(self.device.context, cl.mem_flags.READ_WRITE, max(int(nbytes), 16))

    def _upload(self, array: np.ndarray) -> cl.Buffer:
        data = np.ascontiguousarray(array)
        if data.nbytes == 0:
            data = np.zeros(16, np.uint8)
        return cl.Buffer(self.device.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=data)

    def _alloc(self) -> None:
        n = self.pixels
        self.gbuf = [self._buf(n * L.GSAMPLE.itemsize) for _ in range(2)]
        self.res_initial = self._buf(n * L.RESERVOIR.itemsize)
        self.res_temp = self._buf(n * L.RESERVOIR.itemsize)
        self.res_history = [self._buf(n * L.RESERVOIR.itemsize) for _ in range(2)]
        self.sample_buf = self._buf(n * 16)
        self.taa_history = [self._buf(n * 16) for _ in range(2)]
        self.sum_buf = self._buf(n * 16)
        self.sum_half = self._buf(n * 16)
        self.guard_buf = self._buf(4 * L.GUARD_COUNT)
        self.cameras = [self._buf(L.CAMERA.itemsize) for _ in range(3)]  # current, previous, next
        self.vector_buf = self._buf(n * 16)
        self.motion_buf: cl.Buffer | None = None  # per-object motion rows, uploaded by _upload_scene
        self.tile_rec: cl.Buffer | None = None  # presampled light tiles, allocated when first used
        self.tile_info: cl.Buffer | None = None
        self.light_tiles_used = False  # whether the last frame drew its RIS candidates from the tiles
        self._no_buffer = self._buf(16)  # bound to the tile arguments of kernels that run without tiles
        cl.enqueue_fill_buffer(self.device.queue, self.guard_buf, np.int32(0), 0, 4 * L.GUARD_COUNT)
        self._cur = 0  # index of the current frame's G-buffer / history slot

    def _upload_scene(self, frame: int) -> None:
        """Upload geometry and lights for `frame` when they differ from what the device holds."""
        scene = self.scene
        geo_key = frame if self.moving_objects else 0
        world = None
        if self._geometry_key != geo_key:
            world = scene.world_triangles(frame)
            t0 = time.perf_counter()
            bvh = build_bvh(world.v0, world.v1, world.v2)
            tris = make_tris(world.v0, world.v1, world.v2, world.material, world.prim, bvh.order)
            tris["e2"][:, 3] = L.int_bits(world.object[bvh.order])
            self.bvh_seconds = time.perf_counter() - t0
            self.nodes_buf = self._upload(bvh.nodes)
            self.tris_buf = self._upload(tris)
            self.triangle_count = len(world)
            mats = np.zeros(max(len(scene.materials), 1), L.MATERIAL)
            for i, m in enumerate(scene.materials):
                mats["albedo"][i, :3] = m.albedo
                mats["emission"][i, :3] = m.radiance
                mats["emission"][i, 3] = float(m.is_emissive)
            self.materials_buf = self._upload(mats)
            self._geometry_key = geo_key
        lights_key = frame if (self.moving_lights or self.moving_objects) else 0
        self._lights_changed = self._lights_key != lights_key
        if self._lights_changed:
            if world is None:
                world = scene.world_triangles(frame)
            lights = scene_lights(scene, frame, world)
            if self._light_count is not None and self._light_count != len(lights):
                self._history_valid = False  # light indices changed: old reservoirs point elsewhere
            elif self._light_count is not None:
                self._lights_switched = _lights_switched(self.lights.power, lights.power,
                                                         self.settings.light_change_ratio)
            self.lights = lights
            self._light_count = len(lights)
            self.light_array = build_light_array(lights.power, self.settings.slots_per_light)
            self.lights_buf = self._upload(lights.records)
            self.slots_buf = self._upload(self.light_array.slots)
            self.light_pdf_buf = self._upload(self.light_array.pdf)
            self._lights_key = lights_key
        # per object: rows of M_prev M_cur^-1 (reprojection), then of M_next M_cur^-1 (the Vector pass); identities
        # (uploaded once) when nothing moves
        if not self.moving_objects and self.motion_buf is not None:
            return
        n_obj = max(len(scene.meshes), 1)
        motion = np.zeros((n_obj, 2, 3, 4), np.float32)
        motion[:, :, :, :3] = np.eye(3)
        if self.moving_objects:
            prev_f = self._last_frame if self._last_frame is not None else frame
            next_f = min(frame + 1, self.frame_count - 1)
            for k, mesh in enumerate(scene.meshes):
                inv = np.linalg.inv(Scene.at(mesh.transforms, frame))
                motion[k, 0] = (Scene.at(mesh.transforms, prev_f) @ inv)[:3, :]
                motion[k, 1] = (Scene.at(mesh.transforms, next_f) @ inv)[:3, :]
        self.motion_buf = self._upload(motion)

    def _build(self) -> None:
        s = self.scene
        # a camera animation whose transforms are all equal does not move: no motion vectors to compile
        moving_camera = s.camera is not None and bool(np.any(s.camera.transforms != s.camera.transforms[:1]))
        if self.settings.specialise:
            flags = derive_flags(self.lights.type_set, moving_camera or self.moving_objects, self.moving_objects)
        else:
            flags = general_flags()
        self.flags = flags
        self.features = describe(flags)
        t0 = time.perf_counter()
        self.program = build_program(self.device, flags)
        self.build_seconds = time.perf_counter() - t0
        names = ["primary", "light_tiles_fill", "shade_direct", "shade_reference", "accumulate", "restir_initial",
                 "restir_temporal", "restir_spatial", "restir_shade", "taa"]
        self.k = {name: cl.Kernel(self.program, name) for name in names}
        self.max_local = {name: int(k.get_work_group_info(cl.kernel_work_group_info.WORK_GROUP_SIZE,
                                                          self.device.device))
                          for name, k in self.k.items()}

    def reset(self) -> None:
        """Drop all history (ReSTIR reservoirs, TAA, accumulation)."""
        self._history_valid = False
        self._last_frame = None

    # ---- parameters ---------------------------------------------------------------------------------

    def _restir_params(self) -> np.void:
        s = self.settings
        p = np.zeros(1, L.RESTIR_PARAMS)
        p["candidates"] = s.candidates
        p["spatial_neighbours"] = s.spatial_neighbours
        p["spatial_radius"] = s.spatial_radius
        p["m_cap"] = s.m_cap * s.candidates
        p["depth_tolerance"] = s.depth_tolerance
        p["normal_cos"] = math.cos(math.radians(s.normal_angle))
        p["frame"] = self._sample
        p["seed"] = s.seed
        return p[0]

    def _taa_params(self, moving: bool) -> np.void:
        s = self.settings
        p = np.zeros(1, L.TAA_PARAMS)
        p["alpha_min"] = s.alpha_min
        p["gamma"] = s.gamma
        p["depth_tolerance"] = s.depth_tolerance
        p["normal_cos"] = math.cos(math.radians(s.normal_angle))
        p["moving"] = int(moving)
        p["max_history"] = s.max_history
        return p[0]

    def _run(self, name: str, size: tuple[int, ...], *args) -> None:
        """Launch with a fixed local size (64 or 8x8, smaller only where the device allows the kernel fewer
        work-items: local_size), the global size padded to a multiple of it (OpenCL 1.2): every kernel returns
        early outside the image. PoCL's own choice was 25-40 % slower (docs/benchmarks.md)."""
        kernel = self.k[name]
        kernel.set_args(*args)
        local = local_size(len(size), self.max_local[name])
        padded = tuple(-(-n // m) * m for n, m in zip(size, local, strict=True))
        cl.enqueue_nd_range_kernel(self.device.queue, kernel, padded, local)

    def _use_light_tiles(self, method: str, light_count: int) -> bool:
        """RIS candidates from presampled tiles: only for the RIS-based methods, and ("auto") only where the light
        array is too large to stay in cache (LIGHT_TILES_AUTO lights), since the tiles cost a pass per frame."""
        mode = self.settings.light_tiles
        if method not in ("ris", "restir") or light_count < 2 or mode == "off":
            return False
        return mode == "on" or light_count >= LIGHT_TILES_AUTO

    def _sampled_light_count(self) -> int:
        """The number of lights the samplers draw from: 0 when no light emits (an empty light array)."""
        return len(self.lights) if self.light_array.slot_count and len(self.light_array.slots) else 0

    def will_use_light_tiles(self) -> bool:
        """Whether the frames of this scene and settings (with its current lights) draw their RIS candidates from
        light tiles."""
        return self._use_light_tiles(self.settings.method, self._sampled_light_count())

    def _fill_light_tiles(self) -> tuple:
        """Draw this frame's light tiles; returns the tile arguments of the RIS kernels."""
        s = self.settings
        entries = s.light_tile_count * s.light_tile_size
        if self.tile_rec is None or self.tile_rec.size < entries * L.LIGHT.itemsize:
            self.tile_rec = self._buf(entries * L.LIGHT.itemsize)
            self.tile_info = self._buf(entries * TILE_INFO_BYTES)
        self._run("light_tiles_fill", (entries,), self.lights_buf, self.slots_buf,
                  np.int32(self.light_array.slot_count), self.light_pdf_buf, np.int32(entries),
                  np.uint32(self._sample), np.uint32(s.seed), self.tile_rec, self.tile_info)
        return self.tile_rec, self.tile_info, np.int32(s.light_tile_count), np.int32(s.light_tile_size)

    # ---- the frame -------------------------------------------------------------------------------------

    def render_frame(self, frame: int, *, still: bool = False, aovs: bool = True) -> Frame:
        """Render animation frame `frame`, carrying history from the previous call (reset on a camera cut).
        aovs=False reads back the colour and the noisy sample only (no depth, normal, vector, albedo): a real-time
        viewer needs no more, and the G-buffer read-back cost ~20 ms per 640x360 frame on a 2-core CPU."""
        t0 = time.perf_counter()
        stage, color_buf, gbuf = self._render(frame, still)
        out = self._read(color_buf, gbuf, frame, aovs=aovs)
        out.stage_ms = stage
        out.ms = (time.perf_counter() - t0) * 1e3
        return out

    def _render(self, frame: int, still: bool, jitter_px: tuple[float, float] | None = None
                ) -> tuple[dict[str, float], cl.Buffer, cl.Buffer]:
        """Run the passes of one frame; returns the stage times (ms), the colour buffer and the G-buffer."""
        s, scene, q = self.settings, self.scene, self.device.queue
        cam = scene.camera
        assert cam is not None
        stage: dict[str, float] = {}

        def mark(name: str, t0: float) -> float:
            q.finish()
            t1 = time.perf_counter()
            stage[name] = stage.get(name, 0.0) + (t1 - t0) * 1e3
            return t1

        t = time.perf_counter()
        self._lights_switched = False
        self._upload_scene(frame)
        cut = frame in cam.cuts and frame != self._last_frame
        consecutive = self._last_frame is not None and frame in (self._last_frame, self._last_frame + 1)
        history = self._history_valid and consecutive and not cut
        prev_frame = self._last_frame if history else frame
        # A light switched on or off (or its power jumped) makes last frame's reservoirs samples of another target:
        # kept, they would dilute this frame's estimate for many frames. The decision depends on the scene only, not
        # on any sample, so dropping them keeps the unbiased mode unbiased.
        restir_history = history and not self._lights_switched
        t = mark("upload", t)

        # 1 primary: camera rays -> G-buffer (ping-pong with last frame's)
        cur, prev = self._cur, 1 - self._cur
        jit = jitter_px if jitter_px is not None else jitter(self._sample) if s.jitter else (0.0, 0.0)
        cl.enqueue_copy(q, self.cameras[0], camera_record(cam, frame, jit))
        cl.enqueue_copy(q, self.cameras[1], camera_record(cam, prev_frame))
        cl.enqueue_copy(q, self.cameras[2], camera_record(cam, min(frame + 1, self.frame_count - 1)))
        w, h, n = self.width, self.height, self.pixels
        self._run("primary", (w, h), *self.cameras, self.nodes_buf, self.tris_buf, self.materials_buf,
                  self.motion_buf, self.gbuf[cur], self.vector_buf)
        t = mark("primary", t)

        light_count = self._sampled_light_count()
        la = (self.lights_buf, np.int32(light_count), self.slots_buf, np.int32(self.light_array.slot_count),
              self.light_pdf_buf)
        geo = (self.nodes_buf, self.tris_buf)
        method = s.method
        if method == "ris" and light_count == 1:
            method = "light_array"  # RIS over one light picks that light: leave the loop out
        # presampled light tiles (many lights): the RIS candidates of this frame come from them
        self.light_tiles_used = self._use_light_tiles(method, light_count)
        tiles = (self._no_buffer, self._no_buffer, np.int32(0), np.int32(0))
        if self.light_tiles_used:
            tiles = self._fill_light_tiles()
            t = mark("tiles", t)
        if method == "restir":
            params = self._restir_params()
            bias = np.int32(BIAS_CORRECTIONS.index(s.bias_correction))
            vis = np.int32(s.visibility_reuse)
            # 2-3 initial reservoirs (RIS), visibility of the chosen sample
            self._run("restir_initial", (n,), self.gbuf[cur], np.int32(n), *geo, *la, *tiles, params, vis,
                      self.res_initial)
            t = mark("initial", t)
            res = self.res_initial
            # 4 temporal reuse
            if s.temporal and restir_history:
                self._run("restir_temporal", (w, h), self.gbuf[cur], self.gbuf[prev], np.int32(w), np.int32(h), *geo,
                          self.lights_buf, params, bias, vis, np.int32(not self._lights_changed), res,
                          self.res_history[prev], self.res_temp, self.guard_buf)
                res = self.res_temp
                t = mark("temporal", t)
            # 5 spatial reuse, ping-pong between the temporal buffer and this frame's history slot
            if s.spatial and s.spatial_neighbours > 0:
                bufs = [self.res_history[cur], self.res_temp if res is not self.res_temp else self.res_initial]
                for p in range(s.spatial_passes):
                    dst = bufs[p % 2]
                    self._run("restir_spatial", (w, h), self.gbuf[cur], np.int32(w), np.int32(h), *geo,
                              self.lights_buf, params, bias, vis, np.int32(p), res, dst)
                    res = dst
                t = mark("spatial", t)
            if res is not self.res_history[cur]:
                cl.enqueue_copy(q, self.res_history[cur], res)
            # 6 shade: one shadow ray to the final sample
            known = s.visibility_reuse and s.bias_correction != "none"
            self._run("restir_shade", (n,), self.gbuf[cur], np.int32(n), *geo, self.lights_buf,
                      self.res_history[cur], np.int32(known), self.guard_buf, self.sample_buf)
            t = mark("shade", t)
        elif method == "reference":
            self._run("shade_reference", (n,), self.gbuf[cur], np.int32(n), *geo, self.lights_buf,
                      np.int32(light_count), np.uint32(self._sample), np.uint32(s.seed), self.guard_buf,
                      self.sample_buf)
            t = mark("shade", t)
        else:
            self._run("shade_direct", (n,), self.gbuf[cur], np.int32(n), *geo, *la, *tiles,
                      np.int32(_METHOD_CODE[method]), np.int32(s.candidates), np.uint32(self._sample),
                      np.uint32(s.seed), self.guard_buf, self.sample_buf)
            t = mark("shade", t)

        # 7 temporal accumulation (animation frames only; a still render averages instead)
        color_buf = self.sample_buf
        if s.taa and not still:
            # Only a camera that moved between the two frames makes this a moving scene: an animation of a still
            # camera (frame numbers advancing, transforms equal) used to clip its history to the noisy 3x3
            # neighbourhood every frame, a lasting bias: the stress case long_animation came out 0.7% (ReSTIR) to
            # 16% (light_array) too dark.
            camera_moved = not np.array_equal(Scene.at(cam.transforms, prev_frame), Scene.at(cam.transforms, frame))
            moving = camera_moved or self.moving_lights or self.moving_objects
            self._run("taa", (w, h), self.sample_buf, self.gbuf[cur], self.gbuf[prev], self.taa_history[prev],
                      self.taa_history[cur], np.int32(w), np.int32(h), self._taa_params(moving=moving),
                      np.int32(not history), self.guard_buf)
            color_buf = self.taa_history[cur]
            t = mark("taa", t)

        self._history_valid = True
        self._last_frame = frame
        self._sample += 1
        self._cur = prev
        return stage, color_buf, self.gbuf[cur]

    # ---- output -----------------------------------------------------------------------------------------

    def _read_guards(self) -> dict[str, int]:
        g = np.zeros(L.GUARD_COUNT, np.int32)
        cl.enqueue_copy(self.device.queue, g, self.guard_buf)
        cl.enqueue_fill_buffer(self.device.queue, self.guard_buf, np.int32(0), 0, 4 * L.GUARD_COUNT)
        for i, name in enumerate(L.GUARD_NAMES[: L.GUARD_COUNT]):
            self.guard_totals[name] += int(g[i])
        return dict(self.guard_totals)

    def _read_gbuffer(self, gbuf: cl.Buffer) -> np.ndarray:
        g = np.empty(self.pixels, L.GSAMPLE)
        cl.enqueue_copy(self.device.queue, g, gbuf)
        return g.reshape(self.height, self.width)

    def _read(self, color_buf: cl.Buffer, gbuf: cl.Buffer, frame: int, scale: float = 1.0, aovs: bool = True) -> Frame:
        q = self.device.queue
        h, w = self.height, self.width
        color = np.empty((h, w, 4), np.float32)
        cl.enqueue_copy(q, color, color_buf)
        noisy = np.empty((h, w, 4), np.float32)
        cl.enqueue_copy(q, noisy, self.sample_buf)
        rgb = color[..., :3]
        if scale != 1.0:
            rgb *= np.float32(scale)
        if not np.isfinite(rgb).all():  # the kernels guard already; this keeps a NaN from ever leaving the renderer
            bad = ~np.isfinite(rgb)
            rgb[bad] = 0.0
            self.guard_totals["nonfinite_sample"] += int(bad.any(axis=-1).sum())
        color[..., 3] = 1.0
        # noisy: a (H, W, 3) view of the RGBA read-back (a copy cost ~1.5 ms per 640x360 frame)
        out = Frame(color=color, noisy=noisy[..., :3], depth=None, normal=None, vector=None, albedo=None,
                    frame=frame, guards=self._read_guards(), features=list(self.features))
        if aovs:
            g = self._read_gbuffer(gbuf)
            hit = L.float_bits_to_int(g["normal"][..., 3]) >= 0
            vector = np.empty((h, w, 4), np.float32)
            cl.enqueue_copy(q, vector, self.vector_buf)
            vector[..., 1] *= -1.0  # Blender's pixel y points up
            vector[..., 3] *= -1.0
            out.depth = np.where(hit, g["pos"][..., 3], np.inf).astype(np.float32)
            out.normal = np.where(hit[..., None], g["normal"][..., :3], 0.0).astype(np.float32)
            out.vector = vector
            out.albedo = np.where(hit[..., None], g["albedo"][..., :3], 0.0).astype(np.float32)
        return out

    def history_length(self) -> np.ndarray:
        """(H, W) TAA history length n of the last rendered frame (1: the pixel restarted from its new sample)."""
        hist = np.empty((self.height, self.width, 4), np.float32)
        cl.enqueue_copy(self.device.queue, hist, self.taa_history[1 - self._cur])
        return hist[..., 3]

    # ---- still renders --------------------------------------------------------------------------------

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
        q = self.device.queue
        for b in (self.sum_buf, self.sum_half):
            cl.enqueue_fill_buffer(q, b, np.float32(0), 0, self.pixels * 16)
        n_half = 0
        done = 0
        stage: dict[str, float] = {}
        t0 = time.perf_counter()
        gbuf = self.gbuf[self._cur]
        # ReSTIR's temporal reuse correlates consecutive frames: each half buffer gets its own chain of reservoirs
        # (and G-buffers), so the two halves stay independent (error_estimate).
        chains = self.settings.method == "restir" and self.settings.temporal
        saved: dict[int, tuple] = {}
        active: int | None = None
        # Pixel jitter: one Halton sequence shared by the halves would put them in different strata, and their
        # difference would see antialiasing error as noise (stratified, the mean's error falls faster than 1/n).
        # Two independently shifted Halton sequences (randomised QMC) are independent estimates of the pixel.
        counts = [0, 0]
        shifts = np.random.default_rng([self.settings.seed, 0x5EED]).random((2, 2))
        for k in range(max(int(samples), 1)):
            if should_stop is not None and done > 0 and should_stop():
                break
            half = _half_of(k)
            jit = None
            if self.settings.jitter:  # each half its own Halton sequence with its own random shift (see below)
                i = counts[half] = counts[half] + 1
                jit = ((halton(i, 2) + shifts[half][0]) % 1.0 - 0.5, (halton(i, 3) + shifts[half][1]) % 1.0 - 0.5)
            if chains and half != active:
                if active is not None:
                    saved[active] = (self.gbuf, self.res_history, self._cur, self._history_valid)
                    if half in saved:
                        self.gbuf, self.res_history, self._cur, self._history_valid = saved[half]
                    else:  # the second chain starts from fresh buffers, without history
                        self.gbuf, self.res_history = self._chain_buffers()
                        self._history_valid = False
                active = half
            st, _, gbuf = self._render(frame, still=True, jitter_px=jit)
            for key, v in st.items():
                stage[key] = stage.get(key, 0.0) + v
            self._run("accumulate", (self.pixels,), self.sample_buf, np.int32(self.pixels), np.int32(half),
                      self.sum_buf, self.sum_half)
            n_half += half
            done += 1
            self._still_counts = (done, n_half)
            if progress is not None:
                progress(done, samples)
            if checkpoint is not None:
                q.finish()
                tc = time.perf_counter()
                checkpoint(done, tc - t0)
                t0 += time.perf_counter() - tc  # the caller's look at the image is not render time
            if target_error is not None and done >= 2 * HALF_BLOCK and done % 4 == 0:
                estimate = self.error_estimate(done, n_half)
                if estimate is not None and estimate <= target_error:
                    break
        first = _half_of(0)
        if chains and active is not None and active != first:  # back to the first chain's (the renderer's) buffers
            self.gbuf, self.res_history, self._cur, self._history_valid = saved[first]
        out = self._read(self.sum_buf, gbuf, frame, scale=1.0 / done)
        noisy = np.empty((self.height, self.width, 4), np.float32)
        cl.enqueue_copy(q, noisy, self.sample_buf)
        out.noisy = noisy[..., :3].copy()
        out.samples = done
        out.stage_ms = {k: v / done for k, v in stage.items()}
        out.ms = (time.perf_counter() - t0) * 1e3 / done
        out.error_estimate = self.error_estimate(done, n_half) if done >= 2 else None
        return out

    @property
    def still_counts(self) -> tuple[int, int]:
        """(samples accumulated, of which in half buffer 1) of the still render in progress."""
        return self._still_counts

    def mean_image(self) -> np.ndarray:
        """(H, W, 3) running mean of the still render in progress (for checkpoint callbacks)."""
        done, _ = self._still_counts
        total = np.empty((self.height, self.width, 4), np.float32)
        cl.enqueue_copy(self.device.queue, total, self.sum_buf)
        return total[..., :3] / max(done, 1)

    def _chain_buffers(self) -> tuple[list[cl.Buffer], list[cl.Buffer]]:
        """G-buffers and reservoir histories of the second chain of a still ReSTIR render (allocated once)."""
        if getattr(self, "_chain2", None) is None:
            n = self.pixels
            self._chain2 = ([self._buf(n * L.GSAMPLE.itemsize) for _ in range(2)],
                            [self._buf(n * L.RESERVOIR.itemsize) for _ in range(2)])
        return self._chain2

    def error_estimate(self, done: int, n_half: int) -> float | None:
        """relMSE of the running mean estimated from two half buffers, no reference needed: the halves are
        independent estimates, so E|a - b|^2 = var_a + var_b, and the full mean has a quarter of that when the
        halves are equal in size (relative to r^2 + 0.01 as relMSE is, r^2 estimated robustly, see below).

        What makes the halves independent (render_still): they are blocks of HALF_BLOCK frames (_half_of), not
        odd and even frames, each with its own randomly shifted Halton jitter sequence (odd and even frames of one
        sequence sit in different strata: the estimate was 17x too large at 256 samples on a small cornell_box,
        and with one sequence split in blocks it still grew 2x too large by 256 samples on many_lights, whose
        sub-pixel lamps are antialiased faster than 1/n); and ReSTIR with temporal reuse runs one chain of
        reservoirs per half (correlated frames made it 2-10x too small)."""
        if n_half == 0 or done - n_half == 0:
            return None
        q = self.device.queue
        total = np.empty((self.pixels, 4), np.float32)
        half = np.empty((self.pixels, 4), np.float32)
        cl.enqueue_copy(q, total, self.sum_buf)
        cl.enqueue_copy(q, half, self.sum_half)
        a = half[:, :3] / n_half
        b = (total[:, :3] - half[:, :3]) / (done - n_half)
        mean = total[:, :3] / done
        var_mean = (a - b) ** 2 * (n_half * (done - n_half)) / (done * done)
        # r^2 of relMSE's denominator: mean^2 is inflated by the very outliers whose error it should weigh (one
        # firefly in a half caps the pixel's term near 1); the harmonic mean of the halves ignores one outlier
        # half but is 0 where a half is (a sub-pixel light hit in one half only), so it is floored at (mean / 2)^2.
        s = a + b
        hm = np.divide(2 * a * b, s, out=np.zeros_like(s), where=s > 0)
        r2 = np.maximum(hm * hm, R2_FLOOR * mean * mean)
        return float(np.mean(var_mean / (r2 + 0.01)))
