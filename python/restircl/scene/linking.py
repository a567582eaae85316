"""Light linking and shadow linking of one emitter (a light, or a mesh whose material emits), as Blender 4.0+
describes them on the object (`object.light_linking.receiver_collection` / `blocker_collection`): the objects of
each collection with their link state, by mesh name.

Receivers: where the emitter's collection holds any INCLUDE entry, it lights only those objects; where it holds
EXCLUDE entries alone, it lights every object but them. Blockers, the same for the objects that cast its shadows.
An empty Linking (the default) lights every object and is shadowed by every one. lights/linking.py turns the links
of a scene into the light sets the device reads."""

from __future__ import annotations

from dataclasses import dataclass, field

from .errors import SceneError

LINK_STATES = ("INCLUDE", "EXCLUDE")


@dataclass
class Linking:
    receivers: dict[str, str] = field(default_factory=dict)  # mesh name -> INCLUDE | EXCLUDE
    blockers: dict[str, str] = field(default_factory=dict)  # mesh name -> INCLUDE | EXCLUDE

    @property
    def empty(self) -> bool:
        return not self.receivers and not self.blockers

    def validate(self, label: str) -> None:
        """Raise SceneError naming the emitter and the bad entry."""
        for kind in ("receivers", "blockers"):
            for name, state in getattr(self, kind).items():
                if state not in LINK_STATES:
                    raise SceneError(f"{label}: {kind} link state of {name!r} must be one of {LINK_STATES}, "
                                     f"got {state!r}")
