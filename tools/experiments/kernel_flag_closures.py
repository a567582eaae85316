"""Which kernels' code changes with the feature flags: per kernel of opencl/restircl.cl, how many distinct
preprocessed closures (the kernel and every function, type and global it reaches, after the preprocessor has
expanded the flags) the flag sets of a $RESTIRCL_BUILD_LOG run give, against how many of that run's programs compiled
the kernel at its first launch. A kernel with one closure reads no flag those sets vary (the film program's kernels,
opencl/film/film.cl); one with few could have a program keyed by fewer flags. `--flags` also lists the flags whose
removal from the all-features set changes each kernel's closure. Needs a C preprocessor (`cpp`).

    python tools/experiments/kernel_flag_closures.py /tmp/builds.jsonl [--flags taa primary]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import subprocess
import tempfile
from collections import defaultdict
from pathlib import Path

from restircl.core.program import MAIN_SOURCE, opencl_dir
from restircl.core.side_programs import SIDE_PROGRAMS
from restircl.core.source_inline import inline_includes

IDENT = re.compile(r"[A-Za-z_]\w*")


def top_level_items(text: str) -> dict[str, list[str]]:
    """The preprocessed text's top-level declarations and definitions by name (a function's name, a typedef's)."""
    out: dict[str, list[str]] = defaultdict(list)
    depth, start, i = 0, 0, 0
    while i < len(text):
        c = text[i]
        if c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                m = re.match(r"\s*(\w+)?\s*;", text[i + 1 :])  # typedef struct {...} Name;
                end = i + 1 + (m.end() if m else 0)
                _add(out, text[start:end])
                start = i = end
                continue
        elif c == ";" and depth == 0:
            _add(out, text[start : i + 1])
            start = i + 1
        i += 1
    return out


def _add(out: dict[str, list[str]], item: str) -> None:
    item = item.strip()
    if not item:
        return
    head = item.split("{", 1)[0]
    if "(" in head and not head.lstrip().startswith("typedef"):
        name = IDENT.findall(head.split("(", 1)[0])[-1]
    else:
        ids = IDENT.findall(item.rsplit("}", 1)[-1]) or IDENT.findall(head)
        name = ids[-1] if ids else item[:20]
    out[name].append(item)


def closure_digests(source: Path, options: list[str], kernels: list[str]) -> dict[str, str]:
    """kernel -> digest of its closure in `source` preprocessed with the -D `options`."""
    text = subprocess.run(["cpp", "-P", "-undef", *options, str(source)], capture_output=True, text=True).stdout
    items = top_level_items(text)
    out = {}
    for k in kernels:
        if k not in items:
            continue
        seen: set[str] = set()
        stack = [k]
        while stack:
            name = stack.pop()
            if name in seen or name not in items:
                continue
            seen.add(name)
            for item in items[name]:
                stack.extend(set(IDENT.findall(item)) - seen)
        body = "\n".join(x for name in sorted(seen) for x in items[name])
        out[k] = hashlib.sha1(body.encode()).hexdigest()[:12]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("log", type=Path)
    ap.add_argument("--flags", nargs="*", default=[], help="kernels whose flags to list")
    args = ap.parse_args()
    rows = [json.loads(line) for line in args.log.read_text().splitlines()]
    # the renderer's programs: those with a feature flag (a test's own source has other kernels)
    sets: dict[tuple[str, ...], set[str]] = defaultdict(set)  # options -> the programs (digests) built with them
    for r in rows:
        if "options" in r and any("-DHAS_" in o for o in r["options"]):
            sets[tuple(r["options"])].add(r["hash"])
    first: dict[str, dict[str, float]] = defaultdict(dict)
    for r in rows:
        if "kernel" in r:
            first[r["kernel"]].setdefault(r["hash"], r["s"])
    root = opencl_dir()
    with tempfile.TemporaryDirectory() as tmp:
        source = Path(tmp) / "program.cl"
        source.write_text(inline_includes((root / MAIN_SOURCE).read_text(), MAIN_SOURCE, root))
        digests: dict[str, dict[str, str]] = defaultdict(dict)
        for options, programs in sets.items():
            for k, d in closure_digests(source, list(options), list(first)).items():
                digests[k].update(dict.fromkeys(programs, d))
        for side in SIDE_PROGRAMS:  # a side program's kernels (core/side_programs.py), with the defines it keeps
            path = Path(tmp) / side.source.replace("/", "_")
            path.write_text(inline_includes((root / side.source).read_text(), side.source, root))
            for options, programs in sets.items():
                kept = side.defines(dict(o[2:].partition("=")[::2] for o in options))
                for k, d in closure_digests(path, [f"-D{n}={v}" for n, v in kept.items()], list(side.kernels)).items():
                    digests[k].update(dict.fromkeys(programs, d))
        for k in sorted(digests, key=lambda k: -sum(first[k].values())):
            progs = [h for h in digests[k] if h in first[k]]
            seconds = sum(first[k][h] for h in progs)
            print(
                f"{k:26s} programs {len(progs):4d}  distinct closures {len({digests[k][h] for h in progs}):4d}  "
                f"first launches {seconds:6.1f} s"
            )
        if args.flags:
            _flag_dependence(source, sets, args.flags)


def _flag_dependence(source: Path, sets: dict[tuple[str, ...], set[str]], kernels: list[str]) -> None:
    """The flags whose removal from the all-features set changes each kernel's closure."""
    every: dict[str, str] = {}
    for options in sets:
        for o in options:
            every.setdefault(o.split("=")[0], o)
    base = closure_digests(source, list(every.values()), kernels)
    found: dict[str, list[str]] = defaultdict(list)
    for name in every:
        if not name.startswith(("-DHAS_", "-DTRANSPARENT")):
            continue
        changed = closure_digests(source, [o for n, o in every.items() if n != name], kernels)
        for k in kernels:
            if changed.get(k) != base.get(k):
                found[k].append(name[2:])
    for k in kernels:
        print(f"{k}: {' '.join(found[k])}")


if __name__ == "__main__":
    main()
