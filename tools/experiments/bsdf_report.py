"""Error against run time with and without BSDF-sampled candidates (docs/measurements/error-vs-time.md, "BSDF
candidates").

    python -m tools.experiments.bsdf_report neon|glossy_many_lights|SCENE.npz OUT_DIR REFERENCE_SECONDS METHODS

The scene is built in-process (restircl.eval.scenes.bsdf: scene files do not keep glossy inputs yet), at 160x90;
the reference is RIS with 32 light candidates and one BSDF candidate (both unbiased:
tests/render/test_bsdf_candidates.py) for REFERENCE_SECONDS; METHODS are names of
restircl.eval.report.methods.METHODS, comma-separated."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from restircl import Renderer, Scene, Settings
from restircl.eval.report.main import run_report
from restircl.eval.scenes.bsdf import SCENES


def main() -> None:
    name, out, ref_s, methods = sys.argv[1], Path(sys.argv[2]), float(sys.argv[3]), sys.argv[4].split(",")
    scene = SCENES[name]() if name in SCENES else Scene.load(name)
    assert scene.camera is not None
    scene.camera.width, scene.camera.height = 160, 90
    r = Renderer(scene, Settings(method="ris", candidates=32, bsdf_sampling="on", seed=987654))
    r.render_still(0, 2)
    t0 = time.perf_counter()
    # one accumulation, stopped by the clock: separate render_still calls would each restart the pixel jitter's
    # Halton sequence, and the reference would average the same few sub-pixel positions over and over
    ref = r.render_still(0, 1 << 30, should_stop=lambda: time.perf_counter() - t0 > ref_s)
    print(f"reference: ris 32 + bsdf, {ref.samples} frames, {time.perf_counter() - t0:.1f} s")
    rep = run_report(scene, methods, (0.5, 1.0, 2.0, 4.0), ("accumulate",), reference=ref.color[..., :3])
    print(rep.table())
    for p in rep.write(out):
        print("wrote", p)


if __name__ == "__main__":
    main()
