"""The program's source with its `#include "..."` files written in place, so that no include path reaches the
OpenCL compiler.

An include path is a build option, and drivers split build options at spaces: PoCL takes neither a path with a
space nor a quoted one, and the extensions folder has spaces on Windows ("...\\Blender Foundation\\Blender\\...") and
macOS (".../Application Support/Blender/..."). The compiler sees the same text its preprocessor would have made:
every include is written out where it stands (the headers' own guards drop repeats, also inside a false `#if`),
and `#line` directives keep the file names and line numbers of its messages.
"""

from __future__ import annotations

import re
from pathlib import Path

_INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*"([^"]+)"(.*)$')
MAX_DEPTH = 64  # deeper is an include cycle without a guard


def inline_includes(text: str, name: str, root: Path) -> str:
    """`text` (the file `name`, relative to `root`) with each quoted include replaced by the file's text, found
    as the preprocessor finds it: beside the including file first, then under `root`. An include not found stays
    as it is, for the compiler to report."""
    return _expand(text, name, root, root, 0)


def _expand(text: str, name: str, here: Path, root: Path, depth: int) -> str:
    if depth > MAX_DEPTH:
        raise RecursionError(f"{name}: includes nested deeper than {MAX_DEPTH} (a cycle without a guard?)")
    out: list[str] = []
    for number, line in enumerate(text.split("\n"), 1):
        m = _INCLUDE.match(line)
        path = _find(m.group(1), here, root) if m else None
        if path is None:
            out.append(line)
            continue
        rel = path.relative_to(root).as_posix() if path.is_relative_to(root) else path.name
        out.append(f'#line 1 "{rel}"')
        out.append(_expand(path.read_text(), rel, path.parent, root, depth + 1))
        tail = m.group(2).strip()  # a comment after the include (it may go on over the next lines)
        out.append(f'#line {number} "{name}"\n{tail}' if tail else f'#line {number + 1} "{name}"')
    return "\n".join(out)


def _find(include: str, here: Path, root: Path) -> Path | None:
    for base in (here, root):
        path = base / include
        if path.is_file():
            return path
    return None
