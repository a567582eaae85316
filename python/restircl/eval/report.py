"""Error against run time (`restircl report`).

Still camera (run_report): every method renders while the wall clock runs, and its error against a converged
reference is recorded at a series of time budgets; Cycles (direct light only) is rendered at the same budgets when
`bpy` imports. Writes a CSV and a JSON table and a log-log plot (error against seconds, one line per method).

Moving camera (run_moving): every method renders the animation in order with the same wall time per frame (a
method faster than the budget renders extra samples of that frame: more TAA history, or a longer per-frame mean),
and the error of each evaluated frame is taken against a converged reference of that frame.

References are computed once and cached on disk, keyed by the scene file's content, the frame, the device and a
digest of the reference estimator's own first two frames (a probe: an edit of the code that changes what the
reference estimator renders gives another key, so a stale reference is never reused; an edit that leaves it
bit-identical, e.g. to the ReSTIR kernels, keeps the cache). A reference is an unbiased
estimator run long: exhaustive over the lights (`reference`) when the scene has few, else RIS with 32 candidates;
its own remaining error is estimated from its half buffers and written into the report. Unbiased methods fall
with a slope of about -1 on the plot; a biased one levels off at its bias.
"""

from __future__ import annotations

import csv
import hashlib
import json
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pyopencl as cl

from ..pipeline import Renderer, Settings
from ..scene import Scene

# name -> Settings overrides
METHODS: dict[str, dict] = {
    "uniform": dict(method="uniform"),
    "light_array": dict(method="light_array"),
    "ris": dict(method="ris"),
    "restir_temporal": dict(method="restir", spatial=False),
    "restir_spatial": dict(method="restir", temporal=False),
    "restir": dict(method="restir"),
    "restir_temporal_biased": dict(method="restir", spatial=False, bias_correction="none"),
    "restir_spatial_biased": dict(method="restir", temporal=False, bias_correction="none"),
    "restir_biased": dict(method="restir", bias_correction="none"),
}
UNBIASED = ("uniform", "light_array", "ris", "restir_temporal", "restir_spatial", "restir", "cycles")
DEFAULT_BUDGETS = (0.25, 0.5, 1.0, 2.0, 4.0)
def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    """mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)."""
    x = np.asarray(x, dtype=np.float64)[..., :3]
    ref = np.asarray(ref, dtype=np.float64)[..., :3]
    return float(np.mean((x - ref) ** 2 / (ref * ref + 0.01)))


def rmse(x: np.ndarray, ref: np.ndarray) -> float:
    x = np.asarray(x, dtype=np.float64)[..., :3]
    ref = np.asarray(ref, dtype=np.float64)[..., :3]
    return float(np.sqrt(np.mean((x - ref) ** 2)))


def flip(x: np.ndarray, ref: np.ndarray) -> float | None:
    """Mean FLIP (HDR) when `flip-evaluator` is installed, else None."""
    try:
        import flip_evaluator as flip_mod  # type: ignore[import-not-found]
    except ImportError:
        return None
    try:
        _, mean, _ = flip_mod.evaluate(ref[..., :3].astype(np.float32), x[..., :3].astype(np.float32), "HDR")
        return float(mean)
    except Exception:
        return None


def estimator_digest(probe: np.ndarray, device_label: str) -> str:
    """Digest of a probe image (the reference estimator's first frames, bit for bit) and of the device."""
    h = hashlib.sha256()
    h.update(device_label.encode())
    h.update(np.ascontiguousarray(probe, dtype=np.float32).tobytes())
    return h.hexdigest()[:12]


def scene_digest(scene: Scene, cache_dir: Path) -> str:
    tmp = cache_dir / f"scene.{time.monotonic_ns()}.tmp.npz"
    scene.save(tmp)
    try:
        return hashlib.sha256(tmp.read_bytes()).hexdigest()[:16]
    finally:
        tmp.unlink()


@dataclass
class Reference:
    image: np.ndarray  # (H, W, 3) float32
    method: str
    frames: int
    seconds: float
    est_rel_mse: float | None  # its own remaining error, estimated from its half buffers
    path: str


