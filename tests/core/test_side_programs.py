"""The side programs' define lists (core/side_programs.py) against the preprocessor: a side program is built with the
defines it declares it reads and no others, so one it reads but does not declare would be dropped without a word.
Checked with `cpp` (Linux): for many define sets the side program's preprocessed text is the same with every define
as with those `defines()` keeps, and its kernel's code (the kernel and the functions, types and constants it
reaches) is the one the main program's headers give with every define. A table with a read left out fails both
(the negative controls)."""

from __future__ import annotations

import dataclasses
import random
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from restircl.core.kernels import parse_kernel_parameters
from restircl.core.program import MAIN_SOURCE, host_kernel_defines, opencl_dir
from restircl.core.side_programs import SIDE_PROGRAMS, TAA, SideProgram
from restircl.core.source_inline import inline_includes

from tools.experiments.kernel_flag_closures import closure_digests

CPP = shutil.which("cpp")
needs_cpp = pytest.mark.skipif(CPP is None or sys.platform != "linux", reason="needs the C preprocessor (cpp)")

_CONDITION = re.compile(r"^[ \t]*#[ \t]*(?:if|ifdef|ifndef|elif)\b(.*)$", re.M)
_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_GUARD = re.compile(r"RESTIRCL_\w+_H")
_NAME = re.compile(r"\b[A-Z_][A-Z0-9_]*\b")
RANDOM_SETS = 24


def _sources() -> list[Path]:
    return sorted(p for p in opencl_dir().rglob("*") if p.suffix in (".h", ".cl"))


def defines_a_build_may_pass() -> set[str]:
    """Every name a build may define: those the sources' #if lines test (not the headers' guards, nor the
    compiler's __names__), with the host's (settings table, BVH layout)."""
    names: set[str] = set()
    for path in _sources():
        for m in _CONDITION.finditer(_COMMENT.sub(" ", path.read_text())):
            names.update(_NAME.findall(m.group(1)))
    names = {n for n in names if not n.startswith("__") and not _GUARD.fullmatch(n)}
    return names | set(host_kernel_defines())


def _options(defines: dict[str, str]) -> list[str]:
    # the includes found by cpp under opencl/, as core/source_inline.py finds them (cpp skips a guarded repeat
    # faster than the inlined text's)
    return ["-I", str(opencl_dir()), *(f"-D{k}={v}" for k, v in sorted(defines.items()))]


def _preprocess(path: Path, defines: dict[str, str]) -> str:
    args = [CPP or "cpp", "-P", "-undef", *_options(defines), str(path)]
    return subprocess.run(args, capture_output=True, text=True, check=False).stdout


def define_sets(names: set[str], seed: int = 7) -> list[dict[str, str]]:
    """All on; the host's alone; each name off from all on and on from the host's alone; random sets (half the
    names, values 1 or 3, so that a test of a value is seen too)."""
    host = {k: str(v) for k, v in host_kernel_defines().items()}
    every = {n: host.get(n, "1") for n in sorted(names)}
    sets = [every, dict(host)]
    sets += [{k: v for k, v in every.items() if k != n} for n in sorted(names)]
    sets += [{**host, n: every[n]} for n in sorted(names)]
    rng = random.Random(seed)
    for _ in range(RANDOM_SETS):
        sets.append({**host, **{n: rng.choice(("1", "3")) for n in sorted(names) if rng.random() < 0.5}})
    return sets


def text_mismatches(side: SideProgram, names: set[str], first: bool = False) -> list[str]:
    """The define sets whose dropped defines change the side program's preprocessed text (`first`: the first)."""
    root = opencl_dir()
    path = root / side.source
    text = inline_includes(path.read_text(), side.source, root)
    used = {n for n in names if re.search(rf"\b{n}\b", text)}  # a name the text never spells cannot change it
    out = []
    for defines in define_sets(used):
        kept = {k: str(v) for k, v in side.defines(defines).items()}
        if kept != defines and _preprocess(path, defines) != _preprocess(path, kept):
            out.append(" ".join(sorted(set(defines) - set(kept))))
            if first:
                break
    return out


def closure_mismatches(side: SideProgram, folder: Path, names: set[str], sets: int = 8) -> list[str]:
    """The define sets under which a side program's kernels differ from those the main program's headers give with
    every define (the main source with the side program's includes after its own)."""
    root = opencl_dir()
    side_text = (root / side.source).read_text()
    includes = "\n".join(line for line in side_text.split("\n") if line.startswith("#include"))
    whole = folder / "whole.cl"
    whole.write_text((root / MAIN_SOURCE).read_text() + "\n" + includes + "\n")
    out = []
    for defines in define_sets(names)[:2] + define_sets(names, seed=11)[-sets:]:
        kept = {k: str(v) for k, v in side.defines(defines).items()}
        ref = closure_digests(whole, _options(defines), list(side.kernels))
        got = closure_digests(root / side.source, _options(kept), list(side.kernels))
        if ref != got or len(ref) != len(side.kernels):
            out.append(" ".join(sorted(defines)))
    return out


@needs_cpp
@pytest.mark.parametrize("side", SIDE_PROGRAMS, ids=lambda s: s.source)
def test_a_side_program_reads_only_the_defines_it_declares(side: SideProgram) -> None:
    assert text_mismatches(side, defines_a_build_may_pass()) == []


@needs_cpp
@pytest.mark.parametrize("side", SIDE_PROGRAMS, ids=lambda s: s.source)
def test_a_side_programs_kernels_are_the_main_headers_kernels(side: SideProgram, tmp_path: Path) -> None:
    assert closure_mismatches(side, tmp_path, defines_a_build_may_pass()) == []


@needs_cpp
def test_a_forgotten_define_fails_the_checks(tmp_path: Path) -> None:
    """Negative controls: TAA without HAS_GLOSSY among its reads fails both checks; without GLASS_KEEPS_HISTORY (a
    probe's define, read under HAS_TRANSMISSION alone) the text check."""
    names = defines_a_build_may_pass()
    no_glossy = dataclasses.replace(TAA, reads=tuple(n for n in TAA.reads if n != "HAS_GLOSSY"))
    assert text_mismatches(no_glossy, names, first=True)
    assert closure_mismatches(no_glossy, tmp_path, names, sets=2)
    no_glass = dataclasses.replace(TAA, reads=tuple(n for n in TAA.reads if n != "GLASS_KEEPS_HISTORY"))
    assert text_mismatches(no_glass, names, first=True)


def test_each_kernel_is_in_one_program() -> None:
    """A side program's kernels are those its source declares, and the main program declares none of them."""
    root = opencl_dir()
    main = parse_kernel_parameters(inline_includes((root / MAIN_SOURCE).read_text(), MAIN_SOURCE, root))
    for side in SIDE_PROGRAMS:
        own = parse_kernel_parameters(inline_includes((root / side.source).read_text(), side.source, root))
        assert set(own) == set(side.kernels), side.source
        assert not set(own) & set(main), side.source


def test_defines_keeps_the_read_ones() -> None:
    flags = {
        "HAS_GLOSSY": True,
        "HAS_SPOT_LIGHTS": True,
        "HAS_PATHS": True,
        "HAS_TEXTURES": False,
        "MAX_NEIGHBOURS": 16,
    }
    assert TAA.defines(flags) == {"HAS_GLOSSY": True}
