"""What a frame leaves to the next: G-buffers, ReSTIR reservoirs and TAA colour, each a pair of buffers (this frame
writes slot `cur` and reads last frame's slot `prev`), swapped once per frame in swap().

In glossy builds (HAS_GLOSSY) each G-buffer has its extension (GlossySample: the view direction and the resolved
specular lobes), kept and swapped with it; otherwise the extension is a 16-byte placeholder the kernels never read.

ReSTIR GI's reservoirs (animation and viewport frames only) are one pair beside the chains, at the active chain's
slot index, allocated by the first frame that runs ReSTIR GI; `gi_valid` says whether last frame's slot holds
reservoirs of the frame before this one.

A still ReSTIR render runs two chains of history, one per half buffer (render/still.py), so that the halves stay
independent: a Chain is one pair of G-buffers and reservoirs with its own slot index and validity. The TAA colour
follows the slot index of the active chain, and so does the TAA moments pair of the noise-aware blend (allocated by
the first frame that uses it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import pyopencl as cl

from ..core import layouts as L


@dataclass
class Chain:
    gbuf: list[cl.Buffer]
    reservoirs: list[cl.Buffer]
    glossy: list[cl.Buffer]
    cur: int = 0  # the slot this frame writes
    valid: bool = False  # whether slot 1 - cur holds a frame this one may reuse


class History:
    def __init__(self, alloc: Callable[[int], cl.Buffer], pixels: int, glossy: bool = False) -> None:
        self._alloc = alloc
        self.pixels = pixels
        self.glossy_bytes = pixels * L.GLOSSY_SAMPLE.itemsize if glossy else 16
        self.chains = [self._new_chain()]
        self.active = 0
        self.taa = [alloc(pixels * 16) for _ in range(2)]  # rgb: colour; w: history length n
        self._taa_moments: list[cl.Buffer] = []
        self._placeholder: cl.Buffer | None = None
        self._gi: list[cl.Buffer] = []
        self.gi_valid = False  # slot prev holds ReSTIR GI reservoirs of the last frame
        self._gi_kept = False  # this frame kept its ReSTIR GI reservoirs

    def _new_chain(self) -> Chain:
        n = self.pixels
        return Chain([self._alloc(n * L.GSAMPLE.itemsize) for _ in range(2)],
                     [self._alloc(n * L.RESERVOIR.itemsize) for _ in range(2)],
                     [self._alloc(self.glossy_bytes) for _ in range(2)])

    @property
    def chain(self) -> Chain:
        return self.chains[self.active]

    @property
    def cur(self) -> int:
        return self.chain.cur

    @property
    def prev(self) -> int:
        return 1 - self.chain.cur

    @property
    def valid(self) -> bool:
        return self.chain.valid

    def invalidate(self) -> None:
        self.chain.valid = False
        self.gi_valid = False

    def gbuf(self, slot: int) -> cl.Buffer:
        return self.chain.gbuf[slot]

    def glossy(self, slot: int) -> cl.Buffer:
        """The G-buffer extension of slot `slot` (a placeholder in diffuse-only builds)."""
        return self.chain.glossy[slot]

    def reservoirs(self, slot: int) -> cl.Buffer:
        return self.chain.reservoirs[slot]

    def keep_reservoirs(self, queue: cl.CommandQueue, res: cl.Buffer) -> None:
        """Make `res`, this frame's final reservoirs, the history the next frame reuses (a copy unless the last
        pass wrote it there already)."""
        if res is not self.reservoirs(self.cur):
            cl.enqueue_copy(queue, self.reservoirs(self.cur), res)

    def taa_moments(self, slot: int, used: bool) -> cl.Buffer:
        """TAA's moments history of slot `slot` (taa/blend_weight.h: float4 per pixel, allocated by the first frame
        that uses it, in step with the TAA colour), or, when not `used`, a 16-byte placeholder the kernel never
        reads."""
        if not used:
            if self._placeholder is None:
                self._placeholder = self._alloc(16)
            return self._placeholder
        if not self._taa_moments:
            self._taa_moments = [self._alloc(self.pixels * 16) for _ in range(2)]
        return self._taa_moments[slot]

    def gi_reservoirs(self, slot: int) -> cl.Buffer:
        """ReSTIR GI's reservoirs of slot `slot`."""
        if not self._gi:
            self._gi = [self._alloc(self.pixels * L.GI_RESERVOIR.itemsize) for _ in range(2)]
        return self._gi[slot]

    def keep_gi(self, queue: cl.CommandQueue, res: cl.Buffer) -> None:
        """Make `res`, this frame's final ReSTIR GI reservoirs, the history the next frame reuses."""
        if res is not self.gi_reservoirs(self.cur):
            cl.enqueue_copy(queue, self.gi_reservoirs(self.cur), res)
        self._gi_kept = True

    def swap(self) -> None:
        """End of a frame: it is now history, valid for the next one, whose slot is the other."""
        self.chain.valid = True
        self.gi_valid, self._gi_kept = self._gi_kept, False
        self.chain.cur = self.prev

    def use_chain(self, index: int, fresh: bool) -> None:
        """Continue on chain `index`; `fresh`: it starts without history, at the active chain's slot index."""
        if index == len(self.chains):
            self.chains.append(self._new_chain())  # allocated once, kept for later still renders
        if fresh:
            self.chains[index].cur = self.cur
            self.chains[index].valid = False
        self.active = index
        self.gi_valid = False