def default_cache_dir() -> Path:
    return Path.home() / ".cache" / "restircl"


def get_reference(scene: Scene, frame: int = 0, seconds_hint: float = 60.0, frames: int | None = None, device=None,
              cache_dir: Path | None = None, log: Callable[[str], None] = print) -> Reference:
    """A converged image of `scene` at `frame`, cached on disk (see the module docstring)."""
    cache_dir = Path(cache_dir or default_cache_dir())
    cache_dir.mkdir(parents=True, exist_ok=True)
    n_lights = len(scene.lights) + sum(1 for m in scene.materials if m.is_emissive)
    settings = Settings(method="reference" if n_lights <= 16 else "ris", candidates=32, seed=987654)
    r = Renderer(scene, settings, device)
    # the probe also keeps lazy kernel compilation and first uploads out of the timing below
    probe = r.render_still(frame, 2).color
    key = f"{scene_digest(scene, cache_dir)}_{estimator_digest(probe, r.device.label)}_f{frame}"
    path = cache_dir / f"reference_{scene.name}_{key}.npy"
    meta_path = path.with_suffix(".json")
    if path.exists() and meta_path.exists():
        meta = json.loads(meta_path.read_text())
        log(f"reference: cached {path}")
        return Reference(np.load(path), meta["method"], meta["frames"], meta["seconds"], meta["est_rel_mse"],
                         str(path))
    if frames is None:
        t0 = time.perf_counter()
        r.render_still(frame, 4)
        per = (time.perf_counter() - t0) / 4
        frames = int(min(max(seconds_hint / max(per, 1e-6), 256), 1 << 17))
    log(f"reference: {settings.method} x {frames} frames ...")
    t0 = time.perf_counter()
    out = r.render_still(frame, frames)
    seconds = time.perf_counter() - t0
    img = out.color[..., :3].astype(np.float32)
    np.save(path, img)
    meta = {"method": settings.method, "frames": frames, "seconds": seconds, "est_rel_mse": out.error_estimate,
            "scene": scene.name, "frame": frame}
    meta_path.write_text(json.dumps(meta, indent=1))
    est = f"{out.error_estimate:.2e}" if out.error_estimate is not None else "n/a"
    log(f"reference: saved {path} ({seconds:.0f} s, its estimated relMSE {est})")
    return Reference(img, settings.method, frames, seconds, out.error_estimate, str(path))


def reference_image(scene: Scene, seconds_hint: float = 60.0, frames: int | None = None, device=None,
                    cache_dir: Path | None = None, log: Callable[[str], None] = print, frame: int = 0) -> np.ndarray:
    """The image of get_reference(...)."""
    return get_reference(scene, frame, seconds_hint, frames, device, cache_dir, log).image


# ---- still camera: error against seconds ----------------------------------------------------------------------


@dataclass
class Row:
    method: str
    mode: str  # accumulate (running mean) | taa (TAA output) ; Cycles: accumulate
    budget_s: float
    seconds: float
    frames: int | None  # samples per pixel (None: Cycles with a time limit, count not reported)
    rel_mse: float
    rmse: float
    flip: float | None = None


