"""Frame policy: what one frame runs and reuses, decided from the settings and a small description of the frame's
situation, in one pure function (plan_frame) that touches no device, so that each decision can be tested with the
values a case should give (tests/render/test_plan.py).

The renderer (render/pipeline.py) uploads the scene at the frame, describes its situation (FrameSituation: which
frame follows which, the camera cut, the history's validity, the lights and materials, Sobol or random numbers,
still or animation), and runs what plan_frame returns (FramePlan): the sampler that runs, the history the frame may
reuse, where its light candidates come from (light tree, tiles, the still render's per-pixel pick table or the light
array), its BSDF candidates or BSDF MIS sample, and which of the optional stages run. The stages
(render/stages.py) read the plan; none of them decides anything about the frame.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..lights.pick_table import uses_table
from ..settings.table import BSDF_ANALYTIC_MAX, LIGHT_TILES_AUTO, Settings

#: the methods whose light candidates are resampled (RIS-based): the only ones with a light proposal and BSDF
#: candidates
RIS_METHODS = ("ris", "restir")


@dataclass(frozen=True)
class FrameSituation:
    """What the renderer knows about a frame before running it, after its scene was uploaded."""

    frame: int
    last_frame: int | None = None  # the frame rendered before this one (None: none since the history was reset)
    frame_count: int = 1  # of the scene's animation
    cut_at_frame: bool = False  # the camera cuts at `frame` (Camera.cuts)
    history_valid: bool = False  # the history's slot holds the last rendered frame (History.valid)
    lights_reindexed: bool = False  # the light count changed: last frame's reservoirs point at other lights
    lights_switched: bool = False  # a light switched on or off, or its power jumped (Settings.light_change_ratio)
    light_count: int = 1  # the lights the light array samples (the environment is one of them)
    environment: bool = False  # the world is a light
    glossy: bool = False  # some material has a specular lobe
    analytic_lights: int = 0  # lights that BSDF rays test one by one (lights/hit.py)
    triangle_lights: bool = False  # some light is an emissive triangle
    sobol: bool = False  # the frame draws from the Sobol sequence (FrameParams.qmc)
    light_tree: bool = False  # the renderer built a light tree for its candidates (lights/tree.py tree_proposal)
    path_light_tree: bool = False  # ... or for NEE at path vertices (lights/tree.py path_tree)
    pick_table: bool = False  # a still render whose build has the per-pixel pick table (lights/pick_table.py)
    still: bool = False  # a frame of a still render, averaged (else an animation or viewport frame)
    camera_moved: bool = False  # the camera sees from elsewhere than at the last frame (render/camera.py)
    scene_moves: bool = False  # objects or lights move between frames, or an interactive edit moved something
    gi_history_valid: bool = False  # the last frame left ReSTIR GI reservoirs (History.gi_valid)
    transmission: bool = False  # some material refracts (glass): ReSTIR GI does not reuse paths refracted at x0


@dataclass(frozen=True)
class FramePlan:
    """What a frame runs and reuses (plan_frame)."""

    frame: int
    prev_frame: int  # the frame whose history this one reuses (itself when there is none)
    next_frame: int  # the Vector pass's next frame
    drop_history: bool  # invalidate the history before the frame (its reservoirs point at other lights)
    history: bool  # last frame's G-buffer and TAA colour belong to this frame's predecessor
    restir_history: bool  # ... and its reservoirs sample this frame's lights
    method: str  # the sampler that runs: Settings.method, or light_array for RIS over one light
    light_tree: bool  # RIS candidates from the light tree
    tiles: bool  # RIS candidates from this frame's light tiles
    pick_table: bool  # RIS picks lights from the still render's per-pixel table
    bsdf_candidates: int  # BSDF-sampled candidates per pixel (direct/bsdf_candidates.h)
    mis_sample: bool  # RIS adds one BSDF sample combined by MIS (direct/bsdf_mis.h), in place of BSDF candidates
    bsdf_analytic: int  # the analytic lights BSDF rays test (0: none, or too many to test one by one)
    bsdf_triangles: bool  # BSDF rays look for emissive triangles
    bsdf_glossy_only: bool  # BSDF candidates only where the surface is glossy (bsdf_sampling "auto")
    temporal: bool  # 4 ReSTIR temporal reuse
    boiling: bool  # 4b the boiling filter
    spatial: bool  # 5 ReSTIR spatial reuse
    taa: bool  # 7 temporal accumulation
    taa_moving: bool  # ... which validates and clips its history
    filter: bool  # 8 the real-time filter of the TAA output
    paths: bool = False  # 6b the path pass: light that bounced (Settings.max_bounces > 0), where ReSTIR GI does not run
    path_light_tree: bool = False  # NEE at path vertices picks from the light tree (else the light array)
    path_analytic: int = 0  # the analytic lights path rays test (0: none, or too many to test one by one)
    path_triangles: bool = False  # path rays look for emissive triangles
    gi: bool = False  # 6b ReSTIR GI in place of the path pass: its initial samples (the paths) and shading
    gi_temporal: bool = False  # ... its temporal reuse
    gi_boiling: bool = False  # ... its boiling filter (biased: the animation path only, as ReSTIR DI's)
    gi_spatial: bool = False  # ... its spatial reuse
    texture_full: bool = False  # camera rays read images at full resolution (else the mip level of their ray cone)


def effective_method(settings: Settings, light_count: int, environment: bool, sobol: bool) -> str:
    """The sampler that runs. RIS over one light picks that light: the loop is left out (light_array), except for
    the environment, whose candidates are directions that RIS and the BSDF candidates choose between, and for Sobol
    frames (still or animation), whose points on the light only RIS's candidates draw from the sequence."""
    if settings.method == "ris" and light_count == 1 and not environment and not sobol:
        return "light_array"
    return settings.method


