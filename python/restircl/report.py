"""Error against run time (`restircl report`): every method renders a still camera while the wall clock runs, and
its error against a converged reference is recorded at a series of time budgets. Writes a CSV and a JSON table and
a log-log plot (error against seconds, one line per method).

The reference is computed once per scene and resolution and cached (an unbiased estimator run long: RIS with many
candidates over many frames; `reference` itself when the scene has few lights). Unbiased methods fall with a slope
of about -1 on the plot; a biased one levels off at its bias.
"""

from __future__ import annotations

import csv
import hashlib
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .pipeline import Renderer, Settings
from .scene import Scene

# name -> (Settings overrides, accumulate (True) or TAA with a_min (False))
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
DEFAULT_BUDGETS = (0.25, 0.5, 1.0, 2.0, 4.0)


def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    """mean over pixels and channels of (x - r)^2 / (r^2 + 0.01)."""
    return float(np.mean((x - ref) ** 2 / (ref * ref + 0.01)))


def rmse(x: np.ndarray, ref: np.ndarray) -> float:
    return float(np.sqrt(np.mean((x - ref) ** 2)))


def flip(x: np.ndarray, ref: np.ndarray) -> float | None:
    """Mean FLIP (HDR) when `flip-evaluator` is installed, else None."""
    try:
        import flip_evaluator as flip_mod  # type: ignore[import-not-found]
    except ImportError:
        return None
    try:
        _, mean, _ = flip_mod.evaluate(ref.astype(np.float32), x.astype(np.float32), "HDR")
        return float(mean)
    except Exception:
        return None


def reference_image(scene: Scene, seconds_hint: float = 60.0, frames: int | None = None, device=None,
                    cache_dir: Path | None = None, log: Callable[[str], None] = print) -> np.ndarray:
    """A converged image of `scene` at frame 0, cached on disk by a hash of the scene file's content."""
    cache_dir = cache_dir or Path.home() / ".cache" / "restircl"
    cache_dir.mkdir(parents=True, exist_ok=True)
    tmp = cache_dir / "scene.tmp.npz"
    scene.save(tmp)
    digest = hashlib.sha256(tmp.read_bytes()).hexdigest()[:16]
    tmp.unlink()
    path = cache_dir / f"reference_{scene.name}_{digest}.npy"
    if path.exists():
        log(f"reference: cached {path}")
        return np.load(path)
    n_lights = len(scene.lights) + sum(1 for m in scene.materials if m.is_emissive)
    settings = Settings(method="reference" if n_lights <= 16 else "ris", candidates=32, seed=987654)
    r = Renderer(scene, settings, device)
    if frames is None:
        t0 = time.perf_counter()
        r.render_still(0, 4)
        per = (time.perf_counter() - t0) / 4
        frames = int(min(max(seconds_hint / max(per, 1e-6), 64), 8192))
    log(f"reference: {settings.method} x {frames} frames ...")
    img = r.render_still(0, frames).color[..., :3].astype(np.float32)
    np.save(path, img)
    log(f"reference: saved {path}")
    return img


