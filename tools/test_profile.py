"""Where a test run's time goes: per test file, the CPU seconds, the programs it built, the seconds of those builds
and of its kernels' first launches (where PoCL compiles each kernel), from the log that $RESTIRCL_BUILD_LOG names
(core/build_log.py writes a line per program build and per first launch of a kernel, tests/conftest.py a line per
test). A build or launch counts for the test that was running in that process at the time; `first` counts the
programs no earlier test of the run (any worker) had built: what a shared cache cannot save. Build and launch seconds
are wall time (under load, more than their CPU); a fetch from PoCL's cache takes well under a second.

    RESTIRCL_BUILD_LOG=/tmp/builds.jsonl RESTIRCL_TEST_KERNEL_CACHE=fresh pytest -n 2 --dist loadfile
    python tools/test_profile.py /tmp/builds.jsonl [--top 30]
"""

from __future__ import annotations

import argparse
import json
from collections import defaultdict
from pathlib import Path

COLUMNS = ("tests", "cpu", "children_cpu", "builds", "first", "build_s", "launch_s")


def load(path: Path) -> dict[str, list[dict]]:
    """The log's lines by kind: test, build, kernel."""
    rows: dict[str, list[dict]] = {"test": [], "build": [], "kernel": []}
    for line in path.read_text().splitlines():
        row = json.loads(line)
        rows["test" if "test" in row else "kernel" if "kernel" in row else "build"].append(row)
    return rows


def _owner(by_pid: dict[int, list[dict]], row: dict) -> str:
    """The test file running in the row's process when it ended."""
    start = row["t"] - row["s"]
    test = next((t for t in by_pid[row["pid"]] if t["t0"] - 0.01 <= start and row["t"] <= t["t1"] + 0.01), None)
    return test["test"].split("::", 1)[0] if test else "(outside tests)"


def per_file(rows: dict[str, list[dict]]) -> dict[str, dict]:
    out: dict[str, dict] = defaultdict(lambda: dict.fromkeys(COLUMNS, 0))
    by_pid: dict[int, list[dict]] = defaultdict(list)
    for t in rows["test"]:
        by_pid[t["pid"]].append(t)
        f = out[t["test"].split("::", 1)[0]]
        f["tests"] += 1
        f["cpu"] += t["cpu"]
        f["children_cpu"] += t["children_cpu"]
    seen: set[str] = set()
    for b in sorted(rows["build"], key=lambda r: r["t"]):
        f = out[_owner(by_pid, b)]
        f["builds"] += 1
        f["first"] += b["hash"] not in seen
        f["build_s"] += b["s"]
        seen.add(b["hash"])
    for k in rows["kernel"]:
        out[_owner(by_pid, k)]["launch_s"] += k["s"]
    return out


def concurrent_duplicates(rows: list[dict]) -> tuple[int, float]:
    """Builds of a program (or first launches of a kernel of it) that another process was doing at the same time (both
    cold: PoCL's cache had no entry yet): their count and seconds."""
    count, seconds = 0, 0.0
    by_hash = defaultdict(list)
    for b in rows:
        by_hash[b["hash"], b.get("kernel")].append(b)
    for same in by_hash.values():
        for b in same:
            if any(o["pid"] != b["pid"] and o["t"] - o["s"] < b["t"] and b["t"] - b["s"] < o["t"] for o in same):
                count += 1
                seconds += b["s"]
    return count, seconds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log", type=Path)
    ap.add_argument("--top", type=int, default=30)
    args = ap.parse_args()
    rows = load(args.log)
    tests, builds, kernels = rows["test"], rows["build"], rows["kernel"]
    print(
        f"{len(tests)} tests, CPU {sum(t['cpu'] for t in tests):.0f} s "
        f"(+{sum(t['children_cpu'] for t in tests):.0f} s of children); {len(builds)} builds of "
        f"{len({b['hash'] for b in builds})} distinct programs, {sum(b['s'] for b in builds):.0f} s; "
        f"first launches {sum(k['s'] for k in kernels):.0f} s"
    )
    dup, dup_s = concurrent_duplicates(builds)
    kdup, kdup_s = concurrent_duplicates(kernels)
    print(
        f"overlapping the same work in another process: {dup} builds ({dup_s:.0f} s), "
        f"{kdup} first launches ({kdup_s:.0f} s)"
    )
    print("cpu_s  kids_s  tests  builds  first  build_s  launch_s  file")
    for name, f in sorted(per_file(rows).items(), key=lambda kv: -kv[1]["cpu"])[: args.top]:
        print(
            f"{f['cpu']:6.1f} {f['children_cpu']:6.1f} {f['tests']:6d} {f['builds']:7d} {f['first']:6d} "
            f"{f['build_s']:8.1f} {f['launch_s']:8.1f}  {name}"
        )


if __name__ == "__main__":
    main()