@dataclass
class Report:
    scene: str
    device: str
    width: int
    height: int
    rows: list[Row] = field(default_factory=list)
    reference: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def write(self, out: Path) -> list[Path]:
        header = ["method", "mode", "budget_s", "seconds", "frames", "rel_mse", "rmse", "flip"]
        cells = [[r.method, r.mode, r.budget_s, f"{r.seconds:.4f}", "" if r.frames is None else r.frames,
                  f"{r.rel_mse:.6g}", f"{r.rmse:.6g}", "" if r.flip is None else f"{r.flip:.6g}"] for r in self.rows]
        meta = {"scene": self.scene, "device": self.device, "width": self.width, "height": self.height,
                "reference": self.reference, "notes": self.notes, "slopes": self.slopes(),
                "rows": [asdict(r) for r in self.rows]}
        return _write(Path(out) / f"report_{self.scene}_{self.width}x{self.height}", header, cells, meta, self.plot)

    def keys(self) -> list[tuple[str, str]]:
        order = [*METHODS, "cycles"]
        return sorted(dict.fromkeys((r.method, r.mode) for r in self.rows),
                      key=lambda k: (k[1] != "accumulate", order.index(k[0]) if k[0] in order else 99))

    def series(self, method: str, mode: str) -> list[Row]:
        return [r for r in self.rows if r.method == method and r.mode == mode]

    def slopes(self) -> dict[str, float]:
        return {f"{m} ({mode})": slope(self.series(m, mode)) for m, mode in self.keys()}

    def plot(self, path: Path) -> Path | None:
        lines = []
        for method, mode in self.keys():
            rows = self.series(method, mode)
            lines.append(([r.seconds for r in rows], [r.rel_mse for r in rows], method, mode,
                          "-" if mode == "accumulate" else "--"))
        return _plot(path, lines, (9.5, 5.4), True, "wall-clock seconds (after kernel build and scene upload)",
                     "relMSE vs reference", f"{self.scene} {self.width}x{self.height} on {self.device}")

    def budgets(self) -> list[float]:
        return sorted({r.budget_s for r in self.rows})

    def table(self) -> str:
        budgets = self.budgets()
        lines = [f"{'relMSE':<24} {'mode':<10} " + " ".join(f"{b:>9.2f}s" for b in budgets) + "   slope"]
        for method, mode in self.keys():
            rows = {r.budget_s: r for r in self.series(method, mode)}
            s = slope(list(rows.values()))
            lines.append(f"{method:<24} {mode:<10} " + " ".join(
                f"{rows[b].rel_mse:>10.3e}" if b in rows else f"{'-':>10}" for b in budgets) + f"  {s:6.2f}")
        return "\n".join(lines)


def _settings(name: str, base: Settings | None, seed: int) -> Settings:
    return Settings(**{**(base.__dict__ if base else {}), **METHODS[name], "seed": seed})


def run_report(scene: Scene, methods: list[str], budgets: tuple[float, ...] = DEFAULT_BUDGETS, modes=("accumulate",),
               device=None, reference: np.ndarray | Reference | None = None, base: Settings | None = None,
               log: Callable[[str], None] = print, cycles: bool | object = False, seed: int = 4242,
               reference_seconds: float = 60.0, cache_dir: Path | None = None) -> Report:
    """Render each method with a still camera until each budget (seconds) has passed; record the error.

    cycles: False; True (write `scene` into bpy, needs bpy); or a bpy scene to render (e.g. from a .blend)."""
    ref_meta = {}
    if reference is None:
        reference = get_reference(scene, 0, reference_seconds, device=device, cache_dir=cache_dir, log=log)
    if isinstance(reference, Reference):
        ref_meta = {"method": reference.method, "frames": reference.frames, "seconds": round(reference.seconds, 2),
                    "est_rel_mse": reference.est_rel_mse, "path": reference.path}
        ref = reference.image
    else:
        ref = np.asarray(reference)
    cam = scene.camera
    assert cam is not None
    report = Report(scene.name, "", cam.width, cam.height, reference=ref_meta)
    budgets = tuple(sorted(budgets))
    for name in methods:
        for mode in modes:
            r = Renderer(scene, _settings(name, base, seed), device)
            report.device = r.device.label
            # warm-up on the path that is timed (PoCL compiles a kernel at its first launch; the temporal pass and
            # TAA run from the second frame): compilation and first uploads stay out of the timing
            if mode == "accumulate":
                r.render_still(0, 2)
            else:
                r.render_frame(0, aovs=False)
                r.render_frame(0, aovs=False)
            r.reset()
            pending = list(budgets)

            def record(img: np.ndarray, secs: float, done: int, name=name, mode=mode, pending=pending) -> None:
                while pending and secs >= pending[0]:
                    report.rows.append(Row(name, mode, pending.pop(0), secs, done, rel_mse(img, ref),
                                           rmse(img, ref), flip(img, ref)))

            if mode == "accumulate":
                def checkpoint(done: int, secs: float, r=r, pending=pending, record=record) -> None:
                    if pending and secs >= pending[0]:
                        record(r.mean_image(), secs, done)

                r.render_still(0, 1 << 30, should_stop=lambda pending=pending: not pending, checkpoint=checkpoint)
            elif mode == "taa":
                t0 = time.perf_counter()
                done = 0
                paused = 0.0  # time spent computing the error metrics is not render time
                while pending:
                    f = r.render_frame(0, aovs=False)
                    done += 1
                    tc = time.perf_counter()
                    record(f.color[..., :3], tc - t0 - paused, done)
                    paused += time.perf_counter() - tc
            else:
                raise ValueError(f"unknown mode {mode!r} (accumulate, taa)")
            last = report.series(name, mode)[-1]
            log(f"{name:<24} {mode:<10} {last.frames:>6} frames in {last.seconds:6.2f} s: relMSE {last.rel_mse:.3e}")
    if cycles is not False:
        add_cycles(report, scene if cycles is True else None, budgets, ref, log, bpy_scene=None if cycles is True
                   else cycles)
    return report


