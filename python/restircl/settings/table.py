"""The settings table: every parameter of a render, declared once as a field of `Settings` (settings/spec.py says
how). `validate()`, the command line (cli/main.py), the add-on's panels and the kernels' -D limits all read it."""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..core import layouts as L
from .spec import Choice, Range, SettingError, check, declared, setting

METHOD_CHOICES = (
    Choice("uniform", "Uniform", "One light picked uniformly", 3),
    Choice("light_array", "Light Array", "One light picked from the power-proportional light array", 2),
    Choice("ris", "RIS", "Resampled importance sampling over light-array candidates, no reuse", 1),
    Choice("restir", "ReSTIR", "Reservoir resampling with temporal and spatial reuse", 0),
    Choice("reference", "Reference", "Every light, one sample each: exhaustive, for ground truth (slow)", 4),
)
METHODS = tuple(c.id for c in METHOD_CHOICES)
# in the order of the kernels' BIAS_* codes (index = code)
BIAS_CHOICES = (
    Choice("none", "None (biased)", "M-weighted merge, no shadow rays: faster, darkens at contact shadows", 2),
    Choice("z_count", "1/Z (unbiased)", "Divide by the number of reservoirs whose sample could have produced this "
           "pixel's sample", 1),
    Choice("pairwise", "Pairwise MIS (unbiased)", "Weigh each neighbour's sample against this pixel's by their "
           "targets (balance heuristic in pairs): unbiased and robust next to small or touching lights", 0),
)
BIAS_CORRECTIONS = tuple(c.id for c in BIAS_CHOICES)
#: light count from which light_tiles="auto" draws RIS candidates from presampled tiles: measured on the 2-core VM
#: (docs/measurements/benchmarks.md), tiles cost 2 % of a ReSTIR frame at 1e4 point lights and saved 5 % at 3e4 and
#: a quarter at 1e6
LIGHT_TILES_AUTO = 20000
LIGHT_TILE_CHOICES = (
    Choice("auto", "Auto", f"Presampled light tiles from {LIGHT_TILES_AUTO:,} lights on, where the lights no longer "
           "fit the CPU cache", 0),
    Choice("on", "On", "Draw the RIS candidates from presampled light tiles", 1),
    Choice("off", "Off", "Draw the RIS candidates from the whole light array", 2),
)
LIGHT_TILES = tuple(c.id for c in LIGHT_TILE_CHOICES)
#: the one-sample methods of the direct pass (opencl/direct/direct.cl), by their device code (METHOD_*)
SHADE_METHODS = ("uniform", "light_array", "ris")
TAA_FILTER_CHOICES = (
    Choice("bilinear", "Bilinear", "History fetched from the 2x2 taps around its reprojected position", 0),
    Choice("catmull_rom", "Catmull-Rom", "History fetched with a 4x4 Catmull-Rom filter: sharper under motion "
           "(bilinear where a tap shows another surface)", 1),
)
TAA_FILTERS = tuple(c.id for c in TAA_FILTER_CHOICES)
# in the order of restir/boiling.cl's mode codes (index = code)
BOILING_MODE_CHOICES = (
    Choice("weight", "Weight", "Empty a reservoir whose weight W stands far above its tile's (RTXDI's)", 0),
    Choice("contribution", "Contribution", "Empty a reservoir whose contribution (target x W, what it adds to its "
           "pixel) stands far above its tile's", 1),
    Choice("forget", "Forget", "A reservoir whose contribution stands far above its tile's keeps its sample and "
           "weight but its M drops to 1, so that spatial and temporal reuse weigh it as one candidate and let it go",
           2),
)
BOILING_MODES = tuple(c.id for c in BOILING_MODE_CHOICES)

PATH_LIGHT_PICK_CHOICES = (
    Choice("auto", "Auto", "The light tree wherever the scene has two lights or more (render/plan.py "
           "path_tree_pays), else the light array", 0),
    Choice("array", "Light Array", "Every path vertex picks its light from the power-proportional light array", 1),
    Choice("tree", "Light Tree", "Every path vertex picks its light from the light tree: by power, distance and "
           "orientation (a spot's cone, an area light's side) at the vertex", 2),
)

