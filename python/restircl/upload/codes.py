"""The integer codes and shared constants that cross the host/device line, each read from its one Python source,
and the header the kernels include (opencl/codes.h, generated from them: types.h includes it).

    python -m restircl.upload.codes          # rewrite opencl/codes.h from the Python tables
    python -m restircl.upload.codes --check  # exit 1 if opencl/codes.h is not what the tables give

A family is a prefix and (name, value) pairs: light types (`LIGHT_<TYPE>`, from each type's module through
lights/registry.py), the flags of the light records, closure kinds, texture nodes and their options, the reuse
modes (bias correction), the one-sample methods of the direct pass, the boiling filter's modes, TAA's history
filters, camera kinds, the guard counters, and the sizes and constants that host packing and device reading share.
Light proposals reach the device as on/off fields of SamplerParams (light_tree, pick_table), not as codes; the
sampler setting as the bits of FrameParams.qmc (QMC_*). No kernel source defines any of these names itself:
tests/upload/test_codes.py checks that, that the header is current, and that a kernel reads every value as the host
has it.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..core import layouts as L
from ..core.program import opencl_dir
from ..lights import (
    area_sampling,
    camera_visible,
    linking,
    pick_floor,
    pick_table,
    record,
    registry,
    sphere,
    tree,
    tree_exact,
)
from ..lights import environment as environment_light
from ..materials import thin_film
from ..materials.material import MAX_LAYERS
from ..materials.textures import (
    ATTRIBUTE_OUTPUTS,
    COLOR_MODES,
    COORDS,
    EXTENSIONS,
    INTERPOLATIONS,
    MATH_OPS,
    MIX_BLENDS,
    RAMP_INTERPOLATIONS,
    VECTOR_OPS,
)
from ..render import qmc
from ..render.passes import LIGHT_PLANES
from ..scene.camera import CAMERA_TYPES
from ..settings.table import BIAS_CORRECTIONS, BOILING_MODES, SHADE_METHODS, TAA_FILTERS
from . import ggx_tables, glass_tables, tri_attributes
from . import materials as material_pack
from . import textures as texture_pack

HEADER = "codes.h"


@dataclass(frozen=True)
class Family:
    """Codes of one kind: C macro names (prefix + name) and their values, with where the host defines them."""

    title: str
    source: str  # the Python place the values come from
    codes: tuple[tuple[str, int | float], ...]
    kind: str = "enum"  # "enum": distinct codes; "flags": distinct bits; "constants": sizes and parameters


def _enum(prefix: str, names: Sequence[str]) -> tuple[tuple[str, int], ...]:
    """Codes by position: prefix + NAME -> index."""
    return tuple((prefix + n.upper(), i) for i, n in enumerate(names))


def _texture_families() -> tuple[Family, ...]:
    """The texture programs' families (TexNode's op codes and the program's size), in the header's order."""
    return (
        Family("texture nodes (TexNode.op.x)", "upload/textures.py NODE_KINDS",
               _enum("TEXNODE_", [name for name, _ in texture_pack.NODE_KINDS])),
        Family("image interpolation (TexNode.op.y)", "materials/textures.py INTERPOLATIONS",
               _enum("TEXINTERP_", INTERPOLATIONS)),
        Family("image extension (TexNode.op.z)", "materials/textures.py EXTENSIONS", _enum("TEXEXT_", EXTENSIONS)),
        Family("texture coordinates (TexNode.op.w)", "materials/textures.py COORDS", _enum("TEXCOORD_", COORDS)),
        Family("Mix Color blend modes (TexNode.op.y)", "materials/textures.py MIX_BLENDS",
               _enum("TEXMIX_", MIX_BLENDS)),
        Family("Separate / Combine Color modes (TexNode.op.y)", "materials/textures.py COLOR_MODES",
               _enum("TEXCOLOR_", COLOR_MODES)),
        Family("Math operations (TexNode.op.y)", "materials/textures.py MATH_OPS", _enum("TEXMATH_", MATH_OPS)),
        Family("Vector Math operations (TexNode.op.y)", "materials/textures.py VECTOR_OPS",
               _enum("TEXVEC_", VECTOR_OPS)),
        Family("Color Ramp interpolations (TexNode.op.y)", "materials/textures.py RAMP_INTERPOLATIONS",
               _enum("TEXRAMP_", RAMP_INTERPOLATIONS)),
        Family("Attribute outputs (TexNode.op.z)", "materials/textures.py ATTRIBUTE_OUTPUTS",
               _enum("TEXATTR_", ATTRIBUTE_OUTPUTS)),
        Family("texture programs", "upload/textures.py", (("MAX_TEX_PROGRAM", texture_pack.MAX_TEX_PROGRAM),),
               kind="constants"),
    )


def families() -> tuple[Family, ...]:
    """Every family, in the header's order."""
    light_types = tuple((f"LIGHT_{t.name.upper()}", t.code) for t in registry.TYPES)
    return (
        Family("light types", "lights/<type>.py TYPE.code, listed by lights/registry.py", light_types),
        Family("flags of a Light record (L.w)", "lights/record.py, lights/sphere.py, lights/area_sampling.py", (
            ("LIGHT_FLAG_TWO_SIDED", record.FLAG_TWO_SIDED), ("LIGHT_FLAG_SOFT_FALLOFF", sphere.FLAG_SOFT_FALLOFF),
            ("LIGHT_FLAG_SOLID_ANGLE", area_sampling.FLAG_SOLID_ANGLE),
            ("LIGHT_FLAG_SA_AUTO", area_sampling.FLAG_SA_AUTO), ("LIGHT_FLAG_SA_NEAR", area_sampling.FLAG_SA_NEAR),
            ("LIGHT_FLAG_TEXTURED", record.FLAG_TEXTURED)),
               kind="flags"),
        Family("flags of the environment light's record", "lights/environment.py", (
            ("ENV_FLAG_CAMERA", environment_light.FLAG_CAMERA), ("ENV_FLAG_CDF", environment_light.FLAG_CDF),
            ("ENV_FLAG_HALF", environment_light.FLAG_HALF), ("ENV_FLAG_LINEAR", environment_light.FLAG_LINEAR)),
               kind="flags"),
        Family("closure kinds (Closure.kind.x)", "upload/materials.py KIND_CODE",
               tuple((f"CLOSURE_{k.upper()}", v) for k, v in material_pack.KIND_CODE.items())),
        Family("materials", "materials/material.py, upload/materials.py", (
            ("MAX_LAYERS", MAX_LAYERS), ("MATERIAL_MIX", material_pack.MATERIAL_MIX),
            ("TEX_NONE", material_pack.TEX_NONE)), kind="constants"),
        Family("thin film", "materials/thin_film.py", (("THIN_FILM_CUTOFF", thin_film.CUTOFF),), kind="constants"),
        *_texture_families(),
        Family("per-object attribute flags (ObjectInfo)", "upload/tri_attributes.py", (
            ("OBJECT_ATTRIBUTES", tri_attributes.OBJECT_ATTRIBUTES), ("OBJECT_NORMALS", tri_attributes.OBJECT_NORMALS),
            ("OBJECT_UVS", tri_attributes.OBJECT_UVS), ("OBJECT_HOLDOUT", tri_attributes.OBJECT_HOLDOUT),
            ("OBJECT_CAMERA_HIDDEN", tri_attributes.OBJECT_CAMERA_HIDDEN)), kind="flags"),
        Family("reuse modes (Settings.bias_correction)", "settings/table.py BIAS_CORRECTIONS",
               _enum("BIAS_", BIAS_CORRECTIONS)),
        Family("one-sample methods of the direct pass (ShadeParams.method)", "settings/table.py SHADE_METHODS",
               _enum("METHOD_", SHADE_METHODS)),
        Family("boiling filter modes (Settings.boiling_mode)", "settings/table.py BOILING_MODES",
               _enum("BOIL_", BOILING_MODES)),
        Family("TAA history filters (Settings.taa_filter)", "settings/table.py TAA_FILTERS",
               _enum("TAA_", TAA_FILTERS)),
        Family("the planes of the light passes", "render/passes.py LIGHT_PLANES",
               (*_enum("LPASS_", LIGHT_PLANES), ("LPASS_COUNT", len(LIGHT_PLANES))), kind="constants"),
        Family("camera kinds (Camera.kind)", "scene/camera.py CAMERA_TYPES", _enum("CAMERA_", CAMERA_TYPES)),
        Family("guard counters", "core/layouts.py GUARD_NAMES",
               (*_enum("GUARD_", L.GUARD_NAMES[: L.GUARD_COUNT - 1]), ("GUARD_COUNT", L.GUARD_COUNT)),
               kind="constants"),
        Family("the camera-visible lights' table", "lights/camera_visible.py", (
            ("CAMERA_LIGHT_ROWS", camera_visible.ROWS),), kind="constants"),
        Family("the per-pixel light pick", "lights/pick_table.py", (
            ("PICK_TABLE_MAX", pick_table.MAX_LIGHTS), ("PICK_TABLE_FLOOR", pick_table.FLOOR)), kind="constants"),
        Family("the light tree", "lights/tree.py, lights/pick_floor.py, lights/tree_exact.py", (
            ("LIGHT_TREE_FLOOR", pick_floor.FLOOR), ("LIGHT_TREE_MIN_BRANCH", pick_floor.MIN_BRANCH),
            ("LIGHT_TREE_TWO_SIDED", tree.NODE_TWO_SIDED), ("LIGHT_TREE_EXACT", tree_exact.EXACT),
            ("LIGHT_TREE_NEAR", tree_exact.NEAR)),
               kind="constants"),
        Family("GGX energy tables", "upload/ggx_tables.py", (
            ("GGX_E_SIZE", ggx_tables.E_SIZE), ("GGX_S_SIZE", ggx_tables.S_SIZE),
            ("GGX_E_OFFSET", ggx_tables.E_OFFSET), ("GGX_E_AVG_OFFSET", ggx_tables.E_AVG_OFFSET),
            ("GGX_S_OFFSET", ggx_tables.S_OFFSET)), kind="constants"),
        Family("light and shadow linking", "lights/linking.py", (
            ("LIGHT_FLAG_SHADOW_LINKED", linking.FLAG_SHADOW_LINKED), ("LINK_SHIFT", linking.LINK_SHIFT),
            ("LINK_OBJECT_MASK", (1 << linking.OBJECT_BITS) - 1), ("LINK_RECEIVER_SHIFT", linking.RECEIVER_SHIFT),
            ("LINK_BLOCKER_SHIFT", linking.BLOCKER_SHIFT), ("LINK_SET_MASK", linking.MAX_SETS - 1)),
               kind="constants"),
        Family("glass energy tables", "upload/glass_tables.py", (
            ("GLASS_SIZE", glass_tables.SIZE), ("GLASS_E_OFFSET", glass_tables.E_OFFSET),
            ("GLASS_E_INV_OFFSET", glass_tables.E_INV_OFFSET), ("GLASS_E_AVG_OFFSET", glass_tables.E_AVG_OFFSET),
            ("GLASS_E_INV_AVG_OFFSET", glass_tables.E_INV_AVG_OFFSET)), kind="constants"),
        Family("the Sobol sampler's bits of FrameParams.qmc", "render/qmc.py", (
            ("QMC_ON", qmc.ON), ("QMC_PIXEL_JITTER", qmc.PIXEL_JITTER)), kind="flags"),
    )


