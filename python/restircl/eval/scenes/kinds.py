"""Every scene kind `restircl compare` renders, by name: the tuning kinds (held_out.py, gi_tuning.py for global
illumination), the validation kinds of global illumination (validation.py), of direct light
(validation_direct.py) and a typical user's F12 (user_scene.py: built in Blender and exported by the add-on), the
glass table of issue 39 (glass.py) and its lights inside glass globes (glass_globe.py)."""

from __future__ import annotations

from ...scene.scene import Scene
from . import gi_tuning, glass, glass_globe, held_out, user_scene, validation, validation_direct

KINDS = held_out.KINDS + validation.KINDS + validation_direct.KINDS + gi_tuning.KINDS + glass.KINDS + user_scene.KINDS
KINDS += glass_globe.KINDS


def scene_of_kind(kind: str, width: int = held_out.WIDTH, height: int = held_out.HEIGHT) -> Scene:
    """The tuning or validation scene of `kind` at width x height."""
    if kind in held_out.KINDS:
        return held_out.held_out(kind, width, height)
    if kind in validation.KINDS:
        return validation.validation(kind, width, height)
    if kind in gi_tuning.KINDS:
        return gi_tuning.gi_tuning(kind, width, height)
    if kind in validation_direct.KINDS:
        return validation_direct.validation_direct(kind, width, height)
    if kind in glass.KINDS:
        return glass.glass_table(width, height)
    if kind in user_scene.KINDS:
        return user_scene.user_scene(width, height)[0]
    if kind in glass_globe.KINDS:
        return glass_globe.glass_globe(kind, width, height)
    raise ValueError(f"no scene kind {kind!r}; kinds: {', '.join(KINDS)}")
