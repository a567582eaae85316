"""`restircl compare`: ours against Cycles at equal wall time on the tuning scenes (restircl/eval/cycles, imported
when the command runs; needs bpy)."""

from __future__ import annotations

import argparse

from .arguments import BOUNCES, COUNT, POSITIVE, SECONDS


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    c = sub.add_parser("compare", help="ours against Cycles at equal wall time on the tuning scenes (needs bpy)",
                       description="Render the tuning scenes (studio, neon, garden; sky, an HDRI world, with "
                                   "--kinds; the validation scenes interior, outdoor and gallery and the tuning "
                                   "scenes of global illumination gi_tuning_room and gi_tuning_yard; user, a typical "
                                   "user's glossy, textured scene under an HDRI with 43 lights, built in Blender "
                                   "and exported by the add-on, a validation kind) with Cycles "
                                   "(direct light only, or --max-bounces) and our methods (default: ReSTIR as "
                                   "for an animation; auto: F12's still estimator; ris and the other still "
                                   "candidates of eval/cycles_compare.OURS) for each wall-time budget, and "
                                   "compare their relMSE against a cached 2 x N-spp Cycles image: tables, CSV/JSON, "
                                   "plot.")
    c.add_argument("--kinds", default="studio,neon,garden",
                   help="tuning kinds (studio, neon, garden, sky), the validation kinds (interior, outdoor: global "
                        "illumination; gallery, user: direct light) and the tuning kinds of global "
                        "illumination (gi_tuning_room, gi_tuning_yard) (%(default)s)")
    c.add_argument("--methods", default="cycles,default,auto,ris")
    c.add_argument("--budgets", type=POSITIVE.parse_list, default="1,4,16", help="seconds (%(default)s)")
    c.add_argument("--reps", type=COUNT, default=3, help="repetitions of every budget (%(default)s)")
    c.add_argument("--width", type=COUNT, default=192)
    c.add_argument("--height", type=COUNT, default=108)
    c.add_argument("--reference-spp", type=COUNT, default=1024, help="samples of each of the two reference halves")
    c.add_argument("--agreement-seconds", type=SECONDS, default=60.0, help="time for our converged image")
    c.add_argument("--threads", type=COUNT, default=2, help="Cycles' render threads (%(default)s)")
    c.add_argument("--cycles-world-map", type=int, default=0, metavar="N",
                   help="the timed Cycles renders' world importance map: Manual at N (default 0: Blender's "
                        "Automatic, built in every render call)")
    c.add_argument("--max-bounces", type=BOUNCES, default=0, metavar="N",
                   help="Light Paths of every render, ours and Cycles' (timed, reference, calibration): Max Bounces "
                        "(default 0: direct light only)")
    c.add_argument("--diffuse-bounces", type=BOUNCES, default=None, metavar="N",
                   help="Light Paths: Diffuse (default: Cycles' 4, never more than --max-bounces)")
    c.add_argument("--glossy-bounces", type=BOUNCES, default=None, metavar="N",
                   help="Light Paths: Glossy (default: Cycles' 4, never more than --max-bounces)")
    c.add_argument("--cache-dir", default=None, help="reference cache (default: ~/.cache/restircl)")
    c.add_argument("--out", default="out", help="writes OUT/data/compare_cycles_WxH.* and OUT/img/...png")
    c.add_argument("--device", default=None)
    c.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    from ..eval.cycles import compare_report as cycles_compare_report

    return cycles_compare_report.main(a)
