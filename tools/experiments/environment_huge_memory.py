"""The 16384 x 8192 environment stress case (tests/environment/test_stress.py::test_16384_by_8192_map_renders) with
a chosen texel format, for its peak memory: run it under /usr/bin/time -v and read "Maximum resident set size".

    /usr/bin/time -v python -m tools.experiments.environment_huge_memory half|float|auto
"""

from __future__ import annotations

import sys

import numpy as np
from restircl import Environment, Renderer, Settings
from restircl.lights import environment
from restircl.scenes.hdri_sky import sky


def main(fmt: str) -> None:
    environment.TEXEL_FORMAT = fmt
    img = np.full((8192, 16384, 3), 0.25, np.float32)  # 1.6 GB of source image, counted in the peak
    img[4000:4010, 9000:9010] = 5e3
    scene = sky(24, 16, map_height=16)
    scene.environment = Environment("huge", color=(1, 1, 1), image=img)
    r = Renderer(scene, Settings(method="ris", seed=2))
    out = np.stack([r.render_frame(0, still=True).color for _ in range(2)])
    packed = r.device_scene.lights.environment
    assert packed is not None and np.all(np.isfinite(out)) and out[..., :3].mean() > 0
    print(f"texels {packed.stored.fmt}, table {packed.kind}, device data {packed.data.nbytes / 1e9:.2f} GB")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "auto")
