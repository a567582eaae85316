"""What the export of one material could not represent, gathered so that each kind is said once per material:
one warning for every lobe left out, one for every node type baked, and the other notes one by one."""

from __future__ import annotations

from collections.abc import Callable


class Notes:
    def __init__(self, material: str, warn: Callable[[str], None]):
        self.material = material
        self._warn = warn
        self.lobes: list[str] = []  # "coat (Principled BSDF)"
        self.baked: list[str] = []  # node type labels
        self.dropped: list[str] = []  # closures beyond MAX_LAYERS
        self.other: list[str] = []

    def note(self, msg: str) -> None:
        if msg not in self.other:
            self.other.append(msg)

    def lobe(self, what: str) -> None:
        if what not in self.lobes:
            self.lobes.append(what)

    def bake(self, label: str) -> None:
        if label not in self.baked:
            self.baked.append(label)

    def flush(self) -> None:
        m = f"material {self.material!r}"
        if self.lobes:
            self._warn(f"{m}: not supported and left out: {', '.join(self.lobes)}")
        if self.dropped:
            self._warn(f"{m}: more closures than the renderer mixes; left out: {', '.join(self.dropped)}")
        if self.baked:
            self._warn(f"{m}: baked to images (node types: {', '.join(self.baked)})")
        for msg in self.other:
            self._warn(f"{m}: {msg}")
