"""Error against run time with and without BSDF-sampled candidates (docs/error-vs-time.md, "BSDF candidates").

    python tools/bsdf_report.py neon|glossy_many_lights|SCENE.npz OUT_DIR REFERENCE_SECONDS METHODS

The scene is built in-process (restircl.eval.bsdf_scenes: scene files do not keep glossy inputs yet), at 160x90;
the reference is RIS with 32 light candidates and one BSDF candidate (both unbiased: tests/test_bsdf_candidates.py)
for REFERENCE_SECONDS; METHODS are names of restircl.eval.report_methods.METHODS, comma-separated."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from restircl import Renderer, Scene, Settings
from restircl.eval.bsdf_scenes import SCENES
from restircl.eval.report import run_report


def main() -> None:
    name, out, ref_s, methods = sys.argv[1], Path(sys.argv[2]), float(sys.argv[3]), sys.argv[4].split(",")
    scene = SCENES[name]() if name in SCENES else Scene.load(name)
    assert scene.camera is not None
    scene.camera.width, scene.camera.height = 160, 90
    r = Renderer(scene, Settings(method="ris", candidates=32, bsdf_sampling="on", seed=987654))
    r.render_still(0, 2)
    t0 = time.perf_counter()
    acc, n = np.zeros((90, 160, 3)), 0
    while time.perf_counter() - t0 < ref_s:
        acc += r.render_still(0, 16).color
        n += 1
    print(f"reference: ris 32 + bsdf, {16 * n} frames, {time.perf_counter() - t0:.1f} s")
    rep = run_report(scene, methods, (0.5, 1.0, 2.0, 4.0), ("accumulate",), reference=acc / max(n, 1))
    print(rep.table())
    for p in rep.write(out):
        print("wrote", p)


if __name__ == "__main__":
    main()