LIGHT_PROPOSAL_CHOICES = (
    Choice("auto", "Auto", "Still RIS renders of at most 64 lights: the per-pixel table (it measured better than "
           "the light array at equal time there); else the light tree where it measured better than the light "
           "array (so far nowhere on the CPU), else the light array", 0),
    Choice("array", "Light Array", "Candidates from the power-proportional light array (O(1) per candidate)", 1),
    Choice("tree", "Light Tree", "Candidates from the light tree: picked by power, distance and orientation at each "
           "shading point (a descent per candidate)", 2),
    Choice("pixel", "Per-Pixel Table", "Still RIS renders of at most 64 lights: candidates picked by each pixel's own "
           "probabilities, from every light's unshadowed contribution estimated once per render; else the light "
           "array", 3),
)
BSDF_SAMPLING_CHOICES = (
    Choice("auto", "Auto", "BSDF-sampled candidates at the pixels whose material has a specular lobe", 0),
    Choice("on", "On", "BSDF-sampled candidates for every scene (also diffuse ones, e.g. with large or mesh lights)",
           1),
    Choice("off", "Off", "Light candidates only", 2),
)
STILL_METHOD_CHOICES = (
    Choice("auto", "Auto", "Still renders replace ReSTIR's reuse, which converges slower on a still camera, by the "
           "estimator that converged fastest per second on stills of the scene's kind (render/still_method.py); the "
           "methods without reuse are used as set", 0),
    Choice("as_set", "As Set", "Still renders use the Method and reuse settings as they are, like an animation", 1),
    Choice("ris", "RIS", "Still renders use independent RIS frames (candidates and BSDF sampling as set)", 2),
    Choice("restir_spatial", "ReSTIR, Spatial Only", "Still renders use ReSTIR with fresh reservoirs every frame and "
           "spatial reuse only", 3),
)
STILL_METHODS = tuple(c.id for c in STILL_METHOD_CHOICES)
SAMPLER_CHOICES = (
    Choice("auto", "Auto", "Scrambled Sobol numbers for still RIS renders (F12), random numbers for animation "
           "frames, the viewport and ReSTIR", 0),
    Choice("random", "Random", "Independent random numbers everywhere", 1),
    Choice("sobol", "Sobol", "Scrambled Sobol numbers for every RIS frame (stills, animation and viewport); "
           "ReSTIR keeps random numbers", 2),
)
AREA_SAMPLING_CHOICES = (
    Choice("auto", "Auto", "Solid angle where an area light looks large from the shaded point, area elsewhere", 0),
    Choice("solid_angle", "Solid Angle", "Area lights, emissive triangles and soft point lights sampled uniformly "
           "in the solid angle they subtend (where float32 allows)", 1),
    Choice("area", "Area", "Area lights and emissive triangles sampled uniformly in area, except within twice their "
           "radius (there in solid angle, as uniform area sampling would give fireflies next to a light)", 2),
)
TEXTURE_FILTER_CHOICES = (
    Choice("auto", "Auto", "Still renders (F12) read images at full resolution, as Cycles does; animation and "
           "viewport frames filter them over the pixel's ray cone", 0),
    Choice("full", "Full Resolution", "Every render reads images at full resolution (Linear: bilinear, Closest: the "
           "nearest texel) per sample, so that averaged samples filter them over the pixel as Cycles does", 1),
    Choice("mip", "Mip Levels", "Every render reads images from the mip level of the camera ray cone's footprint: "
           "less noise per frame, but a minified normal or roughness map is averaged before shading", 2),
)
TEXTURE_FILTERS = tuple(c.id for c in TEXTURE_FILTER_CHOICES)
#: BSDF rays are tested against at most this many analytic lights (a loop per ray); beyond it the BSDF strategy
#: leaves them to light sampling (pdf 0 in the MIS weights, which stay correct)
BSDF_ANALYTIC_MAX = 64
TILE_INFO_BYTES = 8  # a tile entry's int2 (light index, pick pdf bits), next to its Light record
MAX_LIGHT_TILE_ENTRIES = 1 << 22  # light_tile_count * light_tile_size
UINT32_MAX = (1 << 32) - 1

# Blender's greying-out conditions: a setting that has no effect under the other settings' values
_RIS = (("method", ("ris", "restir")),)
_RESTIR = (("method", ("restir",)),)
_TEMPORAL = (*_RESTIR, ("temporal", (True,)))
_SPATIAL = (*_RESTIR, ("spatial", (True,)))
_VIS_TEMPORAL = (*_TEMPORAL, ("visibility_reuse", (True,)))
_TILES = (*_RIS, ("light_tiles", ("auto", "on")))
_TAA = (("taa", (True,)),)
_BSDF = (*_RIS, ("bsdf_sampling", ("auto", "on")))
_GI = (("gi_reuse", (True,)),)