def uses_light_tiles(settings: Settings, method: str, light_count: int) -> bool:
    """RIS candidates from presampled tiles: only for the RIS-based methods over several lights, and ("auto") only
    where the light array is too large to stay in cache (LIGHT_TILES_AUTO lights), since the tiles cost a pass per
    frame."""
    mode = settings.light_tiles
    if method not in RIS_METHODS or light_count < 2 or mode == "off":
        return False
    return mode == "on" or light_count >= LIGHT_TILES_AUTO


def uses_mis_sample(settings: Settings, method: str, light_count: int) -> bool:
    """Whether `ris` frames add one BSDF sample with its own shadow ray, combined by MIS (direct/bsdf_mis.h); it
    replaces the BSDF candidates."""
    return settings.bsdf_mis_sample and method == "ris" and light_count > 0


def bsdf_candidate_count(settings: Settings, method: str, light_count: int, glossy: bool) -> int:
    """BSDF-sampled candidates per pixel (direct/bsdf_candidates.h): for the RIS-based methods, where a material is
    glossy ("auto") or always ("on")."""
    if method not in RIS_METHODS or light_count == 0 or settings.bsdf_sampling == "off":
        return 0
    if settings.bsdf_sampling == "auto" and not glossy:
        return 0
    return settings.bsdf_candidates


def light_source(settings: Settings, method: str, light_count: int, light_tree: bool,
                 pick_table: bool) -> tuple[bool, bool, bool]:
    """(light tree, tiles, pick table): where RIS's light candidates come from, at most one of them (none: the light
    array). The tree, where the renderer built one, takes precedence; then tiles; the per-pixel table is for still
    RIS frames of a few lights only (lights/pick_table.py uses_table)."""
    tree = light_tree and method in RIS_METHODS and light_count > 1
    tiles = not tree and uses_light_tiles(settings, method, light_count)
    table = (pick_table and not tree and not tiles
             and uses_table(settings.light_proposal, method, light_count, still=True))
    return tree, tiles, table


def stills_use_pick_table(settings: Settings, light_count: int, light_tree: bool) -> bool:
    """Whether still RIS renders of this scene may pick lights from the per-pixel table (compiled in: HAS_PICK_TABLE):
    `light_tree`, whether its RIS candidates come from the tree. Asked for RIS whatever settings.method is and
    whatever light tiles are set to: the frames of the other methods, and those of tiles, leave the table out at run
    time (light_source), so a scene's build is the same for every method and switching builds nothing."""
    return not light_tree and uses_table(settings.light_proposal, "ris", light_count, still=True)


