"""How an animation is cut for many machines: contiguous chunks of frames, each preceded by warm-up frames.

ReSTIR's temporal reuse and TAA make a frame depend on the ones before it, so a chunk that started cold would show
a seam: its first frame has no history. Each chunk therefore renders `warmup` frames before its first one and
discards them. The cut does not change the noise of a frame: every frame's random stream is keyed by its frame
number (Renderer.render_frame's `sample`), not by its place in the chunk.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

from ..settings.spec import Range


@dataclass(frozen=True)
class FrameRange:
    """Frames first..last, both included."""

    first: int
    last: int

    @property
    def count(self) -> int:
        return self.last - self.first + 1

    def frames(self) -> range:
        return range(self.first, self.last + 1)


def parse_frames(text: str) -> int | FrameRange:
    """An argparse type: 'N' (a count, frames 0..N-1, or samples of a still) or 'A-B' (frames A to B)."""
    first, dash, last = text.partition("-")
    if not dash or not first:  # a count, or a negative number: the count's own message
        return int(Range(int, 1).parse(text))
    try:
        a, b = int(first), int(last)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a count N or a frame range A-B") from None
    if b < a:
        raise argparse.ArgumentTypeError(f"{text} is out of range: a frame range A-B needs A <= B")
    return FrameRange(a, b)


@dataclass(frozen=True)
class Chunk:
    """Frames first..last are kept; frames start..first-1 are warm-up, rendered and discarded. `warmup` and
    `earliest` (the animation's first frame) are what the warm-up was cut from."""

    index: int
    start: int
    first: int
    last: int
    warmup: int = 0
    earliest: int = 0

    @property
    def kept(self) -> range:
        return range(self.first, self.last + 1)

    @property
    def rendered(self) -> range:
        return range(self.start, self.last + 1)

    def resumed(self, done: set[int]) -> Chunk | None:
        """What is left of this chunk when the frames in `done` are written: from its first missing frame (with a
        warm-up of its own before it) to its end, or None when nothing is missing. A written frame after the first
        missing one is rendered again (as history) but not written again."""
        missing = [f for f in self.kept if f not in done]
        if not missing:
            return None
        return _chunk(self.index, missing[0], self.last, self.warmup, self.earliest)


def _chunk(index: int, first: int, last: int, warmup: int, earliest: int) -> Chunk:
    return Chunk(index, max(first - warmup, earliest), first, last, warmup, earliest)


def plan_chunks(frames: FrameRange, chunk_size: int, warmup: int, earliest: int = 0) -> list[Chunk]:
    """Cut `frames` into chunks of `chunk_size` (the last one may be shorter), each with up to `warmup` frames before
    it, but none before `earliest` (the animation's first frame)."""
    if chunk_size < 1 or warmup < 0:
        raise ValueError(f"chunk size {chunk_size} and warm-up {warmup}: need a size >= 1 and a warm-up >= 0")
    if frames.first < earliest:
        raise ValueError(f"frame {frames.first} is before the animation's first frame {earliest}")
    starts = range(frames.first, frames.last + 1, chunk_size)
    return [_chunk(i, f, min(f + chunk_size - 1, frames.last), warmup, earliest) for i, f in enumerate(starts)]


def default_chunk_size(frames: FrameRange, workers: int) -> int:
    """One contiguous chunk per worker: the fewest warm-up frames (a dead worker's chunk is re-run from its first
    missing frame, so a long chunk loses little)."""
    return max(1, math.ceil(frames.count / max(workers, 1)))