def add_cycles(report: Report, scene: Scene | None, budgets, ref: np.ndarray, log: Callable[[str], None] = print,
               bpy_scene=None, threads: int = 0) -> bool:
    """Rows for Cycles (direct light only, time-limited) at the same budgets; a note and False without bpy."""
    from . import cycles

    if not cycles.available():
        msg = "Cycles: bpy is not importable in this Python; Cycles was skipped (run under a Python with bpy)"
        report.notes.append(msg)
        log(msg)
        return False
    sc = bpy_scene if bpy_scene is not None else cycles.to_bpy(scene)
    cycles.render(sc, samples=1, threads=threads)  # warm-up: kernel loading
    for b in sorted(budgets):
        res = cycles.render(sc, seconds=b, threads=threads, seed=1)
        report.rows.append(Row("cycles", "accumulate", b, res.render_seconds, res.samples, rel_mse(res.image, ref),
                               rmse(res.image, ref), flip(res.image, ref)))
        log(f"{'cycles':<24} {'accumulate':<10} time limit {b:5.2f} s: render {res.render_seconds:5.2f} s "
            f"(call {res.total_seconds:5.2f} s), relMSE {report.rows[-1].rel_mse:.3e}")
    report.notes.append("Cycles: direct light only (bounces 0, light threshold 0, box filter 1 px, no adaptive "
                        "sampling, no denoising, no clamping), CPU, time-limited (Cycles' time_limit, which "
                        "excludes synchronisation); seconds are Cycles' own render time from the EXR metadata")
    return True


def relmse_single_frames(scene: Scene, methods: list[str], reference: np.ndarray, frames: int = 8, warmup: int = 8,
                         device=None) -> dict[str, tuple[float, float]]:
    """(mean relMSE of single frames after warm-up, ms per frame) per method."""
    out = {}
    for name in methods:
        r = Renderer(scene, Settings(**METHODS[name], seed=77, taa=False), device)
        for _ in range(warmup):
            r.render_frame(0, still=True, aovs=False)
        errs, ms = [], []
        for _ in range(frames):
            f = r.render_frame(0, still=True, aovs=False)
            errs.append(rel_mse(f.noisy, reference))
            ms.append(f.ms)
        out[name] = (float(np.mean(errs)), float(np.median(ms)))
    return out


def slope(rows: list[Row]) -> float:
    """Least-squares slope of log(relMSE) against log(seconds)."""
    if len(rows) < 2:
        return math.nan
    x = np.log([r.seconds for r in rows])
    y = np.log([max(r.rel_mse, 1e-30) for r in rows])
    if np.ptp(x) == 0:
        return math.nan
    return float(np.polyfit(x, y, 1)[0])


# ---- moving camera: error per frame at equal time per frame --------------------------------------------------


