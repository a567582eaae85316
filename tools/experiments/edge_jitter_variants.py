"""Copies of this tree's python/ and opencl/ with a variant of the still's pixel jitter each, for a diagnosis only
(edge_convergence.py, edge_variance.py measure them with PYTHONPATH=<copy>/python):

- pp: the frame's Halton point rotated per pixel (Cranley-Patterson, by a hash of the pixel);
- sobol: the pixel's own scrambled Sobol pair (a dimension pair no sampler uses) under its own index shuffle;
- joint: dims 2 and 3 of the first light candidate's 4D group, whose dims 0 and 1 place the point on the light, so
  that the pixel position and the light point are one 4D Sobol net; the resampling choice (that group's dim 3) takes
  a pair of its own. Only for scenes of one light, where the pick (dim 2) chooses nothing.

The Sobol variants apply to stills from the Sobol sampler (RIS) and ignore Settings.jitter.

    python tools/experiments/edge_jitter_variants.py OUT_DIR
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ANCHOR = "    float2 ray_px = (float2)((float)x + 0.5f + cam->jitter.x, (float)y + 0.5f + cam->jitter.y);\n"
QMC = "        Qmc q = qmc_stream(frame_params.qmc, frame_params.qmc_index, frame_params.qmc_key, (uint)i);\n"
PRIMARY = {
    "pp": """    {
        float2 r = (float2)((float)(pcg_hash(2u * (uint)i + 17u) >> 8), (float)(pcg_hash(2u * (uint)i + 18u) >> 8));
        float2 j = (float2)(cam->jitter.x, cam->jitter.y) + 0.5f + r * (1.0f / 16777216.0f);
        j -= floor(j);
        ray_px = (float2)((float)x + j.x, (float)y + j.y);
    }
""",
    "sobol": "    {\n" + QMC + """        if (q.on) {
            float2 j = qmc_pair(&q, 0x70000u);
            ray_px = (float2)((float)x + j.x, (float)y + j.y);
        }
    }
""",
    "joint": "    {\n" + QMC + """        if (q.on) {
            uint4 a = qmc_quad_bits(&q, QMC_LIGHT(0));
            ray_px = (float2)((float)x + qmc_float(a.x), (float)y + qmc_float(a.w));
        }
    }
""",
}
SEL = "if (k0 + k == 0) sel = qmc_float(a.w);"


def patch(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    if old not in text:
        raise SystemExit(f"{path}: the code this variant patches has changed")
    path.write_text(text.replace(old, new))


def main() -> None:
    out = Path(sys.argv[1])
    for name, code in PRIMARY.items():
        tree = out / f"var_{name}"
        shutil.rmtree(tree, ignore_errors=True)
        for part in ("python", "opencl"):
            shutil.copytree(ROOT / part, tree / part, ignore=shutil.ignore_patterns("__pycache__"))
        patch(tree / "opencl" / "camera" / "primary.cl", ANCHOR, ANCHOR + code)
        if name == "joint":
            patch(tree / "opencl" / "direct" / "ris.h", SEL, "if (k0 + k == 0) sel = qmc_pair(q, 0x70001u).x;")
        print(tree)


if __name__ == "__main__":
    main()
