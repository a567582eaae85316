"""numpy mirrors of the structs in opencl/types.h (the one place they are defined on the host side).

tests/core/test_layouts.py compiles a kernel that reports sizeof/offsetof of each struct and compares.
"""

from __future__ import annotations

import numpy as np

F4 = (np.float32, 4)

TRI = np.dtype([("v0", F4), ("e1", F4), ("e2", F4)])
BVH_NODE = np.dtype(
    [("minx", F4), ("maxx", F4), ("miny", F4), ("maxy", F4), ("minz", F4), ("maxz", F4),
     ("child", (np.int32, 4)), ("count", (np.int32, 4))]
)
I4 = (np.int32, 4)
MATERIAL = np.dtype([("albedo", F4), ("emission", F4), ("info", I4)])
CLOSURE = np.dtype([("base", F4), ("spec", F4), ("tint", F4), ("kind", I4), ("tex", I4), ("tex2", I4),
                   ("glass", F4)])
TRI_ATTR = np.dtype([(n, F4) for n in ("n0", "n1", "n2", "u", "v", "o0", "oe1", "oe2", "tangent")])
OBJECT_INFO = np.dtype([("gen_mid", F4), ("gen_scale", F4)])
TEX_NODE = np.dtype([*[(n, F4) for n in ("a", "b", "p", "m0", "m1", "m2")], ("op", I4), ("in", I4), ("blk", I4)])
TEX_IMAGE = np.dtype([(n, np.int32) for n in ("offset", "width", "height", "levels")])
LIGHT = np.dtype([("p", F4), ("a", F4), ("b", F4), ("L", F4)])
LIGHT_TREE_NODE = np.dtype([("lo", F4), ("hi", F4), ("axis", F4), ("meta", I4)])
CAMERA = np.dtype(
    [
        ("origin", F4),
        ("right", F4),
        ("up", F4),
        ("forward", F4),
        ("lens", F4),
        ("jitter", F4),
        ("width", np.int32),
        ("height", np.int32),
        ("kind", np.int32),
        ("texture_full", np.int32),
        ("aperture", F4),
        ("focus", F4),
    ]
)
GSAMPLE = np.dtype(
    [("pos", F4), ("normal", F4), ("gnormal", F4), ("albedo", F4), ("emission", F4), ("motion", F4), ("layer", F4)]
)
LOBE = np.dtype([("a", F4), ("b", F4), ("c", F4), ("d", F4), ("e", F4)])  # lanes per kind: opencl/bsdf/<kind>.h
GLOSSY_SAMPLE = np.dtype([("wo", F4), ("lobe0", LOBE), ("lobe1", LOBE)])
RESERVOIR = np.dtype(
    [
        ("light", np.int32),
        ("u", np.float32),
        ("v", np.float32),
        ("w_sum", np.float32),
        ("M", np.float32),
        ("W", np.float32),
        ("target", np.float32),
        ("vis_age", np.int32),
    ]
)
# a ReSTIR GI reservoir (opencl/restir_gi/)
GI_RESERVOIR = np.dtype([("pos", F4), ("normal", F4), ("radiance", F4), ("w_sum", np.float32), ("M", np.float32),
                         ("W", np.float32), ("target", np.float32)])


def _ints(*names: str) -> list[tuple[str, type]]:
    return [(n, np.int32) for n in names]


def _floats(*names: str) -> list[tuple[str, type]]:
    return [(n, np.float32) for n in names]


# The parameter structs of the passes (types.h "parameters of the passes"): one per stage, read by field name.
FRAME_PARAMS = np.dtype([*_ints("width", "height", "pixels"), ("sample", np.uint32), ("seed", np.uint32),
                         ("qmc", np.int32), ("qmc_index", np.uint32), ("qmc_key", np.uint32)])
SAMPLER_PARAMS = np.dtype([*_ints("light_count", "slot_count", "tile_count", "tile_size", "bsdf_candidates",
                                  "bsdf_analytic", "bsdf_triangles", "bsdf_glossy_only", "light_tree",
                                  "tree_leaves", "tree_distant"), ("tree_p_local", np.float32),
                           *_ints("pick_table", "pad0", "pad1", "pad2")])
SIMILARITY_PARAMS = np.dtype([*_floats("depth_tolerance", "normal_cos"), *_ints("pad0", "pad1")])
INITIAL_PARAMS = np.dtype([("sampler", SAMPLER_PARAMS), *_ints("candidates", "visibility_reuse", "pad0", "pad1")])
TEMPORAL_PARAMS = np.dtype([("similar", SIMILARITY_PARAMS), ("m_cap", np.float32),
                            *_ints("bias_correction", "visibility_reuse", "lights_static"),
                            ("permutation", np.uint32), *_ints("vis_static", "vis_max_age"),
                            ("vis_max_distance", np.float32)])
SPATIAL_PARAMS = np.dtype([("similar", SIMILARITY_PARAMS), ("spatial_neighbours", np.int32),
                           ("spatial_radius", np.float32),
                           *_ints("bias_correction", "visibility_reuse", "pass_index", "boost_neighbours"),
                           ("fresh_m", np.float32), ("fresh_candidates", np.int32), ("sampler", SAMPLER_PARAMS)])
