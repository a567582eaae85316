"""Error per frame for a moving camera (`restircl report --moving`).

Every method renders the animation in order with the same wall time per frame, and the error of each evaluated
frame is taken against a converged reference of that frame (eval/report/reference.py). A method faster than the budget
spends the spare time as a real-time renderer would:
- mode `taa` (the TAA output): at a higher frame rate, k frames along the same camera path for each frame of the
  animation (scene/retime.py), k its frame time's share of the budget; re-rendering the same frame instead would
  look to TAA like a still camera and let its history lag behind the motion;
- mode `frame` (no TAA): more samples of that frame, averaged.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pyopencl as cl

from ...render.pipeline import Renderer
from ...scene.retime import retime
from ...scene.scene import Scene
from ...settings.table import Settings
from ..metrics import rel_mse, rmse
from .files import ReportBase, plot_lines, write_files
from .methods import METHODS, method_settings
from .reference import get_reference


@dataclass
class FrameRow:
    method: str
    mode: str  # taa (TAA output) | frame (mean of this frame's samples, no TAA)
    frame: int
    budget_ms: float
    ms: float  # wall time spent on this frame
    samples: int  # taa: frames rendered along the path per animation frame; frame: samples of this frame
    rel_mse: float
    rmse: float


@dataclass
class MovingReport(ReportBase):
    budget_ms: float
    rows: list[FrameRow] = field(default_factory=list)
    references: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def keys(self) -> list[tuple[str, str]]:
        return self._keys("taa", list(METHODS))

    def summary(self) -> dict[str, dict]:
        out = {}
        for method, mode in self.keys():
            rows = self.series(method, mode)
            out[f"{method} ({mode})"] = {
                "mean_rel_mse": float(np.mean([r.rel_mse for r in rows])),
                "median_rel_mse": float(np.median([r.rel_mse for r in rows])),
                "mean_ms": float(np.mean([r.ms for r in rows])),
                "mean_samples": float(np.mean([r.samples for r in rows])),
            }
        return out

    def table(self) -> str:
        """relMSE per evaluated frame; k: taa rows' frames along the path per animation frame, frame rows' samples."""
        frames = sorted({r.frame for r in self.rows})
        lines = [f"{'relMSE':<24} {'mode':<6} " + " ".join(f"{'f' + str(f):>9}" for f in frames)
                 + f" {'mean':>9} {'ms/frame':>9} {'k':>5}"]
        summ = self.summary()
        for method, mode in self.keys():
            rows = {r.frame: r for r in self.series(method, mode)}
            s = summ[f"{method} ({mode})"]
            lines.append(f"{method:<24} {mode:<6} " + " ".join(
                f"{rows[f].rel_mse:>9.2e}" if f in rows else f"{'-':>9}" for f in frames)
                + f" {s['mean_rel_mse']:>9.2e} {s['mean_ms']:>9.1f} {s['mean_samples']:>5.1f}")
        return "\n".join(lines)

    def write(self, out: Path) -> list[Path]:
        header = ["method", "mode", "frame", "budget_ms", "ms", "samples", "rel_mse", "rmse"]
        cells = [[r.method, r.mode, r.frame, f"{r.budget_ms:.1f}", f"{r.ms:.1f}", r.samples, f"{r.rel_mse:.6g}",
                  f"{r.rmse:.6g}"] for r in self.rows]
        meta = {"scene": self.scene, "device": self.device, "width": self.width, "height": self.height,
                "budget_ms": self.budget_ms, "references": self.references, "notes": self.notes,
                "summary": self.summary(), "rows": [asdict(r) for r in self.rows]}
        base = Path(out) / f"report_moving_{self.scene}_{self.width}x{self.height}"
        return write_files(base, header, cells, meta, self.plot)

    def plot(self, path: Path) -> Path | None:
        return plot_lines(path, self._lines("frame", "taa"), (9.5, 5.0), False, "animation frame",
                          "relMSE vs that frame's reference",
                          f"{self.scene} {self.width}x{self.height}, moving camera, {self.budget_ms:.0f} ms per "
                          f"frame, on {self.device}")


def _read_rgb(r: Renderer, buf) -> np.ndarray:
    img = np.empty((r.height, r.width, 4), np.float32)
    cl.enqueue_copy(r.device.queue, img, buf)
    return img[..., :3]


def frame_time_ms(scene: Scene, name: str, device=None, frames: int = 6, base: Settings | None = None
                  ) -> tuple[float, float]:
    """Median wall and CPU time (ms) of one animation frame of `name` (after two warm-up frames)."""
    r = Renderer(scene, method_settings(name, base, 1), device)
    r.render_frame(0, aovs=False)
    r.render_frame(1 % scene.frames, aovs=False)
    wall, cpu = [], []
    for f in range(1, frames + 1):
        t0, c0 = time.perf_counter(), time.process_time()
        r.run_frame(min(f, scene.frames - 1), still=False)
        r.device.queue.finish()
        wall.append((time.perf_counter() - t0) * 1e3)
        cpu.append((time.process_time() - c0) * 1e3)
    return float(np.median(wall)), float(np.median(cpu))


def run_moving(scene: Scene, methods: list[str], budget_ms: float | None = None, every: int = 4,
               modes=("taa",), device=None, base: Settings | None = None, log: Callable[[str], None] = print,
               reference_seconds: float = 20.0, cache_dir: Path | None = None, seed: int = 4242,
               references: dict[int, np.ndarray] | None = None, budget_factor: float = 1.0) -> MovingReport:
    """Each method renders every frame of the animation in order, with `budget_ms` of wall time per frame (default:
    the slowest method's frame time, so that each renders at least one sample per frame and the faster ones
    render more); the error of every `every`-th frame (and the last) is taken against that frame's reference
    (with the Light Paths of `base`).

    With TAA the number k of frames along the path is fixed before the path is rendered: with the default budget
    it is the ratio of the slowest method's CPU time per frame to this one's (CPU time, because the wall time of
    a shared machine drifts between the measurement and the render), with a given budget that budget over the
    method's wall time per frame. budget_factor (default budget only): the budget is that many times the slowest
    method's frame time, so that every method renders about its share of frames (k rounds to whole frames: at 1.0 a
    method 1.4x as fast gets 1 frame, at 2.0 the slowest gets 2 and it 3)."""
    cam = scene.camera
    assert cam is not None
    n = scene.frames
    evaluated = sorted({*range(0, n, max(every, 1)), n - 1})
    times: dict[str, tuple[float, float]] = {}
    if budget_ms is None or "taa" in modes:
        times = {m: frame_time_ms(scene, m, device, base=base) for m in methods}
    share: dict[str, float] = {}
    if budget_ms is None:
        budget_ms = budget_factor * max(w for w, _ in times.values())
        slowest_cpu = max(c for _, c in times.values())
        share = {m: budget_factor * slowest_cpu / max(c, 1e-6) for m, (_, c) in times.items()}
    else:
        share = {m: budget_ms / max(w, 1e-6) for m, (w, _) in times.items()}
        log(f"budget: {budget_ms:.0f} ms per frame (the slowest method's frame time)")
    rep = MovingReport(scene.name, "", cam.width, cam.height, float(budget_ms))
    refs: dict[int, np.ndarray] = dict(references or {})
    for f in evaluated:
        if f not in refs:
            ref = get_reference(scene, f, reference_seconds, device=device, cache_dir=cache_dir, log=log, paths=base)
            refs[f] = ref.image
            rep.references[str(f)] = {"method": ref.method, "frames": ref.frames, "est_rel_mse": ref.est_rel_mse}
    budget = budget_ms / 1e3
    for name in methods:
        for mode in modes:
            if mode not in ("taa", "frame"):
                raise ValueError(f"unknown mode {mode!r} (taa, frame)")
            if mode == "taa":
                k = max(1, int(share[name] + 0.5))
                _taa_rows(rep, scene, name, k, refs, device, base, seed)
            else:
                _frame_rows(rep, scene, name, budget, refs, device, base, seed)
            rows = rep.series(name, mode)
            unit = "frames along the path" if mode == "taa" else "samples"
            log(f"{name:<24} {mode:<6} mean relMSE {np.mean([x.rel_mse for x in rows]):.3e}, "
                f"{np.mean([x.samples for x in rows]):.1f} {unit} and {np.mean([x.ms for x in rows]):.0f} ms "
                "per frame")
    return rep


def _warm_renderer(scene: Scene, name: str, device, base: Settings | None, seed: int, still: bool) -> Renderer:
    r = Renderer(scene, method_settings(name, base, seed), device)
    for _ in range(2):  # warm-up (kernels compile at their first launch); then start without history
        r.run_frame(0, still=still)
    r.reset()
    return r


def _taa_rows(rep: MovingReport, scene: Scene, name: str, k: int, refs: dict[int, np.ndarray], device,
              base: Settings | None, seed: int) -> None:
    """The path in k frames per animation frame, one sample each, in order; frame f*k is animation frame f."""
    r = _warm_renderer(retime(scene, k), name, device, base, seed, still=False)
    rep.device = r.device.label
    t0 = time.perf_counter()
    for j in range(r.scene.frames):
        _, color_buf, _ = r.run_frame(j, still=False)
        f, rest = divmod(j, k)
        if rest:
            continue
        img = _read_rgb(r, color_buf)
        ms = (time.perf_counter() - t0) * 1e3
        if f in refs:
            rep.rows.append(FrameRow(name, "taa", f, rep.budget_ms, ms, k, rel_mse(img, refs[f]), rmse(img, refs[f])))
        t0 = time.perf_counter()


def _frame_rows(rep: MovingReport, scene: Scene, name: str, budget: float, refs: dict[int, np.ndarray], device,
                base: Settings | None, seed: int) -> None:
    """Each animation frame's own samples (no TAA), as many as fit the budget, averaged."""
    r = _warm_renderer(scene, name, device, base, seed, still=True)
    rep.device = r.device.label
    per_sample = None
    for f in range(scene.frames):
        t0 = time.perf_counter()
        k = 0
        acc = None
        while True:
            t1 = time.perf_counter()
            r.run_frame(f, still=True)
            s = _read_rgb(r, r.sample_buf).astype(np.float64)
            acc = s if acc is None else acc + s
            k += 1
            dt = time.perf_counter() - t1
            per_sample = dt if per_sample is None else 0.8 * per_sample + 0.2 * dt
            # another sample if it ends nearer the budget than stopping now does
            if time.perf_counter() - t0 + 0.5 * per_sample >= budget:
                break
        img = acc / k
        ms = (time.perf_counter() - t0) * 1e3
        if f in refs:
            rep.rows.append(FrameRow(name, "frame", f, rep.budget_ms, ms, k, rel_mse(img, refs[f]), rmse(img, refs[f])))