@dataclass
class FrameRow:
    method: str
    mode: str  # taa (TAA output) | frame (mean of this frame's samples, no TAA)
    frame: int
    budget_ms: float
    ms: float  # wall time spent on this frame
    samples: int  # samples (sub-frames) rendered for this frame
    rel_mse: float
    rmse: float


@dataclass
class MovingReport:
    scene: str
    device: str
    width: int
    height: int
    budget_ms: float
    rows: list[FrameRow] = field(default_factory=list)
    references: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def keys(self) -> list[tuple[str, str]]:
        order = list(METHODS)
        return sorted(dict.fromkeys((r.method, r.mode) for r in self.rows),
                      key=lambda k: (k[1] != "taa", order.index(k[0]) if k[0] in order else 99))

    def series(self, method: str, mode: str) -> list[FrameRow]:
        return [r for r in self.rows if r.method == method and r.mode == mode]

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
        frames = sorted({r.frame for r in self.rows})
        lines = [f"{'relMSE':<24} {'mode':<6} " + " ".join(f"{'f' + str(f):>9}" for f in frames)
                 + f" {'mean':>9} {'ms/frame':>9} {'spp':>5}"]
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
        return _write(base, header, cells, meta, self.plot)

    def plot(self, path: Path) -> Path | None:
        lines = []
        for method, mode in self.keys():
            rows = self.series(method, mode)
            lines.append(([r.frame for r in rows], [r.rel_mse for r in rows], method, mode,
                          "-" if mode == "taa" else "--"))
        return _plot(path, lines, (9.5, 5.0), False, "animation frame", "relMSE vs that frame's reference",
                     f"{self.scene} {self.width}x{self.height}, moving camera, {self.budget_ms:.0f} ms per frame, "
                     f"on {self.device}")