@dataclass
class Row:
    method: str
    mode: str  # accumulate | taa
    budget_s: float
    seconds: float
    frames: int
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

    def write(self, out: Path) -> list[Path]:
        out.mkdir(parents=True, exist_ok=True)
        base = out / f"report_{self.scene}_{self.width}x{self.height}"
        with open(base.with_suffix(".csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["method", "mode", "budget_s", "seconds", "frames", "rel_mse", "rmse", "flip"])
            for r in self.rows:
                w.writerow([r.method, r.mode, r.budget_s, f"{r.seconds:.4f}", r.frames, f"{r.rel_mse:.6g}",
                            f"{r.rmse:.6g}", "" if r.flip is None else f"{r.flip:.6g}"])
        meta = {"scene": self.scene, "device": self.device, "width": self.width, "height": self.height,
                "rows": [r.__dict__ for r in self.rows]}
        base.with_suffix(".json").write_text(json.dumps(meta, indent=1))
        paths = [base.with_suffix(".csv"), base.with_suffix(".json")]
        png = self.plot(base.with_suffix(".png"))
        if png:
            paths.append(png)
        return paths

    def plot(self, path: Path) -> Path | None:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            return None
        fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=110)
        keys = sorted({(r.method, r.mode) for r in self.rows}, key=lambda k: (k[1], list(METHODS).index(k[0])
                                                                               if k[0] in METHODS else 99))
        for method, mode in keys:
            rows = [r for r in self.rows if r.method == method and r.mode == mode]
            ax.plot([r.seconds for r in rows], [r.rel_mse for r in rows], marker="o", ms=3,
                    ls="-" if mode == "accumulate" else "--", label=f"{method} ({mode})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall-clock seconds")
        ax.set_ylabel("relMSE vs reference")
        ax.set_title(f"{self.scene} {self.width}x{self.height} on {self.device}", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(path)
        plt.close(fig)
        return path

    def table(self) -> str:
        lines = [f"{'method':<24} {'mode':<10} " + " ".join(f"{b:>9.2f}s" for b in self.budgets())]
        for method, mode in dict.fromkeys((r.method, r.mode) for r in self.rows):
            rows = {r.budget_s: r for r in self.rows if r.method == method and r.mode == mode}
            lines.append(f"{method:<24} {mode:<10} " + " ".join(
                f"{rows[b].rel_mse:>10.3e}" if b in rows else f"{'-':>10}" for b in self.budgets()))
        return "\n".join(lines)

    def budgets(self) -> list[float]:
        return sorted({r.budget_s for r in self.rows})


def run_report(scene: Scene, methods: list[str], budgets: tuple[float, ...] = DEFAULT_BUDGETS, modes=("accumulate",),
               device=None, reference: np.ndarray | None = None, base: Settings | None = None,
               log: Callable[[str], None] = print) -> Report:
    """Render each method with a still camera until each budget (seconds) has passed; record the error."""
    if reference is None:
        reference = reference_image(scene, device=device, log=log)
    cam = scene.camera
    assert cam is not None
    report = Report(scene.name, "", cam.width, cam.height)
    budgets = tuple(sorted(budgets))
    for name in methods:
        overrides = METHODS[name]
        for mode in modes:
            settings = Settings(**{**(base.__dict__ if base else {}), **overrides, "seed": 4242})
            r = Renderer(scene, settings, device)
            report.device = r.device.label
            r.render_frame(0, still=True)  # warm-up: program build and first upload stay out of the timing
            r.reset()
            pending = list(budgets)
            if mode == "accumulate":
                def checkpoint(done: int, secs: float, r=r, pending=pending, name=name, mode=mode) -> None:
                    while pending and secs >= pending[0]:
                        img = r.mean_image()
                        report.rows.append(Row(name, mode, pending.pop(0), secs, done, rel_mse(img, reference),
                                               rmse(img, reference), flip(img, reference)))

                stop_at = budgets[-1]
                t0 = time.perf_counter()
                r.render_still(0, 1_000_000, should_stop=lambda t0=t0, stop_at=stop_at, pending=pending:
                               time.perf_counter() - t0
                               >= stop_at + 1e-3 or not pending, checkpoint=checkpoint)
            else:
                t0 = time.perf_counter()
                done = 0
                while pending:
                    f = r.render_frame(0)
                    done += 1
                    secs = time.perf_counter() - t0
                    while pending and secs >= pending[0]:
                        img = f.color[..., :3]
                        report.rows.append(Row(name, mode, pending.pop(0), secs, done, rel_mse(img, reference),
                                               rmse(img, reference), flip(img, reference)))
            last = [row for row in report.rows if row.method == name and row.mode == mode][-1]
            log(f"{name:<24} {mode:<10} {last.frames:>6} frames in {last.seconds:6.2f} s: relMSE {last.rel_mse:.3e}")
    return report


def relmse_single_frames(scene: Scene, methods: list[str], reference: np.ndarray, frames: int = 8, warmup: int = 8,
                         device=None) -> dict[str, tuple[float, float]]:
    """(mean relMSE of single frames after warm-up, ms per frame) per method."""
    out = {}
    for name in methods:
        r = Renderer(scene, Settings(**METHODS[name], seed=77, taa=False), device)
        for _ in range(warmup):
            r.render_frame(0, still=True)
        errs, ms = [], []
        for _ in range(frames):
            f = r.render_frame(0, still=True)
            errs.append(rel_mse(f.noisy, reference))
            ms.append(f.ms)
        out[name] = (float(np.mean(errs)), float(np.median(ms)))
    return out


def slope(rows: list[Row]) -> float:
    """Least-squares slope of log(relMSE) against log(seconds)."""
    x = np.log([r.seconds for r in rows])
    y = np.log([max(r.rel_mse, 1e-30) for r in rows])
    if len(rows) < 2 or np.ptp(x) == 0:
        return math.nan
    return float(np.polyfit(x, y, 1)[0])