@dataclass
class Settings:
    """Every parameter of a render. Defaults follow DESIGN section 3, tuned for a 2-core CPU."""

    method: str = setting("restir", "Method", "Direct-light estimator", flag="--method", choices=METHOD_CHOICES,
                          panel="sampling")
    candidates: int = setting(8, "Candidates", "Light candidates per pixel and frame (RIS, ReSTIR)",
                              flag="--candidates", range=Range(int, 1, 4096), panel="sampling", applies_when=_RIS,
                              soft_max=64)
    temporal: bool = setting(True, "Temporal Reuse", "ReSTIR: merge the reprojected reservoir of the previous frame",
                             flag="--no-temporal", panel="reuse", applies_when=_RESTIR)
    spatial: bool = setting(True, "Spatial Reuse", "ReSTIR: merge neighbouring reservoirs", flag="--no-spatial",
                            panel="reuse", applies_when=_RESTIR)
    spatial_neighbours: int = setting(2, "Neighbours", "Neighbour reservoirs merged per spatial pass",
                                      flag="--neighbours", range=Range(int, 0, 16), panel="reuse",
                                      applies_when=_SPATIAL, kernel_limit="MAX_NEIGHBOURS")
    spatial_radius: float = setting(5.0, "Radius", "Radius of the spatial neighbourhood in pixels", flag="--radius",
                                    range=Range(float, 1, finite=True), panel="reuse", applies_when=_SPATIAL,
                                    soft_max=100.0, subtype="PIXEL")
    spatial_passes: int = setting(1, "Passes", "Spatial reuse passes", flag="--passes", range=Range(int, 0, 8),
                                  panel="reuse", applies_when=_SPATIAL)
    bias_correction: str = setting("pairwise", "Bias Correction", "How reuse weighs the merged reservoirs",
                                   flag="--bias-correction", choices=BIAS_CHOICES, panel="reuse",
                                   applies_when=_RESTIR)
    m_cap: float = setting(5.0, "History Cap", "Cap of the temporal history M, as a multiple of the candidates",
                           flag="--m-cap", range=Range(float, 1, finite=True), panel="reuse", applies_when=_TEMPORAL,
                           soft_max=100.0)
    visibility_reuse: bool = setting(True, "Visibility Reuse", "Shadow-test the initial sample before reuse; "
                                     "unbiased reuse then counts visibility", flag="--no-visibility-reuse",
                                     panel="reuse", applies_when=_RESTIR)
    taa: bool = setting(True, "Temporal Anti-Aliasing", "Blend each animation frame with the reprojected, clipped "
                        "colour history", flag="--no-taa", panel="taa")
    alpha_min: float = setting(0.1, "Minimum Blend", "Smallest weight of the new frame in the TAA blend",
                               flag="--alpha-min", range=Range(float, 0, 1), panel="taa", applies_when=_TAA,
                               subtype="FACTOR")
    gamma: float = setting(1.0, "Clip Gamma", "Width of the TAA colour clipping box in standard deviations",
                           flag="--gamma", range=Range(float, 0, min_open=True, finite=True), panel="taa",
                           applies_when=_TAA, soft_max=4.0)
    max_history: int = setting(256, "History Length", "Longest TAA history in frames: a new frame weighs at least "
                               "1/this", flag="--max-history", range=Range(int, 1), panel="taa", applies_when=_TAA,
                               soft_max=1024)
    depth_tolerance: float = setting(0.1, "Depth Tolerance", "Relative view-depth mismatch that rejects a neighbour "
                                     "or the history", flag="--depth-tolerance", range=Range(float, 0, min_open=True),
                                     panel="reuse", applies_when=_RESTIR, soft_max=1.0)
    normal_angle: float = setting(25.0, "Normal Angle", "Degrees of normal mismatch that reject a neighbour or the "
                                  "history", flag="--normal-angle", range=Range(float, 0, 180), panel="reuse",
                                  applies_when=_RESTIR)
    slots_per_light: float = setting(4.0, "Slots per Light", "Light array size as a multiple of the light count "
                                     "(M = k N)", flag="--slots-per-light", range=Range(float, 1, finite=True),
                                     panel="lights", soft_max=16.0)
    light_tiles: str = setting("auto", "Light Tiles", "RIS and ReSTIR: draw the candidates from per-frame presampled "
                               "light tiles (many lights)", flag="--light-tiles", choices=LIGHT_TILE_CHOICES,
                               panel="lights", applies_when=_RIS)
    light_tile_count: int = setting(128, "Tile Count", "Light tiles presampled per frame", flag="--light-tile-count",
                                    range=Range(int, 1, 4096), panel="lights", applies_when=_TILES)
    light_tile_size: int = setting(1024, "Tile Size", "Lights presampled into each tile", flag="--light-tile-size",
                                   range=Range(int, 1, 65536), panel="lights", applies_when=_TILES, soft_max=4096)
    light_change_ratio: float = setting(2.0, "Light Change Ratio", "Drop the ReSTIR history when a light's power "
                                        "changes by more than this factor (0: never)", flag="--light-change-ratio",
                                        range=Range(float, 1, min_open=True, off=0.0), panel="reuse",
                                        applies_when=_RESTIR, soft_max=10.0)
    jitter: bool = setting(True, "Jitter", "Sub-pixel camera jitter (Halton 2, 3 per frame; Sobol stills: "
                           "one Sobol point with the first light sample)", flag="--no-jitter",
                           panel="sampling")
    seed: int = setting(0, "Seed", "Random seed", flag="--seed", range=Range(int, 0, UINT32_MAX), panel="sampling")
    specialise: bool = setting(True, "Specialised Kernels", "Compile only the features the scene needs (off: every "
                               "feature, for tests and benchmarks)", flag="--general", panel="device")
    bake_resolution: int = setting(512, "Bake Resolution", "Size in pixels of the square image to which a node graph "
                                   "the renderer does not evaluate is baked at export (Blender: Cycles' Emit bake on "
                                   "the object's UV map; 0: no baking, the input's value is used)",
                                   flag="--bake-resolution", range=Range(int, 0, 8192), panel="device",
                                   soft_max=2048, subtype="PIXEL")
    bsdf_sampling: str = setting("auto", "BSDF Sampling", "RIS and ReSTIR: add BSDF-sampled candidates, combined "
                                 "with the light candidates by multiple importance sampling", flag="--bsdf-sampling",
                                 choices=BSDF_SAMPLING_CHOICES, panel="sampling", applies_when=_RIS)
    bsdf_candidates: int = setting(1, "BSDF Candidates", "BSDF-sampled candidates per pixel and frame (RIS, ReSTIR)",
                                   flag="--bsdf-candidates", range=Range(int, 1, 64), panel="sampling",
                                   applies_when=_BSDF, soft_max=8)
    warmup_frames: int = setting(0, "Warm-up Frames", "Frames before the first frame of an animation render (and, "
                                 "on a farm, of every chunk) that are rendered with their motion and discarded, to "
                                 "fill the ReSTIR and TAA history", flag="--warmup-frames", range=Range(int, 0, 256),
                                 panel="sampling")
    boiling_filter: float = setting(0.0, "Boiling Filter", "ReSTIR, animation and viewport frames: empty a reservoir "
                                    "whose weight (or, by Boiling Mode, contribution) stands far above the others "
                                    "of its 8x8 tile (RTXDI's filter: strength 0-1, 1 the strongest, 0 off; biased, "
                                    "so still renders never use it)",
                                    flag="--boiling-filter", range=Range(float, 0, 1), panel="reuse",
                                    applies_when=_RESTIR, subtype="FACTOR")
    temporal_permutation: bool = setting(True, "Permutation Sampling", "ReSTIR temporal reuse takes the history of "
                                         "a neighbour within a 4x4 block, permuted every frame (RTXDI's), so that a "
                                         "pixel's frames are less correlated",
                                         flag="--no-temporal-permutation", panel="reuse", applies_when=_RESTIR)
    taa_filter: str = setting("bilinear", "History Filter", "How TAA samples its reprojected history",
                              flag="--taa-filter", choices=TAA_FILTER_CHOICES, panel="taa", applies_when=_TAA)
    taa_dilation: bool = setting(False, "Velocity Dilation", "TAA reprojects by the motion of the nearest surface in "
                                 "the 3x3 neighbourhood first, so the edges of a moving object follow it",
                                 flag="--taa-dilation", panel="taa", applies_when=_TAA)
    realtime_filter: bool = setting(False, "Real-time Filter", "Animation and viewport frames: an edge-aware "
                                    "a-trous filter (SVGF-style) of the TAA output, guided by depth, normal and the "
                                    "estimated variance; the TAA history is not filtered", flag="--realtime-filter",
                                    panel="taa", applies_when=_TAA)
    filter_iterations: int = setting(4, "Filter Iterations", "Real-time filter: a-trous iterations (taps 1, 2, 4, "
                                     "... pixels apart)", flag="--filter-iterations", range=Range(int, 1, 8),
                                     panel="taa", applies_when=(("taa", (True,)), ("realtime_filter", (True,))))
    disocclusion_boost: int = setting(8, "Disocclusion Boost", "ReSTIR: spatial neighbours for a pixel whose "
                                      "temporal pass found no history (disocclusion, off-screen), in place of "
                                      "Neighbours when larger (0: off)", flag="--disocclusion-boost",
                                      range=Range(int, 0, 16), panel="reuse", applies_when=_SPATIAL)
    fresh_candidates: int = setting(64, "Fresh Candidates", "ReSTIR: extra light candidates for a pixel without "
                                    "history that no spatial neighbour is similar to, merged into its own reservoir "
                                    "(0: off)", flag="--fresh-candidates", range=Range(int, 0, 256), panel="reuse",
                                    applies_when=_SPATIAL)
    denoise: bool = setting(False, "Denoise", "Filter each finished image with Intel Open Image Denoise (pyoidn), "
                            "guided by the albedo and normal of the same pixels; the image before it is kept as the "
                            "Noisy Image pass", flag="--denoise", panel="sampling")
    light_passes: bool = setting(False, "Light Passes", "Write Cycles' light passes (Diffuse and Glossy Direct, "
                                 "Indirect and Color, Emission, Environment); the add-on turns this on from the view "
                                 "layer's pass toggles", flag="--light-passes")

    still_method: str = setting("auto", "Still Method", "The estimator of still renders (F12, a still camera): "
                                "animations and the viewport keep Method", flag="--still-method",
                                choices=STILL_METHOD_CHOICES, panel="sampling")

    area_sampling: str = setting("area", "Area Light Sampling", "How a point on an area light (and an emissive "
                                 "triangle, a soft point light) is drawn", flag="--area-sampling",
                                 choices=AREA_SAMPLING_CHOICES, panel="lights")
    light_proposal: str = setting("auto", "Light Proposal", "RIS and ReSTIR: where the light candidates come from",
                                  flag="--light-proposal", choices=LIGHT_PROPOSAL_CHOICES, panel="lights",
                                  applies_when=_RIS)
    boiling_mode: str = setting("weight", "Boiling Mode", "What the boiling filter compares with the other "
                                "reservoirs of its tile, and what it does to an outlier", flag="--boiling-mode",
                                choices=BOILING_MODE_CHOICES, panel="reuse", applies_when=_RESTIR)
    bsdf_mis_sample: bool = setting(False, "BSDF MIS Sample", "RIS (and stills that use it): one BSDF-sampled "
                                    "direction per pixel and frame with its own shadow ray beside the resampled "
                                    "light sample, the two combined by multiple importance sampling, instead of "
                                    "BSDF candidates", flag="--bsdf-mis-sample", panel="sampling",
                                    applies_when=_RIS)

    sampler: str = setting("auto", "Sampler", "Where RIS's light pick, point on the light, BSDF direction and "
                           "resampling choice come from: a per-pixel Owen-scrambled Sobol sequence (a still's mean has "
                           "less error at equal frames than with random numbers) or random numbers",
                           flag="--sampler", choices=SAMPLER_CHOICES, panel="sampling", applies_when=_RIS)
    visibility_max_age: int = setting(0, "Visibility Age", "Visibility shortcut: where last frame's point is this "
                                      "pixel's (Visibility Distance) and nothing moved, the temporal reuse takes "
                                      "the stored shadow tests instead of rays, at most this many frames in a row; "
                                      "0: trace them (unbiased)", flag="--visibility-max-age", range=Range(int, 0, 64),
                                      panel="reuse", applies_when=_VIS_TEMPORAL, soft_max=16)
    visibility_max_distance: float = setting(2.0, "Visibility Distance", "Distance between last frame's point and "
                                             "this pixel's, in pixel footprints, within which the visibility "
                                             "shortcut holds",
                                             flag="--visibility-max-distance", range=Range(float, 0, finite=True),
                                             panel="reuse", applies_when=_VIS_TEMPORAL, soft_max=16.0,
                                             subtype="PIXEL")
    # Blender's Light Paths (the add-on reads them from the scene's Cycles settings where it has them)
    max_bounces: int = setting(0, "Max Bounces", "Light Paths > Total: how often light may bounce after the first "
                               "surface on its way to the camera (0: direct light only). Paths with next-event "
                               "estimation at every vertex, MIS and Russian roulette", flag="--max-bounces",
                               range=Range(int, 0, 1024), panel="light_paths", soft_max=32)
    diffuse_bounces: int = setting(4, "Diffuse", "Light Paths: bounces off diffuse parts of a material",
                                   flag="--diffuse-bounces", range=Range(int, 0, 1024), panel="light_paths",
                                   soft_max=32)
    glossy_bounces: int = setting(4, "Glossy", "Light Paths: bounces off glossy (specular) lobes",
                                  flag="--glossy-bounces", range=Range(int, 0, 1024), panel="light_paths",
                                  soft_max=32)
    min_light_bounces: int = setting(0, "Min Light Bounces", "Light Paths: bounces before Russian roulette may end "
                                     "a path (it starts at the third vertex with 0, as in Cycles)",
                                     flag="--min-light-bounces", range=Range(int, 0, 1024), panel="light_paths",
                                     soft_max=32)
    clamp_direct: float = setting(0.0, "Clamp Direct", "Light Paths: the largest value of one contribution of direct "
                                  "light: the emitters the camera sees, light samples at the first surface and the "
                                  "emitters its BSDF rays meet (biased, fewer fireflies; 0: off)",
                                  flag="--clamp-direct", range=Range(float, 0, finite=True), panel="light_paths",
                                  soft_max=100.0)
    clamp_indirect: float = setting(0.0, "Clamp Indirect", "Light Paths: the largest value of one contribution of "
                                    "bounced light (biased, fewer fireflies; 0: off)", flag="--clamp-indirect",
                                    range=Range(float, 0, finite=True), panel="light_paths", soft_max=100.0)
    light_threshold: float = setting(0.0, "Light Threshold", "Light Paths: light samples of bounced light below this "
                                     "are dropped at random and the rest weighted up (unbiased: fewer shadow rays, "
                                     "more noise; 0: off)", flag="--light-threshold",
                                     range=Range(float, 0, finite=True), panel="light_paths", soft_max=1.0)

    # ReSTIR GI (Max Bounces > 0, animation and viewport frames; still renders take the paths alone)
    gi_reuse: bool = setting(True, "ReSTIR GI", "Animation and viewport frames with Max Bounces > 0: resample the "
                             "bounced light's secondary surface points over time and neighbours (ReSTIR GI); still "
                             "renders use the paths alone", flag="--no-gi-reuse", panel="gi")
    gi_temporal: bool = setting(True, "Temporal Reuse", "ReSTIR GI: merge the reprojected reservoir of the previous "
                                "frame", flag="--no-gi-temporal", panel="gi", applies_when=_GI)
    gi_spatial_neighbours: int = setting(4, "Neighbours", "ReSTIR GI: neighbour reservoirs merged per frame (0: no "
                                         "spatial reuse)", flag="--gi-neighbours", range=Range(int, 0, 16),
                                         panel="gi", applies_when=_GI, kernel_limit="MAX_GI_NEIGHBOURS")
    gi_radius: float = setting(10.0, "Radius", "ReSTIR GI: radius of the spatial neighbourhood in pixels",
                               flag="--gi-radius", range=Range(float, 1, finite=True), panel="gi", applies_when=_GI,
                               soft_max=100.0, subtype="PIXEL")
    gi_m_cap: float = setting(8.0, "History Cap", "ReSTIR GI: cap of the temporal history M, in frames (a "
                              "secondary sample's radiance is as old as its history)", flag="--gi-m-cap",
                              range=Range(float, 1, finite=True), panel="gi", applies_when=_GI, soft_max=100.0)
    gi_bias_correction: str = setting("pairwise", "Bias Correction", "How ReSTIR GI weighs the merged reservoirs "
                                      "(None: no visibility test in the reuse, one at the shading)",
                                      flag="--gi-bias-correction", choices=BIAS_CHOICES, panel="gi",
                                      applies_when=_GI)
    gi_boiling_filter: float = setting(0.0, "Boiling Filter", "ReSTIR GI: empty a reservoir whose contribution (by "
                                       "Boiling Mode: weight, contribution, or forget) stands far above the others "
                                       "of its 8x8 tile (strength 0-1, 0 off; biased, animation and viewport only)",
                                       flag="--gi-boiling-filter", range=Range(float, 0, 1), panel="gi",
                                       applies_when=_GI, subtype="FACTOR")
    gi_disocclusion_boost: int = setting(0, "Disocclusion Boost", "ReSTIR GI: spatial neighbours for a pixel whose "
                                         "temporal pass found no history (disocclusion, off-screen), in place of "
                                         "Neighbours when larger (0: off)", flag="--gi-disocclusion-boost",
                                         range=Range(int, 0, 16), panel="gi", applies_when=_GI)
    path_light_pick: str = setting("auto", "Bounce Light Pick", "Light Paths: where next-event estimation at the "
                                   "vertices of bounced light picks its light (the direct light keeps Light "
                                   "Proposal)", flag="--path-light-pick", choices=PATH_LIGHT_PICK_CHOICES,
                                   panel="lights")
    texture_filter: str = setting("auto", "Texture Filter", "How camera rays read image textures: at full "
                                  "resolution per sample (Cycles' way: the converged image matches it) or from mip "
                                  "levels filtered over the pixel (steadier frames)", flag="--texture-filter",
                                  choices=TEXTURE_FILTER_CHOICES, panel="sampling")
    transmission_bounces: int = setting(12, "Transmission", "Light Paths: bounces through refracting (glass) lobes",
                                        flag="--transmission-bounces", range=Range(int, 0, 1024),
                                        panel="light_paths", soft_max=32)
    transparent_max_bounces: int = setting(8, "Transparent", "Light Paths: how many transparent or alpha-masked "
                                           "surfaces a ray may pass (camera rays end black at the next surface, "
                                           "shadow rays are blocked)", flag="--transparent-max-bounces",
                                           range=Range(int, 0, 1024), panel="light_paths", soft_max=64)
    cryptomatte_levels: int = setting(0, "Cryptomatte Levels", "Ids ranked per pixel in the Cryptomatte passes "
                                      "(object, material, asset; 0: none); the add-on sets it from the view "
                                      "layer's Cryptomatte toggles and Levels", flag="--cryptomatte-levels",
                                      range=Range(int, 0, 16))
    taa_fresh_fill: bool = setting(True, "Fresh-Pixel Fill", "Animation and viewport frames: a pixel without TAA "
                                   "history (uncovered, or new at the border) shows the mean of its 3x3 neighbours "
                                   "on the same surface instead of its one noisy sample (a one-frame blur within "
                                   "the surface)", flag="--no-taa-fresh-fill", panel="taa", applies_when=_TAA)
    taa_clip_surface: bool = setting(False, "Clip to Own Surface", "Moving frames: the clipping box from the 3x3 "
                                     "neighbours on the pixel's surface only: sharper edges without noise, noisier "
                                     "with it", flag="--taa-clip-surface", panel="taa", applies_when=_TAA)
    gi_temporal_permutation: bool = setting(False, "Permutation Sampling", "ReSTIR GI's temporal reuse as ReSTIR "
                                            "DI's Permutation Sampling (off: measured for direct light only)",
                                            flag="--gi-temporal-permutation", panel="gi", applies_when=_GI)

    def validate(self) -> Settings:
        check(self)
        entries = self.light_tile_count * self.light_tile_size
        if entries > MAX_LIGHT_TILE_ENTRIES:
            raise SettingError(f"light_tile_count * light_tile_size = {entries} light tile entries, more than "
                               f"{MAX_LIGHT_TILE_ENTRIES} "
                               f"({MAX_LIGHT_TILE_ENTRIES * (L.LIGHT.itemsize + TILE_INFO_BYTES) >> 20} MiB of tiles)",
                               JOINT_LIMITS[0])
        return self

    @classmethod
    def names(cls) -> list[str]:
        return [f.name for f in fields(cls)]


# settings limited together beyond their own ranges (validate() says how): a test sets the others to their minimum
JOINT_LIMITS = (("light_tile_count", "light_tile_size"),)


def kernel_defines() -> dict[str, int]:
    """The -D limits the kernels take from the table (their arrays are sized by them)."""
    out = {}
    for d in declared(Settings):
        if d.spec.kernel_limit is not None:
            assert d.spec.range is not None and d.spec.range.max is not None
            out[d.spec.kernel_limit] = int(d.spec.range.max)
    return out
