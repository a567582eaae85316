"""One source for every code that crosses the host/device line (python/restircl/upload/codes.py): opencl/codes.h is
what the Python tables give, no kernel source defines a code itself, and a kernel reads every value as the host
has it. Each check is shown to catch the fault it is there for (a stale header, a stray #define, a value the device
reads differently)."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl.core.program import build_program, opencl_dir
from restircl.upload import codes
from restircl.upload.codes import Family, families, header

DEFINE = re.compile(r"^\s*#\s*define\s+(\w+)\b", re.M)


def stray_defines(root: Path, fams: tuple[Family, ...]) -> list[str]:
    """`file: NAME` for every #define of a family's name in a kernel source other than the generated header."""
    names = {n for f in fams for n, _ in f.codes}
    out = []
    for path in sorted(root.rglob("*")):
        if path.suffix in (".h", ".cl") and path.name != codes.HEADER:
            out += [f"{path.relative_to(root)}: {m}" for m in DEFINE.findall(path.read_text()) if m in names]
    return out


def device_values(device, fams: tuple[Family, ...]) -> dict[str, float]:
    """Every family's names as a kernel that includes types.h (which includes codes.h) reads them."""
    names = [n for f in fams for n, _ in f.codes]
    writes = "\n".join(f"    out[{k}] = (float)({n});" for k, n in enumerate(names))
    src = f'#include "types.h"\n__kernel void read_codes(__global float* out)\n{{\n{writes}\n}}\n'
    prog = build_program(device, {}, source=src)
    out = np.full(len(names), np.nan, np.float32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    prog.read_codes(device.queue, (1,), None, buf)
    cl.enqueue_copy(device.queue, out, buf)
    return dict(zip(names, out.tolist(), strict=True))


def mismatches(read: dict[str, float], fams: tuple[Family, ...]) -> list[str]:
    """Names whose value read on the device differs from the host's (as float32, how the kernel wrote them)."""
    return [n for f in fams for n, v in f.codes if read.get(n) != float(np.float32(v))]


def test_header_is_current():
    assert (opencl_dir() / codes.HEADER).read_text() == header(), "run python -m restircl.upload.codes"
    assert codes.main(["--check"]) == 0


def test_a_changed_table_makes_the_header_stale():
    fams = families()
    light = next(i for i, f in enumerate(fams) if f.title == "light types")
    moved = replace(fams[light], codes=((fams[light].codes[0][0], 99), *fams[light].codes[1:]))
    assert header((*fams[:light], moved, *fams[light + 1:])) != (opencl_dir() / codes.HEADER).read_text()


def test_no_kernel_source_defines_a_code_itself(tmp_path):
    assert stray_defines(opencl_dir(), families()) == []
    # the scan finds one where it is
    (tmp_path / "lights").mkdir()
    (tmp_path / "lights" / "sphere.h").write_text("#define LIGHT_SPHERE 3\n")
    (tmp_path / codes.HEADER).write_text("#define LIGHT_SPHERE 3\n")
    assert stray_defines(tmp_path, families()) == ["lights/sphere.h: LIGHT_SPHERE"]


def test_every_family_reads_the_same_on_the_device(device):
    fams = families()
    read = device_values(device, fams)
    assert mismatches(read, fams) == []
    # a value the device would read differently is reported by name
    bias = next(i for i, f in enumerate(fams) if f.title.startswith("reuse modes"))
    wrong = replace(fams[bias], codes=tuple((n, v + 1 if n == "BIAS_PAIRWISE" else v) for n, v in fams[bias].codes))
    assert mismatches(read, (*fams[:bias], wrong, *fams[bias + 1:])) == ["BIAS_PAIRWISE"]


def test_families_are_well_formed():
    """Names unique over all families; an enum's codes distinct; a flag family's values distinct powers of two."""
    names = [n for f in families() for n, _ in f.codes]
    assert len(names) == len(set(names))
    assert {f.kind for f in families()} == {"enum", "flags", "constants"}
    for f in families():
        values = [v for _, v in f.codes]
        if f.kind == "enum":
            assert len(set(values)) == len(values) and all(isinstance(v, int) for v in values), f.title
        elif f.kind == "flags":
            assert all(v > 0 and v & (v - 1) == 0 for v in values) and len(set(values)) == len(values), f.title
    assert codes.c_literal(-1) == "(-1)" and codes.c_literal(0.25) == "0.25f" and codes.c_literal(1e-30) == "1e-30f"


def test_light_flags_are_distinct_bits_below_the_link_index():
    """A light record's flag word holds one bit per LIGHT_FLAG_* and, from LINK_SHIFT up, its link record's index
    (lights/linking.py): two flags on one bit, or a flag in the index's bits, would read one feature as another."""
    from restircl.lights import linking, record

    flags = {"TWO_SIDED": record.FLAG_TWO_SIDED, "TEXTURED": record.FLAG_TEXTURED,
             "SHADOW_LINKED": linking.FLAG_SHADOW_LINKED}
    text = header()
    for name in ("SOFT_FALLOFF", "SOLID_ANGLE", "SA_AUTO", "SA_NEAR"):
        flags[name] = int(text.split(f"#define LIGHT_FLAG_{name}")[1].split()[0])
    values = list(flags.values())
    assert all(v > 0 and v & (v - 1) == 0 for v in values), flags
    assert len(set(values)) == len(values), flags
    assert max(values) < 1 << linking.LINK_SHIFT, flags
