"""Still renders: frames of a still camera averaged into a running sum, split into two half buffers whose
difference estimates the error of the mean without a reference (StillAccumulation.error_estimate).

What makes the halves independent: they are blocks of HALF_BLOCK frames (half_of), not odd and even frames, each
with its own randomly shifted Halton jitter sequence (odd and even frames of one sequence sit in different strata:
the estimate was 17x too large at 256 samples on a small cornell_box, and with one sequence split in blocks it
still grew 2x too large by 256 samples on many_lights, whose sub-pixel lamps are antialiased faster than 1/n); and
ReSTIR with temporal reuse runs one chain of history per half (render/history.py; correlated frames made it 2-10x too
small).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
import pyopencl as cl

from ..core.buffers import alloc
from ..core.kernels import Kernels
from .camera import halton
from .denoise import denoise_frame
from .frame import read_image
from .qmc import still_key, still_uses_sobol

if TYPE_CHECKING:
    from .frame import Frame
    from .pipeline import Renderer

HALF_BLOCK = 8  # frames per block of a still render's two half buffers (error_estimate)
R2_FLOOR = 0.25  # error_estimate: r^2 is taken as at least R2_FLOOR * mean^2


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

    def clear(self, aux: bool = False) -> None:
        """Start a still render; with `aux`, also sum the denoiser's guide images (add_aux)."""
        if aux and self.aux is None:
            context = self.kernels.device.context
            self.aux = tuple(alloc(context, self.pixels * 16) for _ in range(3))
        for b in (self.sum, self.sum_half, *(self.aux if aux and self.aux else ())):
            cl.enqueue_fill_buffer(self.kernels.device.queue, b, np.float32(0), 0, self.pixels * 16)
        self.counts = (0, 0)

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
        done, n_half = self.counts
        self.counts = (done + 1, n_half + half)

    def _read(self, buf: cl.Buffer) -> np.ndarray:
        return read_image(self.kernels.device.queue, buf, self.shape).reshape(self.pixels, 4)

    def mean_image(self) -> np.ndarray:
        """(H, W, 3) running mean of the still render in progress."""
        return self._read(self.sum).reshape(*self.shape, 4)[..., :3] / max(self.counts[0], 1)

    def error_estimate(self, done: int, n_half: int) -> float | None:
        """relMSE of the running mean estimated from two half buffers, no reference needed: the halves are
        independent estimates, so E|a - b|^2 = var_a + var_b, and the full mean has a quarter of that when the
        halves are equal in size (relative to r^2 + 0.01 as relMSE is, r^2 estimated robustly, see below)."""
        if n_half == 0 or done - n_half == 0:
            return None
        total = self._read(self.sum)
        half = self._read(self.sum_half)
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


def render_still(
    r: Renderer,
    frame: int,
    samples: int,
    progress: Callable[[int, int], None] | None,
    should_stop: Callable[[], bool] | None,
    target_error: float | None,
    checkpoint: Callable[[int, float], None] | None,
) -> Frame:
    """Renderer.render_still: average up to `samples` frames of a still camera at `frame`."""
    q = r.device.queue
    acc = r.still
    denoise = r.settings.denoise
    acc.clear(aux=denoise)
    done = 0
    stage: dict[str, float] = {}
    t0 = time.perf_counter()
    history = r.history
    gbuf = history.gbuf(history.cur)
    # ReSTIR's temporal reuse correlates consecutive frames: each half buffer gets its own chain of history (the
    # renderer's own for the first sample's half, a second one for the other), so the two halves stay independent.
    chains = r.settings.method == "restir" and r.settings.temporal
    first = half_of(0)
    started = {0}
    active: int | None = None
    # Pixel jitter: one Halton sequence shared by the halves would put them in different strata, and their
    # difference would see antialiasing error as noise (stratified, the mean's error falls faster than 1/n).
    # Two independently shifted Halton sequences (randomised QMC) are independent estimates of the pixel.
    counts = [0, 0]
    shifts = np.random.default_rng([r.settings.seed, 0x5EED]).random((2, 2))
    # RIS samples from a scrambled Sobol sequence (render/qmc.py): one index count and one scramble key per half buffer
    sobol = still_uses_sobol(r.settings)
    qmc_counts = [0, 0]
    for k in range(max(int(samples), 1)):
        if should_stop is not None and done > 0 and should_stop():
            break
        half = half_of(k)
        if sobol:
            r.qmc = (1, qmc_counts[half], still_key(r.settings.seed, half))
            qmc_counts[half] += 1
        jit = None
        if r.settings.jitter:
            i = counts[half] = counts[half] + 1
            jit = ((halton(i, 2) + shifts[half][0]) % 1.0 - 0.5, (halton(i, 3) + shifts[half][1]) % 1.0 - 0.5)
        if chains and half != active:
            if active is not None:
                chain = 0 if half == first else 1
                history.use_chain(chain, fresh=chain not in started)
                started.add(chain)
            active = half
        st, _, gbuf = r._render(frame, still=True, jitter_px=jit)
        for key, v in st.items():
            stage[key] = stage.get(key, 0.0) + v
        acc.add(r.buffers.sample, r.frame_params(), half)
        if denoise:  # the frame's G-buffer is in the previous slot once _render has swapped the history
            acc.add_aux(gbuf, history.glossy(history.prev), r.frame_params())
        done, n_half = acc.counts
        if progress is not None:
            progress(done, samples)
        if checkpoint is not None:
            q.finish()
            tc = time.perf_counter()
            checkpoint(done, tc - t0)
            t0 += time.perf_counter() - tc  # the caller's look at the image is not render time
        if target_error is not None and done >= 2 * HALF_BLOCK and done % 4 == 0:
            estimate = acc.error_estimate(done, n_half)
            if estimate is not None and estimate <= target_error:
                break
    if chains and history.active != 0:  # back to the first chain: the renderer's own history
        history.use_chain(0, fresh=False)
    done, n_half = acc.counts
    out = r._read(acc.sum, gbuf, frame, scale=1.0 / done)
    out.noisy = read_image(q, r.buffers.sample, acc.shape)[..., :3].copy()
    out.samples = done
    out.stage_ms = {k: v / done for k, v in stage.items()}
    out.ms = (time.perf_counter() - t0) * 1e3 / done
    out.error_estimate = acc.error_estimate(done, n_half) if done >= 2 else None
    if denoise:
        albedo, normal, emission = acc.aux_images(done)
        if denoise_frame(out, albedo, normal, emission):  # the passes show the guides the denoiser saw, as in Cycles
            out.albedo, out.normal = albedo, normal
    return out
