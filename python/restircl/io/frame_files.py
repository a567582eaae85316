"""The files of an animation frame (EXR with AOVs + PNG preview, `NAME_0042.exr`), written so that a reader or a
re-run never sees half of one: each file is written under a temporary name in the same folder and renamed into
place (a rename within a folder is atomic on POSIX and on Windows' NTFS). A frame counts as written when both of
its files exist; the PNG is renamed last."""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterable
from pathlib import Path

from ..render.frame import Frame
from .images import write_exr, write_png


def frame_stem(name: str, frame: int) -> str:
    return f"{name}_{frame:04d}"


def frame_paths(out: Path, name: str, frame: int) -> tuple[Path, Path]:
    stem = frame_stem(name, frame)
    return out / f"{stem}.exr", out / f"{stem}.png"


def written_frames(out: Path, name: str, frames: Iterable[int]) -> set[int]:
    """The frames among `frames` whose EXR and PNG are both in `out`."""
    return {f for f in frames if all(p.exists() for p in frame_paths(out, name, f))}


def write_frame(out: Path, name: str, number: int, frame: Frame) -> tuple[Path, Path]:
    """Write frame `number` atomically: EXR, then PNG."""
    out.mkdir(parents=True, exist_ok=True)
    exr, png = frame_paths(out, name, number)
    _atomic(exr, lambda tmp: write_exr(tmp, frame))
    _atomic(png, lambda tmp: write_png(tmp, frame))
    return exr, png


def _atomic(path: Path, write) -> None:
    # the temporary name keeps the suffix (Pillow picks the format from it) and names the writer, so that two
    # workers that render the same frame (a chunk re-run while its first worker still finishes) never share one
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp{path.suffix}")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
