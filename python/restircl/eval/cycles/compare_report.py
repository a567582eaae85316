"""The tables, files and plot of `restircl compare` (eval/cycles/compare.py): relMSE per scene kind, method and budget
(median over the repetitions, with their range), and our error divided by Cycles' at equal wall time."""

from __future__ import annotations

import csv
import json
import statistics
from dataclasses import asdict
from pathlib import Path

from .compare import ALL_METHODS, KindResult, Row

COLOURS = {"cycles": "black", "default": "#d62728", "ris": "#1f77b4", "auto": "#2ca02c"}


def _series(rows: list[Row], method: str, budget: float) -> list[Row]:
    return sorted((r for r in rows if r.method == method and r.budget_s == budget), key=lambda r: r.rep)


def summary(result: KindResult) -> dict:
    """{method: {budget: {median, min, max, seconds, samples, over_budget, ratio, ratio_min, ratio_max,
    ratio_means}}}; the ratios (ours / Cycles, paired by repetition) only where Cycles ran, and ratio_means the
    ratio of the two methods' mean relMSE over those repetitions: where one side's error is heavy-tailed (a caustic
    that some repetitions meet), the median of a few paired ratios scatters widely around the ratio of the expected
    errors, which the means estimate; over_budget counts the repetitions that took more than OVER_BUDGET x the
    budget (for Cycles: its ratios are not at equal time)."""
    out: dict[str, dict[str, dict]] = {}
    budgets = sorted({r.budget_s for r in result.rows})
    for m in ALL_METHODS:
        for b in budgets:
            rows = _series(result.rows, m, b)
            if not rows:
                continue
            errs = [r.rel_mse for r in rows]
            cell = {"median": statistics.median(errs), "min": min(errs), "max": max(errs),
                    "seconds": statistics.median(r.seconds for r in rows),
                    "samples": statistics.median(r.samples for r in rows), "reps": len(rows),
                    "over_budget": sum(r.over_budget for r in rows)}
            cyc = {r.rep: r.rel_mse for r in _series(result.rows, "cycles", b)}
            ratios = [r.rel_mse / cyc[r.rep] for r in rows if r.rep in cyc and cyc[r.rep] > 0]
            if m != "cycles" and ratios:
                paired = [r.rel_mse for r in rows if r.rep in cyc and cyc[r.rep] > 0]
                cycles_paired = [cyc[r.rep] for r in rows if r.rep in cyc and cyc[r.rep] > 0]
                cell.update(ratio=statistics.median(ratios), ratio_min=min(ratios), ratio_max=max(ratios),
                            ratio_means=statistics.fmean(paired) / statistics.fmean(cycles_paired))
            out.setdefault(m, {})[f"{b:g}"] = cell
    return out


