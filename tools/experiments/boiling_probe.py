"""What the boiling pixels of the flicker metric (eval/report/flicker.py) are: renders a scene's animation path (ReSTIR
defaults unless told) with the reservoirs, the 1-sample estimates and the TAA output of every frame read back, and
describes each boiling pixel of the kept frames: where its excess came from (one frame's sample or many), its final
reservoir (W, M, target, the contribution target x W against its neighbourhood's), where that sample came from
(this frame's candidates, the temporal history or a spatial neighbour) and how many frames it has been held.

    python -m tools.experiments.boiling_probe [many_lights|cornell_box] [--moving] [--npz out/boiling_probe.npz]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L
from restircl.eval.report import flicker as fl
from restircl.eval.report.reference import get_reference


def _read_res(r: Renderer, buf: cl.Buffer) -> np.ndarray:
    out = np.empty((r.height, r.width), L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, out, buf)
    return out


def _read_f4(r: Renderer, buf: cl.Buffer) -> np.ndarray:
    out = np.empty((r.height, r.width, 4), np.float32)
    cl.enqueue_copy(r.device.queue, out, buf)
    return out


def record(r: Renderer, frames: list[int]) -> dict[str, np.ndarray]:
    """Render `frames` on the animation path; per frame the reservoirs after the initial, temporal and spatial
    passes, the 1-sample estimate and the output."""
    rec: dict[str, list[np.ndarray]] = {k: [] for k in ("initial", "temporal", "final", "sample", "output",
                                                         "emission")}
    cur: dict[str, np.ndarray] = {}

    def wrap(stage, key):
        orig = stage.run

        def run(*a, **k):
            out = orig(*a, **k)
            cur[key] = _read_res(r, out if out is not None else a[1])
            return out
        stage.run = run

    wrap(r.initial, "initial")
    wrap(r.temporal, "temporal")
    wrap(r.spatial, "final")
    taa_orig = r.taa.run

    def taa(*a, **k):
        cur["sample"] = _read_f4(r, r.buffers.sample)
        return taa_orig(*a, **k)
    r.taa.run = taa
    for f in frames:
        out = r.render_frame(f, aovs=False).color
        cur.setdefault("temporal", cur["initial"])
        for k in ("initial", "temporal", "final", "sample"):
            rec[k].append(cur.get(k, cur["initial"]))
        rec["output"].append(out)
        g = np.empty((r.height, r.width), L.GSAMPLE)
        cl.enqueue_copy(r.device.queue, g, r.history.gbuf(r.history.prev))  # this frame's, after the swap
        rec["emission"].append(g["emission"][..., :3] @ fl.LUMINANCE)
        cur.clear()
    return {k: np.stack(v) for k, v in rec.items()}


def same_sample(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (a["light"] == b["light"]) & (a["u"] == b["u"]) & (a["v"] == b["v"]) & (a["light"] >= 0)


def describe(rec: dict[str, np.ndarray], refs: list[np.ndarray], kept: slice, radius: int = 30) -> list[dict]:
    lum = fl.LUMINANCE
    s = rec["sample"][..., :3] @ lum  # (T, H, W)
    fin = rec["final"]
    T, H, W = s.shape
    rows = []
    for t in range(kept.start, kept.stop):
        ref = refs[t - kept.start]
        mask = fl.boiling_mask(rec["output"][t], ref)
        rl = ref[..., :3] @ lum
        for y, x in zip(*np.nonzero(mask), strict=True):
            excess = s[: t + 1, y, x] - rl[y, x]
            pos = np.clip(excess, 0, None)
            top = float(pos.max() / pos.sum()) if pos.sum() > 0 else 0.0
            q = fin[t, y, x]
            # frames the final sample has been held in a row (still camera: the same pixel)
            age = 0
            while t - age - 1 >= 0 and same_sample(fin[t - age - 1, y, x], q):
                age += 1
            if same_sample(rec["initial"][t, y, x], q):
                origin = "initial"
            elif t > 0 and same_sample(fin[t - 1, y, x], q):
                origin = "temporal"
            else:
                origin = "spatial"
            y0, y1, x0, x1 = max(0, y - radius), min(H, y + radius + 1), max(0, x - radius), min(W, x + radius + 1)
            win = fin[t, y0:y1, x0:x1]
            copies = int(same_sample(win, np.broadcast_to(q, win.shape)).sum())
            contrib = win["target"] * win["W"]
            valid = win["light"] >= 0
            med = float(np.median(contrib[valid])) if valid.any() else 0.0
            wmean = float(np.mean(win["W"][valid])) if valid.any() else 0.0
            # the frame whose sample put the most excess into this pixel, and that frame's reservoir
            tmax = int(np.argmax(excess))
            qm = fin[tmax, y, x]
            em = rec["emission"][t, max(0, y - 1):y + 2, max(0, x - 1):x + 2]
            kind = ("emitter" if em.max() > 0 else "held" if age >= 4 else origin)
            rows.append(dict(t=t, y=int(y), x=int(x), kind=kind, out=float(rec["output"][t, y, x, :3] @ lum),
                             ref=float(rl[y, x]),
                             top_frame_share=top, spike_frame=tmax, spike=float(excess[tmax]),
                             light=int(q["light"]), W=float(q["W"]), M=float(q["M"]), target=float(q["target"]),
                             contrib=float(q["target"] * q["W"]), contrib_over_median=float(q["target"] * q["W"]) /
                             max(med, 1e-12), W_over_mean=float(q["W"]) / max(wmean, 1e-12), origin=origin, age=age,
                             copies=copies, spike_W=float(qm["W"]), spike_M=float(qm["M"]),
                             spike_contrib=float(qm["target"] * qm["W"]), spike_light=int(qm["light"])))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("scene", nargs="?", default="many_lights", choices=("many_lights", "cornell_box"))
    ap.add_argument("--moving", action="store_true")
    ap.add_argument("--warmup", type=int, default=16)
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--npz", default=None)
    ap.add_argument("--boiling-filter", type=float, default=0.0)
    ap.add_argument("--boiling-mode", default="weight")
    a = ap.parse_args()
    sc = scenes.many_lights(160, 90, frames=8) if a.scene == "many_lights" else scenes.cornell_box(96, 96)
    n = a.warmup + a.frames
    if a.moving:
        sc = fl.slowed(sc, 8)
        frames = list(range(n))
    else:
        frames = [0] * n
    kept = slice(a.warmup, n)
    refs = [get_reference(sc, f, 10.0, cache_dir=Path("out/refs"), log=lambda m: None).image
            for f in sorted(set(frames[kept]))]
    if not a.moving:
        refs = refs * a.frames
    r = Renderer(sc, Settings(seed=4242, boiling_filter=a.boiling_filter, boiling_mode=a.boiling_mode))
    rec = record(r, frames)
    rows = describe(rec, refs, kept)
    if a.npz:
        np.savez_compressed(a.npz, refs=np.stack(refs), **rec)
    print(f"{len(rows)} boiling pixels in {a.frames} frames ({len(rows) / a.frames:.1f} per frame)")
    if not rows:
        return
    emissive = np.array([row["ref"] for row in rows])
    print(f"  reference luminance at the pixel: median {np.median(emissive):.3g}")
    keys = ("top_frame_share", "W", "M", "contrib_over_median", "W_over_mean", "age", "copies")
    for k in keys:
        v = np.array([row[k] for row in rows])
        print(f"  {k:<20} median {np.median(v):10.3g}  p10 {np.percentile(v, 10):10.3g}  "
              f"p90 {np.percentile(v, 90):10.3g}")
    for o in ("initial", "temporal", "spatial"):
        print(f"  final sample from {o:<9} {sum(row['origin'] == o for row in rows)}")
    for o in ("emitter", "held", "initial", "temporal", "spatial"):
        sel = [row for row in rows if row["kind"] == o]
        if sel:
            c = np.median([row["spike_contrib"] for row in sel])
            print(f"  kind {o:<9} {len(sel):5d}  (median spike contribution {c:.3g}, age "
                  f"{np.median([row['age'] for row in sel]):.0f})")
    uniq = {(row["y"], row["x"]) for row in rows}
    print(f"  distinct pixels {len(uniq)}")
    for row in rows[:: max(1, len(rows) // 25)]:
        print("   ", {k: (round(v, 3) if isinstance(v, float) else v) for k, v in row.items()})


if __name__ == "__main__":
    main()
