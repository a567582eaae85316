"""What the still-camera and the moving-camera reports share: their header, their rows by method and mode, and the
files they write (a CSV table, a JSON record and a log-y plot when matplotlib imports)."""

from __future__ import annotations

import csv
import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from .methods import METHODS


@dataclass
class ReportBase:
    """A report's header; a subclass adds `rows`, each with a `method` and a `mode`."""

    scene: str
    device: str
    width: int
    height: int

    def _keys(self, first_mode: str, order: list[str]) -> list[tuple[str, str]]:
        """(method, mode) of the rows: `first_mode` first, then the methods in `order` (others last)."""
        return sorted(dict.fromkeys((r.method, r.mode) for r in self.rows),
                      key=lambda k: (k[1] != first_mode, order.index(k[0]) if k[0] in order else 99))

    def series(self, method: str, mode: str) -> list:
        return [r for r in self.rows if r.method == method and r.mode == mode]

    def _lines(self, x: str, solid_mode: str) -> list:
        """One plot line per method and mode (see plot_lines), relMSE against the rows' field `x`."""
        lines = []
        for method, mode in self.keys():
            rows = self.series(method, mode)
            lines.append(([getattr(r, x) for r in rows], [r.rel_mse for r in rows], method, mode,
                          "-" if mode == solid_mode else "--"))
        return lines


def write_files(base: Path, header: list[str], cells: list[list], meta: dict,
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


def plot_lines(path: Path, lines: list, size: tuple[float, float], log_x: bool, xlabel: str, ylabel: str,
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
        ax.plot(xs, ys, marker="o", ms=3, ls=ls, label=f"{method} ({mode})", **method_style(method))
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


def method_style(method: str) -> dict:
    """One colour per method (the same in every mode); Cycles thick and black."""
    if method == "cycles":
        return {"color": "black", "lw": 2.2}
    colours = ["#7f7f7f", "#bcbd22", "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#e377c2", "#17becf", "#9467bd"]
    names = list(METHODS)
    return {"color": colours[names.index(method) % len(colours)] if method in names else None}
