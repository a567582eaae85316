"""`restircl stress`: stability of every method on the extreme scenes (restircl/eval/stress, imported when the
command runs); exit status 1 if a case fails."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..core.device import get_device
from ..settings.spec import Range
from .arguments import COUNT


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    st = sub.add_parser("stress", help="stability on extreme scenes: NaN/Inf, max value, relMSE, flicker per method",
                        description="Render the built-in extreme scenes (restircl/eval/stress/suite.py) with every "
                                    "method and check them against their references; exit status 1 if any fails. "
                                    "The flicker, flk/err and boil px columns: the temporal stability of 16 "
                                    "consecutive TAA outputs of each case's frame under test.")
    st.add_argument("--full", action="store_true", help="full sizes (1e6 lights, 5000 frames, ...): minutes")
    st.add_argument("--methods", default=None, help="comma-separated subset (default: all)")
    st.add_argument("--cases", default=None, help="comma-separated subset (default: all)")
    st.add_argument("--out", default=None, help="write stress.csv and stress.json here")
    st.add_argument("--seed", type=Range(int, 0).parse, default=0, help="shift of every random seed (%(default)s)")
    st.add_argument("--device", default=None)
    st.add_argument("--bench-specialisation", action="store_true",
                    help="instead: kernel build and frame times, specialised against general builds")
    st.add_argument("--bench-frames", type=COUNT, default=24, help="frames timed per build (%(default)s)")
    st.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    from ..eval.bench import specialisation as bench_specialisation
    from ..eval.stress import judging as stress_judging
    from ..eval.stress import suite as stress

    def log(line: str) -> None:
        print(line, file=sys.stderr, flush=True)

    if a.bench_specialisation:
        rows = bench_specialisation.bench_specialisation(frames=a.bench_frames, log=print)
        if a.out:
            Path(a.out).mkdir(parents=True, exist_ok=True)
            (Path(a.out) / "specialisation.json").write_text(json.dumps(rows, indent=1))
        return 0
    methods = a.methods.split(",") if a.methods else None
    names = a.cases.split(",") if a.cases else None
    device = get_device(a.device)
    print(f"device: {device.label}; {'full' if a.full else 'small'} sizes")
    results = stress.run(full=a.full, methods=methods, names=names, device=device, log=log, seed=a.seed)
    print(stress_judging.format_table(results))
    failed = [r for r in results if not r.passed]
    print(f"{len(results) - len(failed)} of {len(results)} passed")
    if a.out:
        for path in stress_judging.write(results, Path(a.out)):
            print(f"wrote {path}")
    return 1 if failed else 0
