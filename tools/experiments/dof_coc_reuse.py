"""ReSTIR's spatial reuse across the circle of confusion, the simplest variant of Area ReSTIR's idea (Zhang et al.
2024): in animation frames with depth of field, the spatial pass's disk grown from `spatial_radius` to the pixel's
circle of confusion (its radius in pixels: aperture * |1 / depth - 1 / focus| * pixels per unit of the view plane,
at most 64), so that a blurred pixel draws its neighbours from the pixels its blur spreads over. Built with
-D EXPERIMENT_COC_RADIUS_SCALE / EXPERIMENT_COC_FOCUS_INV (opencl/restir/spatial.cl, compiled out of every
ordinary build) against the default build, the same frames and seeds: the neighbour count is unchanged, so the
time per frame is the same and the comparison is at equal time (the ms columns say so). docs/design.md, "Depth of
field and motion blur in motion"; figures in docs/measurements/dof_coc_reuse.md.

    python -m tools.experiments.dof_coc_reuse --scene moving_box --width 160 --height 120 --radius 0.12
    python -m tools.experiments.dof_coc_reuse --scene many_lights --width 160 --height 90 --radius 0.3
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterator

import numpy as np
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.render import pipeline
from restircl.settings.table import Settings

from .dof_motion import SCENES, animation, scene_arguments


@contextlib.contextmanager
def extra_defines(defines: tuple[str, ...]) -> Iterator[None]:
    """Renderers made inside build their kernels with these -D options added."""
    build = pipeline.build_program
    options = tuple(f"-D{d}" for d in defines)
    pipeline.build_program = lambda device, flags=None, **kw: build(device, flags, extra_options=options, **kw)
    try:
        yield
    finally:
        pipeline.build_program = build


def coc_defines(scene) -> tuple[str, ...]:
    """The spatial pass's circle-of-confusion radius: pixels per unit of the view plane times the aperture."""
    cam = scene.camera
    scale = cam.aperture_radius * cam.width / (2.0 * cam.view_plane()[0])
    return (f"EXPERIMENT_COC_RADIUS_SCALE={scale!r}f", f"EXPERIMENT_COC_FOCUS_INV={1.0 / cam.focus_distance!r}f")


def main() -> None:
    ap = scene_arguments(__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=3)
    a = ap.parse_args()
    evaluated = {k for k in range(a.frames) if k % a.every == a.every - 1}
    make, focus = SCENES[a.scene]
    scene = make(a.width, a.height, frames=a.frames)
    assert scene.camera is not None
    scene.camera.aperture_radius, scene.camera.focus_distance = a.radius, focus
    refs = {k: get_reference(scene, k, a.ref_seconds).image[..., :3] for k in sorted(evaluated)}
    result: dict = {"scene": a.scene, "size": [a.width, a.height], "radius": a.radius, "defines": coc_defines(scene),
                    "load_before": os.getloadavg(), "rows": []}
    for seed in range(1, a.seeds + 1):
        row: dict = {"seed": seed}
        for name, defines in (("default", ()), ("coc_radius", coc_defines(scene))):
            with extra_defines(defines):
                ms, images = animation(scene, evaluated, Settings(seed=seed))
            row[f"{name}_ms"] = ms
            row[f"{name}_rel_mse"] = float(np.mean([rel_mse(images[k], refs[k]) for k in evaluated]))
        print(json.dumps(row), flush=True)
        result["rows"].append(row)
    result["load_after"] = os.getloadavg()
    print(json.dumps(result))


if __name__ == "__main__":
    main()
