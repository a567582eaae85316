"""Our converged direct light on two small regions of the `user` kind, around the gold sphere's left rim and the
column's silhouette (issue 37), two renders (RIS, 32 candidates, seeds 101 and 102): cheap enough (about a minute
for 2 x 1024 frames) to compare variants of the kernel source run from a copy of the tree, pixel by pixel, against
each other and against the Cycles renders of tools/experiments/silhouette_probe.py. docs/measurements/
error-vs-time.md, "user: the metals' silhouettes".

    nice python -m tools.experiments.silhouette_regions --tag base --frames 1024
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from restircl.eval.cycles.compare import scene_pair
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings

#: name -> (x0, y0, x1, y1) of the 192 x 108 image, rows from the top
REGIONS = {"gold": (46, 48, 58, 62), "column": (106, 56, 116, 70)}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--tag", default="base")
    p.add_argument("--frames", type=int, default=1024)
    p.add_argument("--out", default="out/silhouette")
    a = p.parse_args()
    scene, _ = scene_pair("user", 192, 108)
    full = scene.camera
    assert full is not None
    out = {}
    for name, (x0, y0, x1, y1) in REGIONS.items():
        scene.camera = full.region(x0, y0, x1, y1)
        for k, seed in enumerate((101, 102)):
            s = Settings(method="ris", candidates=32, seed=seed).validate()
            f = Renderer(scene.validate(), s).render_still(0, a.frames)
            out[f"{name}{k}"] = np.asarray(f.color[..., :3], np.float64)
    path = Path(a.out) / f"region_{a.tag}_{a.frames}.npz"
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, **out)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
