"""Shadow rays through a smooth thin wall against Cycles 5.3 (issue 39): eval/scenes/thin_wall.py's clear pane lit by
a point light in front of it alone ("point only"), and by the area light behind the camera ("area"), with shadow rays
passing the pane (the HAS_THIN_SHADOW build) and stopped at it (as before), at equal samples. Prints each case's
relMSE against Cycles with the noise left in, and converged (test_blender_cycles_glass.converged_relmse).

    PYTHONPATH=python:addon:. /tmp/ci_s5/.venv-blender/5.3/bin/python tools/experiments/thin_shadow_agreement.py [spp]
"""

from __future__ import annotations

import sys

import restircl.upload.device_scene as device_scene

from tests.blender.test_blender_cycles_glass import converged_relmse
from tests.blender.test_blender_cycles_thin_shadow import cycles, ours


def main() -> None:
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 128
    passing = device_scene.scene_has_thin_shadow
    for lamp in ("point only", "area"):
        cyc = cycles(lamp, spp)
        for name, has in (("passing", passing), ("stopped", lambda scene: False)):
            device_scene.scene_has_thin_shadow = has
            rel, raw, z = converged_relmse(ours(lamp, spp), cyc)
            print(f"{lamp:10s} {name}: {spp} spp relMSE {raw:.5f}, converged {rel:.5f}, means {z:.1f} SE apart",
                  flush=True)
        device_scene.scene_has_thin_shadow = passing


if __name__ == "__main__":
    main()
