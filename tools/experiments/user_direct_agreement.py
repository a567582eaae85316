"""`restircl compare`'s agreement figure on the `user` kind (direct light: our converged image against Cycles' 2 x N
spp reference, eval/cycles/compare.py agreement), for the world read texel by texel (Closest: what the exporter made
of Blender's Environment Texture before it read the node's interpolation) and as the node says (Linear, Blender's
default), against one cached reference. The renders' own noise (their estimated relMSE, from half buffers) is
subtracted to give the renderers' difference. docs/measurements/error-vs-time.md, "user's direct light against
Cycles".

    nice python -m tools.experiments.user_direct_agreement --seconds 240 --cache-dir out/cache
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from restircl.eval.cycles.compare import agreement, cycles_reference, scene_pair


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--width", type=int, default=192)
    p.add_argument("--height", type=int, default=108)
    p.add_argument("--reference-spp", type=int, default=1024)
    p.add_argument("--seconds", type=float, default=60.0, help="our converged image's time (as --agreement-seconds)")
    p.add_argument("--interpolations", default="Closest,Linear")
    p.add_argument("--cache-dir", default="out/cache")
    p.add_argument("--out", default=None, help="a JSON file for the figures")
    a = p.parse_args()
    scene, sc = scene_pair("user", a.width, a.height)
    assert scene.environment is not None
    ref = cycles_reference("user", scene, sc, a.reference_spp, 2, Path(a.cache_dir))
    out = {}
    for interp in a.interpolations.split(","):
        scene.environment.interpolation = interp
        r = agreement(scene, ref, seconds=a.seconds, cache_dir=Path(a.cache_dir))
        r["difference"] = r["rel_mse"] - r["ours_est_rel_mse"] - r["cycles_est_rel_mse"]
        out[interp] = r
        print(
            f"{interp}: relMSE {r['rel_mse']:.3e}, sum ratio {r['sum_ratio']:.4f}, noise ours "
            f"{r['ours_est_rel_mse']:.2e} ({r['ours_frames']} frames) + Cycles {r['cycles_est_rel_mse']:.2e}, "
            f"difference {r['difference']:.2e}"
        )
    if a.out:
        Path(a.out).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
