"""The error of cheaper viewport frames at the same time per view: along the orbit of
restircl.eval.report.viewport_orbit (many_lights, one view change per frame), the default ReSTIR + TAA frame against
settings variants that make a frame cheaper, each given the default's mean time per view and spending it on as
many frames of that view as fit; relMSE of every 4th view against its converged reference, per seed:
docs/blender.md ("Frame time").

    python -m tools.experiments.viewport_variants --variant novis=visibility_reuse=false --seeds 7 8 9
"""

from __future__ import annotations

import argparse
import json
import os

import numpy as np
from restircl import Settings
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.eval.report.viewport_orbit import orbit_scene, policy_rows

from tools.experiments.viewport_frame_time import parse_variant


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--variant", action="append", default=[], help="name=key=value,... (repeatable)")
    ap.add_argument("--seeds", type=int, nargs="+", default=[7, 8, 9])
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=90)
    ap.add_argument("--views", type=int, default=24)
    ap.add_argument("--step", type=float, default=2.0, help="degrees of orbit per view (%(default)s)")
    ap.add_argument("--ref-seconds", type=float, default=5.0)
    a = ap.parse_args(argv)
    scene = orbit_scene(a.width, a.height, a.views, a.step)
    every = [k for k in range(a.views) if k % 4 == 3]
    refs = {k: get_reference(scene, k, a.ref_seconds, log=lambda _m: None).image for k in every}
    variants = dict(parse_variant(v) for v in a.variant)
    load_before = os.getloadavg()
    table: dict[str, dict[str, list[float]]] = {n: {"rel_mse": [], "ms": [], "frames": []}
                                                for n in ("default", *variants)}
    for seed in a.seeds:
        rows = {"default": policy_rows(scene, "reprojected", seed)}
        budget = float(np.mean([r["ms"] for r in rows["default"]]))
        for name, kw in variants.items():
            rows[name] = policy_rows(scene, "reprojected", seed, budget_ms=budget, settings=Settings(**kw))
        for name, rs in rows.items():
            sel = [r for r in rs if r["view"] in refs]
            table[name]["rel_mse"].append(float(np.mean([rel_mse(r["image"], refs[r["view"]]) for r in sel])))
            table[name]["ms"].append(float(np.mean([r["ms"] for r in rs])))
            table[name]["frames"].append(float(np.mean([r["frames"] for r in rs])))
    print(json.dumps({"size": f"{a.width}x{a.height}", "views": a.views, "step_deg": a.step, "seeds": a.seeds,
                      "load_before": load_before, "load_after": os.getloadavg(),
                      "settings": {"default": {}, **variants}, "per_seed": table,
                      "mean_rel_mse": {n: float(np.mean(t["rel_mse"])) for n, t in table.items()}}, indent=1))


if __name__ == "__main__":
    main()
