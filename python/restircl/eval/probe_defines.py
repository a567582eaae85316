"""Extra -D options for every kernel build, for probes and tests: a test hook or a probe's variant is an `#ifdef` block
in opencl/ that ordinary builds compile out, switched on here for the programs built afterwards (the negative controls
of tests/bias_controls.py, `--define` of tools/experiments/restir_motion.py and level_probe.py).

The defines join the settings table's own (core/program.py reads `kernel_defines` at every build), so they reach
every program of the process, the renderer's and a test's own kernels alike, and a program built with them is cached
apart from one built without. With the builtin setattr this is process-wide state, the one exception to the house's
"no global state beyond the cached OpenCL context": it is for a probe's own process (a CLI run), never for the
renderer, the add-on or a library user; tests pass their monkeypatch's setattr so it goes with the test."""

from __future__ import annotations

from collections.abc import Callable, Iterable

from ..core import program

#: sets an attribute: the builtin setattr for the rest of the process, a pytest monkeypatch's setattr for one test
Patch = Callable[[object, str, object], None]


def parse_defines(defines: Iterable[str]) -> dict[str, str | bool]:
    """`NAME=VALUE` or `NAME` options as a define dict; a bare NAME is True (-DNAME=1, what -DNAME means too)."""
    out: dict[str, str | bool] = {}
    for d in defines:
        name, eq, value = d.partition("=")
        if not name or not name.replace("_", "a").isalnum() or name[0].isdigit():
            raise ValueError(f"not a define: {d!r} (NAME or NAME=VALUE)")
        out[name] = value if eq else True
    return out


def add_probe_defines(defines: Iterable[str], patch: Patch = setattr) -> None:
    """Build every program made after this call with `defines` (NAME or NAME=VALUE) besides the settings' own; one
    of the same name replaces the setting's. `patch` installs it (see Patch); calls add up."""
    extra = parse_defines(defines)
    base = program.kernel_defines
    patch(program, "kernel_defines", lambda: {**base(), **extra})
