"""The estimator of a still render (Settings.still_method): what F12 and `restircl render` of a still camera use.

ReSTIR's reuse is built for animation: temporal reuse carries a pixel's samples from frame to frame and spatial
reuse shares them between neighbours, so a frame is worth more than an independent one while the camera moves.
Accumulated over the frames of a still camera, the same reuse makes consecutive frames correlated and the mean
converges slower than the mean of independent frames. Measured on the held-out scenes (docs/error-vs-time.md, "The
estimator of a still"), RULE below picks what converged fastest per second. Animations and the viewport keep
Settings.method as it is; only the entry points of a still render (the CLI's still mode, the add-on's F12) call
still_settings, and Renderer.render_still renders with the settings it was given.
"""

from __future__ import annotations

from dataclasses import replace

from .scene import Scene
from .settings import Settings

#: what each explicit choice changes in the settings
OVERRIDES: dict[str, dict] = {
    "ris": {"method": "ris"},
    "restir_spatial": {"method": "restir", "temporal": False},
}


def scene_kind(scene: Scene) -> str:
    """The kind of scene the rule tells apart, from what the host knows before any rendering."""
    del scene
    return "any"


def auto_choice(scene: Scene) -> str:
    """The still estimator `auto` picks for a scene whose Method is ReSTIR (see the module docstring)."""
    del scene
    return "ris"


def still_settings(settings: Settings, scene: Scene) -> Settings:
    """The settings with which to render a still image of `scene`: `settings` with the estimator that
    `settings.still_method` selects. `auto` changes ReSTIR only: the methods without reuse (uniform, light_array,
    ris, reference) already give independent frames and are used as set."""
    choice = settings.still_method
    if choice == "as_set":
        return settings
    if choice == "auto":
        if settings.method != "restir":
            return settings
        choice = auto_choice(scene)
    return replace(settings, **OVERRIDES[choice]).validate()


def describe_still(settings: Settings, resolved: Settings) -> str:
    """One line for a log: the still estimator and why."""
    how = "as set" if settings.still_method == "as_set" or resolved == settings else settings.still_method
    reuse = ""
    if resolved.method == "restir":
        reuse = " (" + ", ".join(n for n, on in (("temporal", resolved.temporal), ("spatial", resolved.spatial))
                                 if on) + " reuse)"
    return f"still method: {resolved.method}{reuse}, {how}"
