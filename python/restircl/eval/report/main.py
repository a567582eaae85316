"""Error against run time for a still camera (`restircl report`).

Every method renders while the wall clock runs, and its error against a converged reference (eval/report/reference.py)
is recorded at a series of time budgets; Cycles (direct light only) is rendered at the same budgets when `bpy`
imports. Writes a CSV and a JSON table and a log-log plot (error against seconds, one line per method). Unbiased
methods fall with a slope of about -1 on the plot; a biased one levels off at its bias. The moving camera is
eval/report/moving.py.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ...render.pipeline import Renderer
from ...scene.scene import Scene
from ...settings.table import Settings
from ..metrics import FLIP_MISSING, flip, flip_available, rel_mse, rmse
from .files import ReportBase, plot_lines, write_files
from .methods import METHODS, method_settings
from .moving import FrameRow, MovingReport
from .reference import Reference, get_reference

DEFAULT_BUDGETS = (0.25, 0.5, 1.0, 2.0, 4.0)


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
class Report(ReportBase):
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
        base = Path(out) / f"report_{self.scene}_{self.width}x{self.height}"
        return write_files(base, header, cells, meta, self.plot)

    def keys(self) -> list[tuple[str, str]]:
        return self._keys("accumulate", [*METHODS, "cycles"])

    def slopes(self) -> dict[str, float]:
        return {f"{m} ({mode})": slope(self.series(m, mode)) for m, mode in self.keys()}

    def plot(self, path: Path) -> Path | None:
        return plot_lines(path, self._lines("seconds", "accumulate"), (9.5, 5.4), True,
                          "wall-clock seconds (after kernel build and scene upload)", "relMSE vs reference",
                          f"{self.scene} {self.width}x{self.height} on {self.device}")

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
    if not flip_available():
        report.notes.append(FLIP_MISSING)
        log(FLIP_MISSING)
    budgets = tuple(sorted(budgets))
    for name in methods:
        for mode in modes:
            r = Renderer(scene, method_settings(name, base, seed), device)
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
    from ..cycles import bridge as cycles

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


def slope(rows: list[Row]) -> float:
    """Least-squares slope of log(relMSE) against log(seconds)."""
    if len(rows) < 2:
        return math.nan
    x = np.log([r.seconds for r in rows])
    y = np.log([max(r.rel_mse, 1e-30) for r in rows])
    if np.ptp(x) == 0:
        return math.nan
    return float(np.polyfit(x, y, 1)[0])


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