def plan_frame(settings: Settings, situation: FrameSituation) -> FramePlan:
    """What the frame in `situation` runs and reuses with `settings`."""
    s, x = settings, situation
    # history: only across consecutive frames (or the same one again) without a cut, and only if the lights kept
    # their indices. A light switched on or off (or its power jumped) makes last frame's reservoirs samples of
    # another target: kept, they would dilute this frame's estimate for many frames; the decision depends on the
    # scene only, not on any sample, so dropping them keeps the unbiased mode unbiased. The TAA colour stays.
    cut = x.cut_at_frame and x.frame != x.last_frame
    consecutive = x.last_frame is not None and x.frame in (x.last_frame, x.last_frame + 1)
    history = x.history_valid and not x.lights_reindexed and consecutive and not cut
    restir_history = history and not x.lights_switched
    method = effective_method(s, x.light_count, x.environment, x.sobol)
    tree, tiles, table = light_source(s, method, x.light_count, x.light_tree, x.pick_table)
    mis_sample = uses_mis_sample(s, method, x.light_count)
    bsdf = 0 if mis_sample else bsdf_candidate_count(s, method, x.light_count, x.glossy)
    hit_tests = bool(bsdf) or mis_sample  # what BSDF rays look for: the candidates' or the MIS sample's
    restir = method == "restir"
    taa = s.taa and not x.still  # a still render averages its frames instead
    # TAA clips its history to the pixel's neighbourhood only where something moved: a still camera's animation
    # (frame numbers advancing, transforms equal) clipped every frame would keep a lasting bias (the stress case
    # long_animation came out 0.7% (ReSTIR) to 16% (light_array) too dark)
    return FramePlan(
        frame=x.frame, prev_frame=x.last_frame if history and x.last_frame is not None else x.frame,
        next_frame=min(x.frame + 1, x.frame_count - 1), drop_history=x.lights_reindexed, history=history,
        restir_history=restir_history, method=method, light_tree=tree, tiles=tiles, pick_table=table,
        bsdf_candidates=bsdf, mis_sample=mis_sample,
        bsdf_analytic=x.analytic_lights if hit_tests and x.analytic_lights <= BSDF_ANALYTIC_MAX else 0,
        bsdf_triangles=hit_tests and x.triangle_lights, bsdf_glossy_only=s.bsdf_sampling == "auto",
        temporal=restir and s.temporal and restir_history,
        boiling=restir and s.boiling_filter > 0 and not x.still,  # biased: the animation path only
        spatial=restir and s.spatial and s.spatial_neighbours > 0,
        taa=taa, taa_moving=taa and (x.scene_moves or (history and x.camera_moved)),
        filter=taa and s.realtime_filter, texture_full=texture_full(s, x.still), **path_plan(s, x, restir_history))


def texture_full(settings: Settings, still: bool) -> bool:
    """Whether camera rays read images at full resolution (textures/image.h level 0): a still's samples are
    averaged, and the average of shaded full-resolution samples is the pixel Cycles converges to, where shading a
    mip level's averaged normals or roughness is not; animation and viewport frames ("auto") read the mip level of
    their ray cone, whose prefiltered texels keep each frame's texture aliasing, and so TAA's flicker, down."""
    mode = settings.texture_filter
    return mode == "full" or (mode == "auto" and still)


def path_plan(settings: Settings, situation: FrameSituation, restir_history: bool) -> dict:
    """The bounced light's part of the plan: the path pass, or ReSTIR GI (animation and viewport frames with
    gi_reuse; still renders average independent paths), what its NEE picks from and what its rays look for. Its
    vertices are not pixels: no presampled tiles, no per-pixel table; the tree where the renderer built one. ReSTIR
    GI reuses last frame's reservoirs where ReSTIR may reuse its history (no cut, no light switched: a secondary
    sample's radiance was gathered under last frame's lights) and the last frame left some."""
    s, x = settings, situation
    bounces = s.max_bounces > 0
    # ReSTIR GI reconnects at the first bounce as if it were a reflection: a path refracted at the visible point
    # is not a sample it can reuse, so where a scene refracts the path pass runs beside it and shades the pixels
    # whose first surface transmits, ReSTIR GI the rest (PathParams / GIShadeParams split_glass)
    gi = bounces and s.gi_reuse and not x.still
    return {"paths": bounces and (not gi or x.transmission),
            "path_light_tree": x.path_light_tree and x.light_count > 1,
            "path_analytic": x.analytic_lights if x.analytic_lights <= BSDF_ANALYTIC_MAX else 0,
            "path_triangles": x.triangle_lights, "gi": gi,
            "gi_temporal": gi and s.gi_temporal and restir_history and x.gi_history_valid,
            "gi_boiling": gi and s.gi_boiling_filter > 0,
            "gi_spatial": gi and s.gi_spatial_neighbours > 0}
