"""The estimator of a still render (Settings.still_method): what F12 and `restircl render` of a still camera use.

ReSTIR's reuse is built for animation: temporal reuse carries a pixel's samples from frame to frame and spatial
reuse shares them between neighbours, so a frame is worth more than an independent one while the camera moves.
Accumulated over the frames of a still camera, the same reuse makes consecutive frames correlated and the mean
converges slower than the mean of independent frames. Measured on the tuning scenes
(docs/measurements/error-vs-time.md, "The estimator of a still"), RULE below picks what converged fastest per
second. Animations and the viewport keep Settings.method as it is; only the entry points of a still render (the
CLI's still mode, the add-on's F12) call still_settings, and Renderer.render_still renders with the settings it was
given.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..environment.sun import is_sunny
from ..scene.scene import Scene
from ..settings.table import Settings

#: what each explicit choice changes in the settings
OVERRIDES: dict[str, dict] = {
    "ris": {"method": "ris"},
    "restir_spatial": {"method": "restir", "temporal": False},
}

#: `auto`'s choice per scene kind (scene_kind), from the measurements in docs/measurements/error-vs-time.md, "The
#: estimator of a still": independent RIS frames converged fastest on every kind; on emissive meshes (neon) BSDF-sampled
#: candidates cut RIS's relMSE x CPU seconds by 40 %, on light objects (studio, garden) they cost more than they gave.
#: (Spatial-only ReSTIR with BSDF candidates was as good as RIS with them on neon, within the noise of the runs,
#: and worse elsewhere: the rule keeps one method, whose frames are independent.)
RULE: dict[str, dict] = {
    "analytic_lights": {"method": "ris"},
    "mesh_lights": {"method": "ris", "bsdf_sampling": "on"},
}
#: what `auto` adds where the world has a sun (environment/sun.py): the BSDF MIS sample (opencl/direct/bsdf_mis.h),
#: which replaces the BSDF candidates, measured on the tuning sky (docs/measurements/error-vs-time.md, "The sky's
#: sun"): relMSE x seconds 3.4-4x below RIS's; with it 4 light candidates did better per second than the default 8
#: (2 and 4 were even within the noise), so auto lowers the candidates to SUNNY_CANDIDATES where they are at their
#: default
SUNNY = {"bsdf_mis_sample": True}
SUNNY_CANDIDATES = 4


def scene_kind(scene: Scene) -> str:
    """The kind of scene RULE tells apart, from what the host knows before rendering: whether any triangle emits
    (mesh lights, which BSDF-sampled directions hit) or every emitter is a light object."""
    emissive = {i for i, m in enumerate(scene.materials) if m.is_emissive}
    if emissive and any(np.isin(mesh.material_ids, list(emissive)).any() for mesh in scene.meshes):
        return "mesh_lights"
    return "analytic_lights"


#: with the Sobol sampler (render/qmc.py), scenes of at most this many light objects and no emissive triangles render
#: their stills with FEW_LIGHTS_CANDIDATES light candidates: the fewer candidates a frame has, the more of its
#: error the stratified dimension pairs remove, and the frames are cheaper (docs/measurements/error-vs-time.md,
#: "Sobol sampler"). Under a sunny world SUNNY_CANDIDATES applies instead (measured with the BSDF MIS sample),
#: unless the world is alone.
FEW_LIGHTS = 16
FEW_LIGHTS_CANDIDATES = 2
#: a single light object and no world: RIS over one candidate, i.e. one Sobol-drawn point on the light (with 2,
#: relMSE at 64 frames of cornell_box was 1.8x that of one candidate, in more time per frame:
#: docs/measurements/error-vs-time.md, "One light"). The same for a world that is the only light (with a sun, beside
#: its BSDF MIS sample): one point drawn by inverting the world's cumulative table (qmc.environment_table) keeps the
#: Sobol strata that resampling scatters; on the tuning sky 0.74x the relMSE of 4 candidates at equal frames in
#: 0.6x the CPU time, without its sun 0.38x that of 2 candidates from the alias table in 0.7x the time
#: (docs/measurements/error-vs-time.md, "A world alone: one candidate")
ONE_LIGHT_CANDIDATES = 1
#: with bounces (Max Bounces > 0) the few-lights and sunny rules take this many light candidates instead where there
#: are at most FEW_LIGHTS light objects: the camera vertex's direct light is then a small part of a frame's variance
#: beside the bounced light's, and each candidate past the first adds time, not accuracy where it counts
#: (docs/measurements/error-vs-time.md, "Light candidates with bounces"): at 64 frames, Max Bounces 4, relMSE x CPU s
#: of 1 against 2 and 4 candidates on the tuning studio 0.92x / 0.76x, on the tuning sky (its world alone, forced
#: counts) 0.72x / 0.54x. On the validation `user` (43 lamps under a sunny world) 1 against 4 was level per CPU
#: second and 7 % worse per frame, so many lamps keep theirs.
BOUNCED_CANDIDATES = 1


def single_emitter(scene: Scene) -> bool:
    """One light object and no world, or the world and no light object (emissive triangles aside: scene_kind)."""
    return len(scene.lights) == (0 if scene.environment is not None else 1)


def auto_overrides(scene: Scene, settings: Settings) -> dict:
    """What `auto` changes in `settings` (whose Method is ReSTIR) for a still of `scene`. A BSDF sampling switched
    off by the user stays off (and so does the BSDF MIS sample of a sunny world)."""
    kind = scene_kind(scene)
    over = dict(RULE[kind])
    default_candidates = settings.candidates == Settings.candidates  # a user's own count is kept
    one = False  # one Sobol-drawn candidate on the only emitter
    if (kind == "analytic_lights" and len(scene.lights) <= FEW_LIGHTS and settings.sampler != "random"
            and default_candidates):
        one = single_emitter(scene)
        over["candidates"] = ONE_LIGHT_CANDIDATES if one else FEW_LIGHTS_CANDIDATES
    if settings.bsdf_sampling == "off":
        over.pop("bsdf_sampling", None)
    elif is_sunny(scene.environment):
        over.update(SUNNY)
        if default_candidates and not one:
            over["candidates"] = SUNNY_CANDIDATES
    if (settings.max_bounces > 0 and settings.sampler != "random" and "candidates" in over
            and len(scene.lights) <= FEW_LIGHTS):
        over["candidates"] = min(over["candidates"], BOUNCED_CANDIDATES)
    return over


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
        return replace(settings, **auto_overrides(scene, settings)).validate()
    return replace(settings, **OVERRIDES[choice]).validate()


def describe_still(settings: Settings, resolved: Settings) -> str:
    """One line for a log: the still estimator and how it was chosen."""
    how = "as set" if resolved == settings else f"still_method {settings.still_method}"
    parts = [resolved.method]
    if resolved.method == "restir":
        reuse = [n for n, on in (("temporal", resolved.temporal), ("spatial", resolved.spatial)) if on]
        parts.append(f"({', '.join(reuse) or 'no'} reuse)")
    if resolved.method == "ris" and resolved.bsdf_mis_sample:
        parts.append(f"{resolved.candidates} candidates, BSDF MIS sample")
    elif resolved.method in ("ris", "restir"):
        parts.append(f"BSDF sampling {resolved.bsdf_sampling}")
    return f"still method: {' '.join(parts)}, {how}"