def ratio_table(results: list[KindResult]) -> str:
    """Markdown: per kind, our relMSE / Cycles' at each budget (median of the paired repetitions, range, and with
    more than two repetitions the ratio of the means after 'means'); where Cycles took longer than OVER_BUDGET x the
    budget, its median seconds follow with a '>' (not equal time)."""
    ran = {r.method for res in results for r in res.rows}
    ours = [m for m in ALL_METHODS if m != "cycles" and m in ran]
    budgets = sorted({r.budget_s for res in results for r in res.rows})
    head = " / ".join(f"{b:g}" for b in budgets)
    lines = ["| scene kind | " + " | ".join(f"{m} at {head} s" for m in ours) + " |",
             "|---|" + "---|" * len(ours)]
    for res in results:
        s = summary(res)
        cells = []
        for m in ours:
            parts = []
            for b in budgets:
                c = s.get(m, {}).get(f"{b:g}")
                cyc = s.get("cycles", {}).get(f"{b:g}")
                late = f" [Cycles > {cyc['seconds']:.1f} s]" if cyc and cyc["over_budget"] else ""
                means = f"; means {c['ratio_means']:.2g}" if c is not None and c.get("reps", 0) > 2 else ""
                parts.append("-" if c is None or "ratio" not in c else
                             f"{c['ratio']:.2g} ({c['ratio_min']:.2g}..{c['ratio_max']:.2g}{means}){late}")
            cells.append(" / ".join(parts))
        lines.append(f"| {res.kind} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def error_table(results: list[KindResult]) -> str:
    """Markdown: relMSE median (min..max), median seconds and samples per kind, method and budget."""
    budgets = sorted({r.budget_s for res in results for r in res.rows})
    lines = ["| kind | method | " + " | ".join(f"{b:g} s: relMSE (range), s, spp" for b in budgets) + " |",
             "|---|---|" + "---|" * len(budgets)]
    for res in results:
        s = summary(res)
        for m, cells in s.items():
            parts = []
            for b in budgets:
                c = cells.get(f"{b:g}")
                parts.append("-" if c is None else f"{c['median']:.2e} ({c['min']:.2e}..{c['max']:.2e}), "
                             f"{c['seconds']:.2f}, {c['samples']:.0f}")
            lines.append(f"| {res.kind} | {m} | " + " | ".join(parts) + " |")
    return "\n".join(lines)


def agreement_table(results: list[KindResult]) -> str:
    lines = ["| kind | ours converged vs Cycles reference: relMSE | sum ours / Cycles | Cycles reference | "
             "its est. relMSE | ours: method x frames, s, est. relMSE |", "|---|---|---|---|---|---|"]
    for res in results:
        a, ref = res.agreement, res.reference
        est = a["ours_est_rel_mse"]
        secs = f"{a['ours_seconds']:.0f} s, " if "ours_seconds" in a else ""
        lines.append(f"| {res.kind} | {100 * a['rel_mse']:.3f} % | {a['sum_ratio']:.4f} | 2 x {ref.spp} spp, "
                     f"{ref.seconds:.0f} s | {ref.est_rel_mse:.1e} | {a['ours_method']} x {a['ours_frames']}, "
                     f"{secs}{'n/a' if est is None else f'{est:.1e}'} |")
    return "\n".join(lines)


def plot(results: list[KindResult], path: Path, title: str) -> Path | None:
    """One log-log panel per kind: relMSE against wall seconds, the median and the range of the repetitions."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, axes = plt.subplots(1, len(results), figsize=(4.2 * len(results), 3.8), dpi=110, squeeze=False)
    for ax, res in zip(axes[0], results, strict=True):
        for m, cells in summary(res).items():
            xs = [c["seconds"] for c in cells.values()]
            ys = [c["median"] for c in cells.values()]
            err = [[y - c["min"] for y, c in zip(ys, cells.values(), strict=True)],
                   [c["max"] - y for y, c in zip(ys, cells.values(), strict=True)]]
            ax.errorbar(xs, ys, yerr=err, marker="o", ms=3, capsize=2, label=m, color=COLOURS.get(m),
                        lw=2.0 if m == "cycles" else 1.3)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(res.kind, fontsize=9)
        ax.set_xlabel("wall seconds of the render call")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("relMSE vs 2x1024-spp Cycles")
    axes[0][0].legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def write(results: list[KindResult], out: Path, meta: dict) -> list[Path]:
    """out/data/compare_cycles_WxH.csv (every row) and .json (rows, summaries, references, agreement, meta),
    out/img/compare_cycles_WxH.png; with bounces WxH is followed by the Light Paths' tag (paths.LightPaths.tag)."""
    w, h = meta["width"], meta["height"]
    data, img = Path(out) / "data", Path(out) / "img"
    data.mkdir(parents=True, exist_ok=True)
    img.mkdir(parents=True, exist_ok=True)
    base = f"compare_cycles_{w}x{h}{meta.get('light_paths_tag', '')}"
    rows = [r for res in results for r in res.rows]
    with open(data / f"{base}.csv", "w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(list(asdict(rows[0])) if rows else list(Row.__dataclass_fields__))
        wr.writerows([list(asdict(r).values()) for r in rows])
    record = {**meta, "kinds": {res.kind: {
        "summary": summary(res), "agreement": res.agreement, "cycles_calibration": res.cycles_calibration,
        "reference": {"spp": res.reference.spp, "seconds": res.reference.seconds,
                      "est_rel_mse": res.reference.est_rel_mse, "sum_rel_std": res.reference.sum_rel_std,
                      "path": res.reference.path},
        "rows": [asdict(r) for r in res.rows]} for res in results}}
    (data / f"{base}.json").write_text(json.dumps(record, indent=1))
    paths = [data / f"{base}.csv", data / f"{base}.json"]
    what = meta.get("light_paths", "direct light")
    png = plot(results, img / f"{base}.png", f"ours vs Cycles ({what}), {w}x{h}, {meta.get('device', '')}")
    if png:
        paths.append(png)
    return paths


def main(a) -> int:
    """`restircl compare`: run cycles_compare on the chosen kinds, print the tables, write the files."""
    import os
    import platform

    from ..scenes.kinds import KINDS
    from . import bridge as cycles
    from .compare import OURS, run
    from .paths import LightPaths

    if not cycles.available():
        raise ValueError("compare: needs the bpy module (run under a Python with bpy installed)")
    kinds = a.kinds.split(",")
    methods = a.methods.split(",")
    for what, names, known in (("kind", kinds, KINDS), ("method", methods, ALL_METHODS)):
        bad = [n for n in names if n not in known]
        if bad:
            raise ValueError(f"compare: unknown {what} {bad}; choose from {', '.join(known)}")
    paths = LightPaths.of(a.max_bounces, a.diffuse_bounces, a.glossy_bounces)
    load = os.getloadavg()
    results = run(kinds, budgets=tuple(a.budgets), reps=a.reps, methods=tuple(methods), width=a.width,
                  height=a.height, reference_spp=a.reference_spp, threads=a.threads, device=a.device,
                  cache_dir=Path(a.cache_dir) if a.cache_dir else None, agreement_seconds=a.agreement_seconds,
                  cycles_world_map=a.cycles_world_map, paths=paths)
    from ...core.device import get_device

    meta = {"width": a.width, "height": a.height, "budgets": list(a.budgets), "reps": a.reps, "threads": a.threads,
            "device": get_device(a.device).label, "cpu": platform.processor() or platform.machine(),
            "load_before": load, "load_after": os.getloadavg(), "ours": OURS, "cycles_world_map": a.cycles_world_map,
            "light_paths": paths.describe(), "light_paths_tag": paths.tag, "max_bounces": paths.max_bounces,
            "diffuse_bounces": paths.diffuse_bounces, "glossy_bounces": paths.glossy_bounces}
    print(f"Light Paths: {paths.describe()}; load average before {load[0]:.2f}, after {meta['load_after'][0]:.2f}")
    print(agreement_table(results))
    print(error_table(results))
    print(ratio_table(results))
    for path in write(results, Path(a.out), meta):
        print(f"wrote {path}")
    return 0
