"""Still renders: frames of a still camera averaged into a running sum, split into two half buffers whose
difference estimates the error of the mean without a reference (StillAccumulation.error_estimate).

What makes the halves independent: they are blocks of HALF_BLOCK frames (half_of), not odd and even frames, each
with its own randomly shifted Halton jitter sequence (odd and even frames of one sequence sit in different strata:
the estimate was 17x too large at 256 samples on a small cornell_box, and with one sequence split in blocks it
still grew 2x too large by 256 samples on many_lights, whose sub-pixel lamps are antialiased faster than 1/n); and
ReSTIR with temporal reuse runs one chain of history per half (render/history.py; correlated frames made it 2-10x too
small).

The loop (render_still) drives the renderer through its public frame API (FrameSource: Renderer.run_frame,
read_frame, frame_params), as any tool may; it decides nothing about a frame but its jitter, its Sobol index and
key, the chain of history it continues, and its time within the shutter (motion blur, render/shutter.py).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Protocol

import numpy as np
import pyopencl as cl

from ..core.buffers import alloc
from ..core.kernels import Kernels
from ..scene.scene import Scene
from ..settings.table import Settings
from . import cryptomatte
from .camera import halton
from .denoise import denoise_frame
from .frame import DeviceFrame, Frame, read_image
from .half_error import rel_mse_from_halves
from .history import History
from .light_passes import fill_planes, planes_buffer
from .passes import LIGHT_PLANES
from .qmc import still_flags, still_key, still_uses_sobol
from .shutter import ShutterTimes

HALF_BLOCK = 8  # frames per block of a still render's two half buffers (error_estimate)


def half_of(k: int) -> int:
    """Half buffer (0 or 1) of sample k of a still render: blocks of HALF_BLOCK consecutive frames, the two blocks
    of each pair in an order drawn from a hash of the pair. Any HALF_BLOCK consecutive frames cover the same
    Halton jitter strata, and the coin makes the finer strata exchangeable between the halves."""
    pair = k // (2 * HALF_BLOCK)
    flip = ((pair * 0x9E3779B1 + 0x7F4A7C15) & 0xFFFFFFFF) >> 31
    return ((k // HALF_BLOCK) & 1) ^ flip


class StillAccumulation:
    """The running sum of a still render's samples and of those of half buffer 1."""

    def __init__(self, kernels: Kernels, pixels: int, shape: tuple[int, int]) -> None:
        self.kernels = kernels
        self.pixels = pixels
        self.shape = shape
        context = kernels.device.context
        self.sum = alloc(context, pixels * 16)
        self.sum_half = alloc(context, pixels * 16)
        self.counts = (0, 0)  # (samples accumulated, of which in half buffer 1)
        self.aux: tuple[cl.Buffer, ...] | None = None  # sums of the denoiser's albedo, normal and emission images
        self.light_planes: cl.Buffer | None = None  # each frame's light passes (render/light_passes.py), where on
        self.light_sums: cl.Buffer | None = None  # ... and their sums
        self.planes = len(LIGHT_PLANES)  # planes in those: the light passes', then the light groups'
        self.crypto: cl.Buffer | None = None  # Cryptomatte's slots (opencl/film/cryptomatte.cl), where on
        self.crypto_levels = 0
        self.holdout: cl.Buffer | None = None  # counts of the samples that met a holdout, and nothing (HAS_HOLDOUT)

    def use_light_passes(self, groups: int = 0) -> cl.Buffer:
        """Sum the light passes' planes (and `groups` light groups' planes) of each sample too; returns the buffer of
        a frame's planes."""
        self.planes = len(LIGHT_PLANES) + groups
        self.light_planes = planes_buffer(self.kernels.device.context, self.pixels, groups)
        self.light_sums = planes_buffer(self.kernels.device.context, self.pixels, groups)
        return self.light_planes

    def clear(self, aux: bool = False) -> None:
        """Start a still render; with `aux`, also sum the denoiser's guide images (add_aux)."""
        if aux and self.aux is None:
            context = self.kernels.device.context
            self.aux = tuple(alloc(context, self.pixels * 16) for _ in range(3))
        for b in (self.sum, self.sum_half, *(self.aux if aux and self.aux else ())):
            cl.enqueue_fill_buffer(self.kernels.device.queue, b, np.float32(0), 0, self.pixels * 16)
        if self.light_sums is not None:
            cl.enqueue_fill_buffer(self.kernels.device.queue, self.light_sums, np.float32(0), 0,
                                   self.pixels * 16 * self.planes)
        if self.holdout is not None:
            cl.enqueue_fill_buffer(self.kernels.device.queue, self.holdout, np.float32(0), 0, self.pixels * 8)
        self.counts = (0, 0)

    def use_holdout(self) -> None:
        """Count the samples whose camera ray met a holdout, and nothing (opencl/still/holdout.cl), from now on."""
        if self.holdout is None:
            self.holdout = alloc(self.kernels.device.context, self.pixels * 8)
        cl.enqueue_fill_buffer(self.kernels.device.queue, self.holdout, np.float32(0), 0, self.pixels * 8)

    def add_holdout(self, gbuf: cl.Buffer, frame_params: np.void) -> None:
        self.kernels.launch("accumulate_holdout", (self.pixels,), gbuf=gbuf, shares=self.holdout,
                            frame_params=frame_params)

    def holdout_shares(self, done: int) -> np.ndarray:
        """(H, W, 2) shares of the samples whose camera ray met a holdout, and nothing."""
        counts = np.empty((self.pixels, 2), np.float32)
        cl.enqueue_copy(self.kernels.device.queue, counts, self.holdout)
        return (counts / max(done, 1)).reshape(*self.shape, 2)

    def use_cryptomatte(self, levels: int) -> None:
        """Count the ids each sample's camera ray hit (Cryptomatte, render/cryptomatte.py) from now on: empty slots."""
        nbytes = 2 * self.pixels * levels * 8
        if self.crypto is None or self.crypto_levels != levels:
            self.crypto, self.crypto_levels = alloc(self.kernels.device.context, nbytes), levels
        cl.enqueue_fill_buffer(self.kernels.device.queue, self.crypto, np.uint32(0), 0, nbytes)

    def add_cryptomatte(self, gbuf: cl.Buffer, frame_params: np.void) -> None:
        self.kernels.launch("accumulate_cryptomatte", (self.pixels,), gbuf=gbuf, slots=self.crypto,
                            frame_params=frame_params, levels=np.int32(self.crypto_levels))

    def cryptomatte(self, scene: Scene, done: int) -> dict[str, np.ndarray]:
        """The Cryptomatte layers of the samples so far."""
        slots = np.empty((2, *self.shape, self.crypto_levels, 2), np.uint32)
        cl.enqueue_copy(self.kernels.device.queue, slots, self.crypto)
        return cryptomatte.layers(scene, slots, done, self.crypto_levels)

    def add_aux(self, gbuf: cl.Buffer, glossy: cl.Buffer, frame_params: np.void) -> None:
        assert self.aux is not None
        self.kernels.launch("accumulate_aux", (self.pixels,), gbuf=gbuf, glossy=glossy, albedo_sum=self.aux[0],
                            normal_sum=self.aux[1], emission_sum=self.aux[2], frame_params=frame_params)

    def aux_images(self, done: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(H, W, 3) mean albedo, mean normal (renormalised; 0 where every sample missed) and mean emission seen by
        the camera over `done` samples."""
        assert self.aux is not None
        albedo = self._read(self.aux[0]).reshape(*self.shape, 4)[..., :3] / max(done, 1)
        n = self._read(self.aux[1]).reshape(*self.shape, 4)[..., :3]
        length = np.linalg.norm(n, axis=-1, keepdims=True)
        normal = np.where(length > 0, n / np.maximum(length, 1e-30), 0.0).astype(np.float32)
        emission = self._read(self.aux[2]).reshape(*self.shape, 4)[..., :3] / max(done, 1)
        return albedo.astype(np.float32), normal, emission.astype(np.float32)

    def add(self, sample: cl.Buffer, frame_params: np.void, half: int) -> None:
        self.kernels.launch("accumulate", (self.pixels,), sample=sample, sum=self.sum, sum_half=self.sum_half,
                            frame_params=frame_params, in_half=np.int32(half))
        if self.light_sums is not None:
            self.kernels.launch("accumulate_light_passes", (self.pixels * self.planes,),
                                light_passes=self.light_planes, sums=self.light_sums, frame_params=frame_params,
                                planes=np.int32(self.planes))
        done, n_half = self.counts
        self.counts = (done + 1, n_half + half)

    def _read(self, buf: cl.Buffer) -> np.ndarray:
        return read_image(self.kernels.device.queue, buf, self.shape).reshape(self.pixels, 4)

    def coverage(self, done: int) -> np.ndarray:
        """(H, W) mean of the samples' w: the film's alpha where rays pass through surfaces."""
        return (self._read(self.sum)[:, 3] / max(done, 1)).reshape(self.shape).astype(np.float32)

    def mean_image(self) -> np.ndarray:
        """(H, W, 3) running mean of the still render in progress."""
        return self._read(self.sum).reshape(*self.shape, 4)[..., :3] / max(self.counts[0], 1)

    def halves(self, done: int, n_half: int) -> tuple[np.ndarray, np.ndarray]:
        """(H, W, 3) means of half buffer 1 (n_half samples) and of half buffer 0 (the other done - n_half)."""
        total = self._read(self.sum)[:, :3]
        half = self._read(self.sum_half)[:, :3]
        shape = (*self.shape, 3)
        return (half / n_half).reshape(shape), ((total - half) / (done - n_half)).reshape(shape)

    def error_estimate(self, done: int, n_half: int) -> float | None:
        """relMSE of the running mean estimated from the two half buffers, no reference needed (render/half_error.py):
        the halves are independent estimates, so E|a - b|^2 = var_a + var_b, and the full mean has a quarter of that
        when the halves are equal in size; relative to r^2 + 0.01 as relMSE is, r^2 estimated robustly."""
        if n_half == 0 or done - n_half == 0:
            return None
        a, b = self.halves(done, n_half)
        return rel_mse_from_halves(a, b, n_half, done - n_half)


class FrameSource(Protocol):
    """What a still render needs of the renderer (Renderer, render/pipeline.py)."""

    settings: Settings
    scene: Scene
    history: History
    still: StillAccumulation
    scene: Scene  # its camera's shutter (motion blur)
    qmc: tuple[int, int, int] | None  # FrameParams (qmc, qmc_index, qmc_key) of the next frame; None: its own
    flags: dict  # the program's feature flags (render/features.py)

    @property
    def sample_buf(self) -> cl.Buffer: ...

    def run_frame(self, frame: int, *, still: bool = False, jitter_px: tuple[float, float] | None = None,
                  wait: bool = True) -> DeviceFrame: ...

    def frame_params(self) -> np.void: ...

    def read_frame(self, color_buf: cl.Buffer, gbuf: cl.Buffer, frame: int, scale: float = 1.0,
                   aovs: bool = True) -> Frame: ...


class HalfStreams:
    """What each half buffer of a still render draws from on its own: its pixel jitter, its Sobol index count and
    key, and (ReSTIR with temporal reuse) its chain of history.

    Pixel jitter: one Halton sequence shared by the halves would put them in different strata, and their difference
    would see antialiasing error as noise (stratified, the mean's error falls faster than 1/n); two independently
    shifted Halton sequences (randomised QMC) are independent estimates of the pixel. From the Sobol sampler each
    pixel's jitter is a part of its own sequence instead (opencl/camera/jitter.h), which each half's key scrambles
    on its own. ReSTIR's temporal reuse
    correlates consecutive frames: each half continues its own chain (the renderer's own for the first sample's
    half, a second one for the other), so the two halves stay independent."""

    def __init__(self, settings: Settings, history: History) -> None:
        self.settings = settings
        self.history = history
        self.jitter_counts = [0, 0]
        self.shifts = np.random.default_rng([settings.seed, 0x5EED]).random((2, 2))
        self.sobol = still_uses_sobol(settings)  # RIS samples from a scrambled Sobol sequence (render/qmc.py)
        self.qmc_counts = [0, 0]
        self.chains = settings.method == "restir" and settings.temporal
        self.first = half_of(0)
        self.started = {0}
        self.active: int | None = None

    def qmc(self, half: int) -> tuple[int, int, int] | None:
        """FrameParams (qmc, qmc_index, qmc_key) of the next frame of `half`; None without the Sobol sampler."""
        if not self.sobol:
            return None
        index = self.qmc_counts[half]
        self.qmc_counts[half] += 1
        return (still_flags(self.settings), index, still_key(self.settings.seed, half))

    def jitter(self, half: int) -> tuple[float, float] | None:
        """The pixel jitter of the next frame of `half` (None: the renderer's own, i.e. none without jitter). From
        the Sobol sampler each pixel takes its own (FrameParams.qmc's PIXEL_JITTER): the frame's offset is 0."""
        if not self.settings.jitter:
            return None
        if self.sobol:
            return (0.0, 0.0)
        i = self.jitter_counts[half] = self.jitter_counts[half] + 1
        shift = self.shifts[half]
        return ((halton(i, 2) + shift[0]) % 1.0 - 0.5, (halton(i, 3) + shift[1]) % 1.0 - 0.5)

    def use_chain(self, half: int) -> None:
        """Continue the chain of history of `half`."""
        if not self.chains or half == self.active:
            return
        if self.active is not None:
            chain = 0 if half == self.first else 1
            self.history.use_chain(chain, fresh=chain not in self.started)
            self.started.add(chain)
        self.active = half

    def end(self) -> None:
        """Back to the first chain: the renderer's own history."""
        if self.chains and self.history.active != 0:
            self.history.use_chain(0, fresh=False)


def render_still(
    r: FrameSource,
    frame: int,
    samples: int,
    progress: Callable[[int, int], None] | None,
    should_stop: Callable[[], bool] | None,
    target_error: float | None,
    checkpoint: Callable[[int, float], None] | None,
) -> Frame:
    """Renderer.render_still: average up to `samples` frames of a still camera at `frame`."""
    acc = r.still
    acc.clear(aux=r.settings.denoise)
    if r.settings.cryptomatte_levels:
        acc.use_cryptomatte(r.settings.cryptomatte_levels)
    acc.use_holdout()  # the film's alpha: the shares of the holdout and the world, in every still
    halves = HalfStreams(r.settings, r.history)
    assert r.scene.camera is not None
    times = ShutterTimes(r.scene.camera.shutter, r.settings.seed)
    gbuf = r.history.gbuf(r.history.cur)
    stage: dict[str, float] = {}
    t0 = time.perf_counter()
    for k in range(max(int(samples), 1)):
        if should_stop is not None and acc.counts[0] > 0 and should_stop():
            break
        gbuf = _add_sample(r, halves, times.time(frame, half_of(k)), half_of(k), stage)
        done, n_half = acc.counts
        if progress is not None:
            progress(done, samples)
        if checkpoint is not None:  # the caller's look at the image is not render time
            t0 += _checkpoint(acc, checkpoint, done, t0)
        if target_error is not None and done >= 2 * HALF_BLOCK and done % 4 == 0:
            estimate = acc.error_estimate(done, n_half)
            if estimate is not None and estimate <= target_error:
                break
    halves.end()
    return _result(r, frame, gbuf, stage, t0)


def _add_sample(r: FrameSource, halves: HalfStreams, frame: float, half: int, stage: dict[str, float]) -> cl.Buffer:
    """Render one frame (at its time within the shutter) into half buffer `half`; adds its stage times to `stage`,
    returns its G-buffer."""
    qmc = halves.qmc(half)
    if qmc is not None:
        r.qmc = qmc
    jit = halves.jitter(half)
    halves.use_chain(half)
    st, _, gbuf = r.run_frame(frame, still=True, jitter_px=jit, wait=False)  # the frames' stages back to back
    for key, v in st.items():
        stage[key] = stage.get(key, 0.0) + v
    r.still.add(r.sample_buf, r.frame_params(), half)
    if r.settings.cryptomatte_levels:  # the frame's G-buffer (the previous slot once the history swapped)
        r.still.add_cryptomatte(gbuf, r.frame_params())
    r.still.add_holdout(gbuf, r.frame_params())  # the frame's G-buffer, as above
    if r.settings.denoise:  # the frame's G-buffer is in the previous slot once run_frame has swapped the history
        r.still.add_aux(gbuf, r.history.glossy(r.history.prev), r.frame_params())
    return gbuf


def _checkpoint(acc: StillAccumulation, checkpoint: Callable[[int, float], None], done: int, t0: float) -> float:
    """Let the caller look at the running mean; returns the seconds it took."""
    acc.kernels.device.queue.finish()
    tc = time.perf_counter()
    checkpoint(done, tc - t0)
    return time.perf_counter() - tc


def _result(r: FrameSource, frame: int, gbuf: cl.Buffer, stage: dict[str, float], t0: float) -> Frame:
    """The mean of the samples accumulated, with the last frame's passes, per-sample times and the error
    estimate; denoised (Settings.denoise) guided by the mean albedo, normal and emission."""
    acc = r.still
    done, n_half = acc.counts
    out = r.read_frame(acc.sum, gbuf, frame, scale=1.0 / done)
    out.noisy = read_image(acc.kernels.device.queue, r.sample_buf, acc.shape)[..., :3].copy()
    out.samples = done
    out.stage_ms = {k: v / done for k, v in stage.items()}
    out.ms = (time.perf_counter() - t0) * 1e3 / done
    out.error_estimate = acc.error_estimate(done, n_half) if done >= 2 else None
    if r.flags.get("HAS_TRANSPARENCY"):  # the samples' w: 1 where the camera ray stopped (transparent.h film_coverage)
        out.coverage = acc.coverage(done)
    out.holdout_shares = acc.holdout_shares(done)  # the shares of the pixel a holdout and the world cover
    if r.settings.denoise:
        albedo, normal, emission = acc.aux_images(done)
        if denoise_frame(out, albedo, normal, emission):  # the passes show the guides the denoiser saw, as in Cycles
            out.albedo, out.normal = albedo, normal
    if r.settings.light_passes or r.scene.light_groups:  # the light passes and groups of the mean (the passes
        assert acc.light_sums is not None  # divided by the mean colours)
        fill_planes(out, acc.kernels.device.queue, acc.light_sums, r.settings.light_passes, r.scene.light_groups,
                    1.0 / done)
    if r.settings.cryptomatte_levels:  # the ids of every sample, ranked by coverage
        out.cryptomatte = acc.cryptomatte(r.scene, done)
    return out
