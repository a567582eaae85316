"""Side programs: kernels built in a program of their own, with only the defines their code reads.

PoCL compiles a kernel at its first launch in each program, and the renderer's program (opencl/restircl.cl) is built
once per set of feature flags: a kernel that reads few of the flags was compiled again in every variant. A side
program holds such a kernel (or a few that read the same flags) and is built with the defines of `reads` alone (of
the feature flags and of the host's: the settings table's array limits, the BVH layout and a test's or probe's
defines), so that variants differing only in other flags share it, in this process's program cache and in PoCL's
disk cache (both keyed by the options and the text).

A define missing here would be dropped silently, so tests/core/test_side_programs.py checks each entry against the
preprocessor (`cpp`): for many define sets, the side program's text with every define equals its text with the
defines `defines()` keeps, and its kernels' code equals the main program's (the functions, types and constants they
reach).

A side program pays only where it saves many compiles: its build parses its headers again (measured cold: about
0.3-0.45 CPU s for TAA's, 1 s for the primary pass's) while a kernel's compile at its first launch took 0.35-0.5 s
(docs/measurements/benchmarks.md, "Test suite time", side programs). TAA was in 64 programs of a cold suite run and
needs 11 side programs; the primary pass was in 195 and would need 66, each costing about what the two compiles it
saves did (and every cold first image would pay it): it stays in the main program.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

Defines = Mapping[str, int | float | bool | str | None]

# bsdf/: the test hooks of the dielectric and thin lobes (tests/bias_controls.py)
LOBE_HOOKS = (
    "DIELECTRIC_WITHOUT_FRESNEL_IN_REFRACTION",
    "TEST_DIELECTRIC_REFLECT_PDF_SCALE",
    "TEST_THIN_TRANSMISSION_PDF_SCALE",
)


@dataclass(frozen=True)
class SideProgram:
    """source: its file under opencl/; kernels: the kernels it has (the main program leaves them out); reads: the
    defines its text depends on."""

    source: str
    kernels: tuple[str, ...]
    reads: tuple[str, ...]

    def defines(self, defines: Defines) -> dict[str, int | float | bool | str]:
        """The defines (feature flags and the host's) this program is built with: those it reads."""
        return {n: v for n, v in defines.items() if n in self.reads and v is not None and v is not False}


# Temporal accumulation (opencl/taa/): the surface and material tests of its history
TAA = SideProgram(
    source="taa/taa_program.cl",
    kernels=("taa",),
    reads=(
        "HAS_GLOSSY",
        "HAS_LIGHT_LINKING",
        "HAS_TEXTURES",
        "HAS_THIN_FILM",
        "HAS_TRANSMISSION",
        "HAS_TRANSPARENCY",
        "MAX_TEX_PROGRAM",
        *LOBE_HOOKS,
        "PROBE_PERMUTATION_FALLBACK",
        "PROBE_PERMUTATION_ONE_TRY",
        "RESTIR_GLOSSY_CAP",
        "TAA_CLIP_RADIUS",
        "TAA_FRESH_FILL_ROBUST",
        "TAA_GLOSSY_ALPHA",
        "TAA_GLOSSY_GAMMA",
        "TAA_SWEEP_MIN",
        "TAA_SWEEP_RADIUS",
        "VIEW_DEPENDENCE_OFF",
        "GLASS_KEEPS_HISTORY",
    ),
)

SIDE_PROGRAMS: tuple[SideProgram, ...] = (TAA,)
