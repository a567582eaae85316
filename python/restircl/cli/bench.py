"""`restircl bench`: benchmark figures (restircl/eval/bench, imported when the command runs)."""

from __future__ import annotations

import argparse

from .arguments import COUNT


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    b = sub.add_parser("bench", help="benchmarks: traversal vs Embree, frame times, light-count scaling",
                       description="Print benchmark figures (not timed tests).")
    b.add_argument("what", nargs="?", choices=("traversal", "frame", "lights", "taa", "filter", "first-image", "all"),
                   default="all",
                   help="traversal: ours vs Embree; frame: ms per stage and method; lights: frame time against "
                        "the light count; taa: error against frame number; filter: the real-time filter's ms "
                        "at 1..5 iterations; first-image: seconds from a fresh process to a still's first frame, "
                        "per phase, with an empty and a warm kernel cache (default: all)")
    b.add_argument("--computed-tables", action="store_true",
                   help="first-image: compute the GGX tables in the process (the cost before they shipped)")
    b.add_argument("--triangles", type=COUNT, default=1_000_000)
    b.add_argument("--width", type=COUNT, default=640)
    b.add_argument("--height", type=COUNT, default=360)
    b.add_argument("--no-embree", action="store_true")
    b.add_argument("--device", default=None)
    b.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    from ..eval.bench import filter as bench_filter
    from ..eval.bench import first_image
    from ..eval.bench import main as bench

    rc = bench.main(a) if a.what not in ("filter", "first-image") else 0
    if a.what in ("filter", "all"):
        rc = rc or bench_filter.main(a)
    if a.what in ("first-image", "all"):
        rc = rc or first_image.main(a)
    return rc
