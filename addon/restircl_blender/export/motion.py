"""Per-frame transform sampling.

Geometry is read once, at the current frame; the other frames asked for only move the depsgraph there and
record each instance's matrix (and a light's power). A track is one value per sampled frame, None where the
instance was not seen; gaps are filled from the nearest earlier (else later) frame at the end."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .report import ExportError


@dataclass(frozen=True)
class Frames:
    """The Blender frames sampled, in order, and the current one (where geometry is read)."""

    numbers: list[int]
    current: int

    @classmethod
    def choose(cls, frames: Sequence[int] | None, current: int, can_move: bool) -> Frames:
        numbers = [current] if not frames else sorted({int(f) for f in frames})
        if current not in numbers:
            raise ExportError(f"export_scene: the current frame {current} is not among the frames {numbers}")
        if len(numbers) > 1 and not can_move:
            raise ExportError("export_scene: frame_set is needed to sample more than one frame")
        return cls(numbers, current)

    @property
    def count(self) -> int:
        return len(self.numbers)

    @property
    def current_index(self) -> int:
        return self.numbers.index(self.current)

    def track(self, value, fill=None) -> list:
        """A new track holding `value` at the current frame and `fill` elsewhere."""
        seq = [fill] * self.count
        seq[self.current_index] = value
        return seq

    def visit_others(self, frame_set: Callable[[int], None] | None, visit: Callable[[int], None]) -> None:
        """Move to every other frame and call visit(index) there; the depsgraph ends at the current frame."""
        if self.count == 1 or frame_set is None:  # (choose() allows no frame_set only for one frame)
            return
        try:
            for k, f in enumerate(self.numbers):
                if f != self.current:
                    frame_set(f)
                    visit(k)
        finally:
            frame_set(self.current)


def instance_key(inst) -> tuple:
    """What identifies an object instance from one frame to the next."""
    ob = inst.object
    parent = inst.parent.original.name if inst.is_instance and inst.parent is not None else ""
    return (ob.original.name if ob.original is not None else ob.name, parent,
            tuple(inst.persistent_id) if inst.is_instance else ())


def fill_gaps(seq: list) -> None:
    """Frames where an object was absent take the nearest earlier (else later) frame's value."""
    known = [i for i, v in enumerate(seq) if v is not None]
    for i in range(len(seq)):
        if seq[i] is None:
            earlier = [j for j in known if j < i]
            seq[i] = seq[earlier[-1] if earlier else known[0]]


def transforms(mats: list[np.ndarray]) -> np.ndarray:
    """One matrix for a track that does not move, else (F, 4, 4)."""
    first = mats[0]
    if all(np.array_equal(m, first, equal_nan=True) for m in mats[1:]):
        return first
    return np.stack(mats)