def c_literal(value: int | float) -> str:
    """The value as OpenCL C reads it: ints as they are (negative ones in brackets), floats as float literals that
    round to the same float32 as the Python value."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"a code must be an int or a float, got {value!r}")
    if isinstance(value, int):
        return f"({value})" if value < 0 else str(value)
    text = repr(float(value))
    if "e" not in text and "." not in text:
        text += ".0"
    return f"({text}f)" if value < 0 else f"{text}f"


def header(fams: Sequence[Family] | None = None) -> str:
    """The text of opencl/codes.h."""
    lines = ["/* GENERATED by `python -m restircl.upload.codes` from the Python tables named below: do not edit. The",
             " * integer codes and shared constants of the host/device line (python/restircl/upload/codes.py). */",
             "#ifndef RESTIRCL_CODES_H", "#define RESTIRCL_CODES_H", ""]
    for fam in fams if fams is not None else families():
        lines.append(f"/* {fam.title} ({fam.source}) */")
        width = max(len(n) for n, _ in fam.codes)
        lines += [f"#define {n.ljust(width)} {c_literal(v)}" for n, v in fam.codes]
        lines.append("")
    lines.append("#endif")
    return "\n".join(lines) + "\n"


def header_path() -> Path:
    return opencl_dir() / HEADER


def main(argv: Sequence[str] | None = None) -> int:
    return generated_main(argv, "restircl.upload.codes", __doc__ or "", HEADER, header)


def write_generated(path: Path, text: str, check: bool, command: str) -> int:
    """Write a generated header where it differs from `text` (0), or with `check` only say whether it is current
    (0) or not (1, naming the `command` that writes it)."""
    current = path.read_text() if path.exists() else None
    if check:
        if current != text:
            print(f"{path} is not current: run {command}", file=sys.stderr)
            return 1
        return 0
    if current != text:
        path.write_text(text)
        print(f"wrote {path}")
    return 0


def generated_main(argv: Sequence[str] | None, module: str, doc: str, header: str, text: Callable[[], str]) -> int:
    """The command line of the module `module` (docstring `doc`) that generates opencl/`header` from `text`:
    rewrite it, or with --check say whether it is current."""
    command = f"python -m {module}"
    ap = argparse.ArgumentParser(prog=command, description=doc.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 if the header differs from what the module gives")
    a = ap.parse_args(argv)
    return write_generated(opencl_dir() / header, text(), a.check, command)


if __name__ == "__main__":
    raise SystemExit(main())
