"""Where a test run's time goes: per test file, the CPU seconds, the programs it built and their build seconds, from
the log that $RESTIRCL_BUILD_LOG names (core/program.py writes a line per program build, tests/conftest.py a line
per test). A program counts for the test that was running in that process when it was built; `first` counts the
programs no earlier test of the run (any worker) had built: what a shared cache cannot save.

    RESTIRCL_BUILD_LOG=/tmp/builds.jsonl RESTIRCL_TEST_KERNEL_CACHE=fresh pytest -n 2 --dist loadfile
    python tools/test_profile.py /tmp/builds.jsonl [--top 30]
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path


def load(path: Path) -> tuple[list[dict], list[dict]]:
    tests, builds = [], []
    for line in path.read_text().splitlines():
        row = json.loads(line)
        (tests if "test" in row else builds).append(row)
    return tests, builds


def per_file(tests: list[dict], builds: list[dict]) -> dict[str, dict]:
    """file -> tests, cpu, children_cpu, builds, first builds, build seconds."""
    out: dict[str, dict] = defaultdict(lambda: dict(tests=0, cpu=0.0, children_cpu=0.0, builds=0, first=0, build_s=0.0))
    for t in tests:
        f = out[t["test"].split("::", 1)[0]]
        f["tests"] += 1
        f["cpu"] += t["cpu"]
        f["children_cpu"] += t["children_cpu"]
    seen: set[str] = set()
    by_pid = defaultdict(list)
    for t in tests:
        by_pid[t["pid"]].append(t)
    for b in sorted(builds, key=lambda r: r["t"]):
        owner = next((t for t in by_pid[b["pid"]] if t["t0"] <= b["t"] <= t["t1"]), None)
        f = out[owner["test"].split("::", 1)[0] if owner else "(outside tests)"]
        f["builds"] += 1
        f["first"] += b["hash"] not in seen
        f["build_s"] += b["s"]
        seen.add(b["hash"])
    return out


def concurrent_duplicates(builds: list[dict]) -> tuple[int, float]:
    """Builds of a program that another process was building at the same time (both cold: PoCL's cache had no entry
    yet): their count and seconds."""
    count, seconds = 0, 0.0
    by_hash = defaultdict(list)
    for b in builds:
        by_hash[b["hash"]].append(b)
    for rows in by_hash.values():
        for b in rows:
            if any(o["pid"] != b["pid"] and o["t"] - o["s"] < b["t"] and b["t"] - b["s"] < o["t"] for o in rows):
                count += 1
                seconds += b["s"]
    return count, seconds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log", type=Path)
    ap.add_argument("--top", type=int, default=30)
    args = ap.parse_args()
    tests, builds = load(args.log)
    files = per_file(tests, builds)
    print(
        f"{len(tests)} tests, {len(builds)} builds of {len({b['hash'] for b in builds})} distinct programs, "
        f"CPU {sum(t['cpu'] for t in tests):.0f} s (+{sum(t['children_cpu'] for t in tests):.0f} s children), "
        f"build calls {sum(b['s'] for b in builds):.0f} s"
    )
    dup, dup_s = concurrent_duplicates(builds)
    print(f"builds overlapping a build of the same program in another process: {dup} ({dup_s:.0f} s)")
    print("cpu_s  kids_s  tests  builds  first  build_s  file")
    for name, f in sorted(files.items(), key=lambda kv: -kv[1]["cpu"])[: args.top]:
        print(
            f"{f['cpu']:6.1f} {f['children_cpu']:6.1f} {f['tests']:6d} {f['builds']:7d} {f['first']:6d} "
            f"{f['build_s']:8.1f}  {name}"
        )


if __name__ == "__main__":
    main()
