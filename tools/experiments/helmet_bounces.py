"""The real DamagedHelmet's scene (tests/blender/gltf_scenes.py real_helmet_scene, the test's own) with Light Paths
Max Bounces 4 (diffuse and glossy 4, Cycles' transparent limit lifted: eval/cycles/bridge.py light_paths) against
Cycles, then with direct light alone, so that the bounced light's share and its error are seen apart (issue 41,
docs/blender.md).

    RESTIRCL_ASSETS=/work/assets python -m tools.experiments.helmet_bounces [WIDTH HEIGHT CYCLES_SPP OURS_SPP]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from restircl.eval import assets  # noqa: E402

from tests.blender.asset_corpus import compare  # noqa: E402
from tests.blender.gltf_scenes import real_helmet_scene  # noqa: E402


def main(argv: list[str]) -> None:
    w, h, cyc_spp, our_spp = (int(a) for a in argv) if argv else (48, 36, 2048, 1024)
    path, why = assets.find("DamagedHelmet.glb")
    if path is None:
        raise SystemExit(why)
    for bounces in (4, 0):
        out = Path(tempfile.mkdtemp(prefix=f"helmet_b{bounces}_"))
        r = compare(real_helmet_scene(path, w, h), cyc_spp, our_spp, bounces, out)
        print(f"bounces {bounces}: {w}x{h} Cycles {cyc_spp} / ours {our_spp}: relMSE {100 * r['relmse']:.3f} %  "
              f"mean ours/cycles {r['mean_ratio']:.4f}  t_cycles {r['t_cycles']:.0f} s t_ours {r['t_ours']:.0f} s  "
              f"images in {out}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