SHADE_PARAMS = np.dtype([("sampler", SAMPLER_PARAMS), *_ints("method", "candidates", "visible_known",
                                                              "bsdf_mis_sample"), ("clamp_direct", np.float32),
                         *_ints("pad0", "pad1", "pad2")])
TAA_PARAMS = np.dtype([("similar", SIMILARITY_PARAMS), *_floats("alpha_min", "gamma"),
                       *_ints("moving", "max_history", "reset", "filter", "dilate", "fresh_fill"),
                       *_floats("sweep_open", "sweep_close"), *_ints("clip_surface", "pad2")])

PATH_PARAMS = np.dtype([("sampler", SAMPLER_PARAMS), *_ints("max_bounces", "max_diffuse", "max_glossy", "min_bounces"),
                        *_floats("clamp_indirect", "light_threshold"), *_ints("max_transmission", "split_glass")])
GI_TEMPORAL_PARAMS = np.dtype([("similar", SIMILARITY_PARAMS), ("m_cap", np.float32), ("bias_correction", np.int32),
                               ("permutation", np.uint32), ("pad0", np.int32)])
GI_SPATIAL_PARAMS = np.dtype([("similar", SIMILARITY_PARAMS), ("neighbours", np.int32), ("radius", np.float32),
                              *_ints("bias_correction", "boost_neighbours")])
GI_SHADE_PARAMS = np.dtype(_ints("visible_known", "split_glass", "pad1", "pad2"))
ATROUS_PARAMS = np.dtype([("step", np.int32), *_floats("sigma_l", "sigma_z"), ("pad0", np.int32)])

#: struct name in types.h -> numpy dtype
STRUCTS: dict[str, np.dtype] = {
    "Tri": TRI,
    "BVHNode": BVH_NODE,
    "Material": MATERIAL,
    "Closure": CLOSURE,
    "TriAttr": TRI_ATTR,
    "ObjectInfo": OBJECT_INFO,
    "TexNode": TEX_NODE,
    "TexImage": TEX_IMAGE,
    "Light": LIGHT,
    "LightTreeNode": LIGHT_TREE_NODE,
    "Camera": CAMERA,
    "GSample": GSAMPLE,
    "Lobe": LOBE,
    "GlossySample": GLOSSY_SAMPLE,
    "Reservoir": RESERVOIR,
    "FrameParams": FRAME_PARAMS,
    "SamplerParams": SAMPLER_PARAMS,
    "SimilarityParams": SIMILARITY_PARAMS,
    "InitialParams": INITIAL_PARAMS,
    "TemporalParams": TEMPORAL_PARAMS,
    "AtrousParams": ATROUS_PARAMS,
    "SpatialParams": SPATIAL_PARAMS,
    "ShadeParams": SHADE_PARAMS,
    "PathParams": PATH_PARAMS,
    "TaaParams": TAA_PARAMS,
    "GIReservoir": GI_RESERVOIR,
    "GITemporalParams": GI_TEMPORAL_PARAMS,
    "GISpatialParams": GI_SPATIAL_PARAMS,
    "GIShadeParams": GI_SHADE_PARAMS,
}

# The guard counters (GUARD_* in opencl/codes.h, generated from GUARD_NAMES): a shading result, a TAA history write
# or a reservoir weight that was NaN/Inf and was replaced (by 0, or an emptied reservoir).
GUARD_NONFINITE_SAMPLE, GUARD_NONFINITE_HISTORY, GUARD_NONFINITE_RESERVOIR = range(3)
GUARD_COUNT = 4
GUARD_NAMES = ("nonfinite_sample", "nonfinite_history", "nonfinite_reservoir", "unused")


def pack(dtype: np.dtype, **fields: float) -> np.void:
    """One struct of `dtype` (a kernel argument passed by value): the named fields set, the rest (padding) 0. A
    nested struct is given as a dict of its fields or as a packed struct. A field the struct lacks is an error
    naming it."""
    record = np.zeros(1, dtype)
    _fill(record[0], dtype, fields)
    return record[0]


def _fill(record: np.void, dtype: np.dtype, fields: dict) -> None:
    assert dtype.names is not None
    for name, value in fields.items():
        if name not in dtype.names:
            raise KeyError(f"{name!r} is not a field of {dtype} (fields: {', '.join(dtype.names)})")
        sub = dtype.fields[name][0]
        if sub.names is not None and isinstance(value, dict):
            _fill(record[name], sub, value)
        else:
            record[name] = value


def int_bits(values: np.ndarray) -> np.ndarray:
    """Reinterpret int32 values as float32, for the int fields stored in a float4's w."""
    return np.ascontiguousarray(values, dtype=np.int32).view(np.float32)


def float_bits_to_int(values: np.ndarray) -> np.ndarray:
    """Inverse of int_bits."""
    return np.ascontiguousarray(values, dtype=np.float32).view(np.int32)
