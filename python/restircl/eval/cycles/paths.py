"""The Light Paths of a comparison with Cycles (`restircl compare --max-bounces N`): the same bounces for our methods'
Settings and for every Cycles render (bridge.light_paths), and the tag that keeps their cached references apart.

Clamp Indirect and Light Threshold stay off and Min Light Bounces 0 on both sides (Settings' defaults; Cycles'
Light Paths default to a threshold of 0.01 and a clamp of 10, which bias the image): the comparison is of converged,
unbiased images. Max Bounces 0 is direct light only, the comparison as it was before bounces, with the same
Cycles settings and cache keys.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...settings.table import Settings

#: Cycles' defaults of the Diffuse and Glossy bounces (Light Paths > Max Bounces)
CYCLES_DIFFUSE = 4
CYCLES_GLOSSY = 4


@dataclass(frozen=True)
class LightPaths:
    max_bounces: int = 0
    diffuse_bounces: int = 0
    glossy_bounces: int = 0

    @classmethod
    def of(cls, max_bounces: int, diffuse: int | None = None, glossy: int | None = None) -> LightPaths:
        """Total bounces with the diffuse and glossy limits: Cycles' defaults when not given, never above the total
        (a limit above it changes nothing, and it would split one set of bounces over two cache keys)."""
        if max_bounces < 0 or (diffuse is not None and diffuse < 0) or (glossy is not None and glossy < 0):
            raise ValueError(f"bounces must be >= 0: {max_bounces}, {diffuse}, {glossy}")
        if max_bounces == 0:
            return cls()
        d = CYCLES_DIFFUSE if diffuse is None else diffuse
        g = CYCLES_GLOSSY if glossy is None else glossy
        return cls(max_bounces, min(d, max_bounces), min(g, max_bounces))

    @property
    def bounces(self) -> bool:
        return self.max_bounces > 0

    def overrides(self) -> dict:
        """Settings fields for our methods (none for direct light: the Settings stay as they were)."""
        if not self.bounces:
            return {}
        return {"max_bounces": self.max_bounces, "diffuse_bounces": self.diffuse_bounces,
                "glossy_bounces": self.glossy_bounces}

    def cycles(self) -> Settings | None:
        """What cycles.render takes as `paths`: None (direct light only) or Settings with these Light Paths."""
        return Settings(**self.overrides()).validate() if self.bounces else None

    @property
    def tag(self) -> str:
        """A part of file names and cache keys: empty for direct light (the keys of before), else _b<N>d<D>g<G>."""
        return f"_b{self.max_bounces}d{self.diffuse_bounces}g{self.glossy_bounces}" if self.bounces else ""

    def describe(self) -> str:
        if not self.bounces:
            return "direct light"
        return f"{self.max_bounces} bounces (diffuse {self.diffuse_bounces}, glossy {self.glossy_bounces})"


DIRECT = LightPaths()