def _write(base: Path, header: list[str], cells: list[list], meta: dict,
           plot: Callable[[Path], Path | None]) -> list[Path]:
    """base.csv (header + cells), base.json (meta) and base.png (plot, when matplotlib imports)."""
    base.parent.mkdir(parents=True, exist_ok=True)
    with open(base.with_suffix(".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(cells)
    base.with_suffix(".json").write_text(json.dumps(meta, indent=1))
    paths = [base.with_suffix(".csv"), base.with_suffix(".json")]
    png = plot(base.with_suffix(".png"))
    if png:
        paths.append(png)
    return paths


def _plot(path: Path, lines: list, size: tuple[float, float], log_x: bool, xlabel: str, ylabel: str,
          title: str) -> Path | None:
    """One log-y plot, a line (xs, ys, method, mode, linestyle) per method and mode, the legend beside it."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, ax = plt.subplots(figsize=size, dpi=110)
    for xs, ys, method, mode, ls in lines:
        ax.plot(xs, ys, marker="o", ms=3, ls=ls, label=f"{method} ({mode})", **_style(method))
    if log_x:
        ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _style(method: str) -> dict:
    """One colour per method (the same in every mode); Cycles thick and black."""
    if method == "cycles":
        return {"color": "black", "lw": 2.2}
    colours = ["#7f7f7f", "#bcbd22", "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#e377c2", "#17becf", "#9467bd"]
    names = list(METHODS)
    return {"color": colours[names.index(method) % len(colours)] if method in names else None}


def _read_rgb(r: Renderer, buf) -> np.ndarray:
    img = np.empty((r.height, r.width, 4), np.float32)
    cl.enqueue_copy(r.device.queue, img, buf)
    return img[..., :3]


def frame_time_ms(scene: Scene, name: str, device=None, frames: int = 4, base: Settings | None = None) -> float:
    """Median wall time (ms) of one animation frame of `name` (after a warm-up frame)."""
    r = Renderer(scene, _settings(name, base, 1), device)
    r.render_frame(0, aovs=False)
    r.render_frame(1 % scene.frames, aovs=False)
    ms = []
    for f in range(1, frames + 1):
        t0 = time.perf_counter()
        r._render(min(f, scene.frames - 1), still=False)
        ms.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(ms))


def run_moving(scene: Scene, methods: list[str], budget_ms: float | None = None, every: int = 4,
               modes=("taa",), device=None, base: Settings | None = None, log: Callable[[str], None] = print,
               reference_seconds: float = 20.0, cache_dir: Path | None = None, seed: int = 4242,
               references: dict[int, np.ndarray] | None = None) -> MovingReport:
    """Each method renders every frame of the animation in order, with `budget_ms` of wall time per frame (default:
    the slowest method's frame time, so that each renders at least one sample per frame and the faster ones
    render more); the error of every `every`-th frame (and the last) is taken against that frame's reference."""
    cam = scene.camera
    assert cam is not None
    n = scene.frames
    evaluated = sorted({*range(0, n, max(every, 1)), n - 1})
    if budget_ms is None:
        budget_ms = max(frame_time_ms(scene, m, device, base=base) for m in methods)
        log(f"budget: {budget_ms:.0f} ms per frame (the slowest method's frame time)")
    rep = MovingReport(scene.name, "", cam.width, cam.height, float(budget_ms))
    refs: dict[int, np.ndarray] = dict(references or {})
    for f in evaluated:
        if f not in refs:
            ref = get_reference(scene, f, reference_seconds, device=device, cache_dir=cache_dir, log=log)
            refs[f] = ref.image
            rep.references[str(f)] = {"method": ref.method, "frames": ref.frames, "est_rel_mse": ref.est_rel_mse}
    budget = budget_ms / 1e3
    for name in methods:
        for mode in modes:
            if mode not in ("taa", "frame"):
                raise ValueError(f"unknown mode {mode!r} (taa, frame)")
            r = Renderer(scene, _settings(name, base, seed), device)
            rep.device = r.device.label
            for _ in range(2):  # warm-up (kernels compile at their first launch); then start without history
                r._render(0, still=mode == "frame")
            r.reset()
            still = mode == "frame"
            per_sample = None
            for f in range(n):
                t0 = time.perf_counter()
                k = 0
                acc = None
                while True:
                    t1 = time.perf_counter()
                    _, color_buf, _ = r._render(f, still=still)
                    if still:
                        s = _read_rgb(r, r.sample_buf)
                        acc = s.astype(np.float64) if acc is None else acc + s
                    k += 1
                    dt = time.perf_counter() - t1
                    per_sample = dt if per_sample is None else 0.8 * per_sample + 0.2 * dt
                    # another sample if it ends nearer the budget than stopping now does
                    if time.perf_counter() - t0 + 0.5 * per_sample >= budget:
                        break
                img = acc / k if still else _read_rgb(r, color_buf)
                ms = (time.perf_counter() - t0) * 1e3
                if f in refs:
                    rep.rows.append(FrameRow(name, mode, f, float(budget_ms), ms, k, rel_mse(img, refs[f]),
                                             rmse(img, refs[f])))
            rows = rep.series(name, mode)
            log(f"{name:<24} {mode:<6} mean relMSE {np.mean([x.rel_mse for x in rows]):.3e}, "
                f"{np.mean([x.samples for x in rows]):.1f} samples and {np.mean([x.ms for x in rows]):.0f} ms "
                "per frame")
    return rep


def load(path: Path) -> Report | MovingReport:
    """A report back from the JSON that write() wrote."""
    meta = json.loads(Path(path).read_text())
    if "budget_ms" in meta:
        return MovingReport(meta["scene"], meta["device"], meta["width"], meta["height"], meta["budget_ms"],
                            [FrameRow(**r) for r in meta["rows"]], meta.get("references", {}), meta.get("notes", []))
    return Report(meta["scene"], meta["device"], meta["width"], meta["height"], [Row(**r) for r in meta["rows"]],
                  meta.get("reference", {}), meta.get("notes", []))


def replot(path: Path) -> list[Path]:
    """Draw the PNG of a written report again (e.g. when it was run under a Python without matplotlib)."""
    rep = load(path)
    png = rep.plot(Path(path).with_suffix(".png"))
    if png is None:
        raise ValueError("replot needs matplotlib")
    return [png]
