"""The converter nodes of PBR graphs -> restircl texture nodes (restircl.materials.textures): Separate / Combine Color
and the legacy Separate / Combine RGB, HSV and XYZ, Math, Vector Math, Invert, Hue/Saturation/Value and Color
Ramp (RGB colour mode; Linear, Constant and Ease) and RGB Curves (a table of Blender's own curve evaluation), read
natively instead of baked.
An operation the renderer does not have gives None: the caller bakes the node."""

from __future__ import annotations

from collections.abc import Callable

from .nodes import Source, find_input

COLOR, VALUE = "color", "value"
# node type -> the colour mode its channels are in (None: the node's own `mode`)
SEPARATE = {"ShaderNodeSeparateColor": None, "ShaderNodeSeparateRGB": "RGB", "ShaderNodeSeparateHSV": "HSV",
            "ShaderNodeSeparateXYZ": "RGB"}
COMBINE = {"ShaderNodeCombineColor": None, "ShaderNodeCombineRGB": "RGB", "ShaderNodeCombineHSV": "HSV",
           "ShaderNodeCombineXYZ": "RGB"}
KINDS = (*SEPARATE, *COMBINE, "ShaderNodeMath", "ShaderNodeVectorMath", "ShaderNodeInvert", "ShaderNodeHueSaturation",
         "ShaderNodeValToRGB", "ShaderNodeRGBCurve")
CURVE_ROWS = 256  # rows of an RGB Curves table, as many as Cycles' own table has

# read(socket, stack, want, depth) -> an Input
Read = Callable[[object, tuple, str, int], object]


def _enabled(sockets) -> list:
    return [s for s in sockets if getattr(s, "enabled", True)]


def converter(src: Source, read: Read, depth: int):
    """The restircl node for a converter node's output `src`, or None to bake it."""
    from restircl.materials.textures import COLOR_MODES

    node, kind = src.node, src.kind
    ins = _enabled(node.inputs)

    def sub(sock, want: str):
        return read(sock, src.stack, want, depth + 1)

    if kind in SEPARATE or kind in COMBINE:
        mode = (SEPARATE.get(kind) or COMBINE.get(kind)) or getattr(node, "mode", "RGB")
        if mode not in COLOR_MODES:
            return None
        if kind in SEPARATE:
            from restircl import SeparateColor

            channel = next((i for i, s in enumerate(_enabled(node.outputs)) if s == src.socket), -1)
            if channel not in (0, 1, 2) or not ins:
                return None
            return SeparateColor(color=sub(ins[0], COLOR), channel=channel, mode=mode)
        from restircl import CombineColor

        r, g, b = (sub(s, VALUE) for s in ins[:3])
        return CombineColor(r=r, g=g, b=b, mode=mode)
    if kind == "ShaderNodeMath":
        return _math(node, ins, sub)
    if kind == "ShaderNodeVectorMath":
        return _vector_math(node, src, sub)
    if kind == "ShaderNodeValToRGB":
        return _color_ramp(node, src, sub)
    if kind == "ShaderNodeRGBCurve":
        return _rgb_curves(node, sub)
    if kind == "ShaderNodeHueSaturation":
        from restircl import HueSaturationValue

        hue, sat, val, fac = (sub(find_input(node, (n,)), VALUE) for n in ("Hue", "Saturation", "Value", "Fac"))
        return HueSaturationValue(color=sub(find_input(node, ("Color",)), COLOR), hue=hue, saturation=sat, value=val,
                                  factor=fac)
    from restircl import Invert

    return Invert(color=sub(find_input(node, ("Color",)), COLOR), factor=sub(find_input(node, ("Fac",)), VALUE))


def _math(node, ins: list, sub):
    from restircl import Math
    from restircl.materials.textures import MATH_OPS

    if node.operation not in MATH_OPS:
        return None
    values = [sub(s, VALUE) for s in ins[:3]] + [0.0] * (3 - len(ins[:3]))
    return Math(op=node.operation, a=values[0], b=values[1], c=values[2], clamp=bool(node.use_clamp))


def _vector_math(node, src: Source, sub):
    from restircl import VectorMath
    from restircl.materials.textures import VECTOR_OPS, VECTOR_VALUE_OPS

    op = node.operation
    if op not in VECTOR_OPS or (src.socket.identifier == "Value") != (op in VECTOR_VALUE_OPS):
        return None
    a, b = (find_input(node, (n,)) for n in ("Vector", "Vector_001"))
    scale = find_input(node, ("Scale",))
    return VectorMath(op=op, a=sub(a, COLOR), b=sub(b, COLOR) if b is not None else (0.0, 0.0, 0.0),
                      scale=sub(scale, VALUE) if scale is not None else 1.0)


def _color_ramp(node, src: Source, sub):
    """A Color Ramp in RGB mode with an interpolation the renderer has (B-Spline and Cardinal are baked)."""
    from restircl import ColorRamp
    from restircl.materials.textures import RAMP_INTERPOLATIONS

    ramp = node.color_ramp
    if ramp.color_mode != "RGB" or ramp.interpolation not in RAMP_INTERPOLATIONS or not len(ramp.elements):
        return None
    stops = [(float(e.position), tuple(float(c) for c in e.color)) for e in ramp.elements]
    return ColorRamp(factor=sub(find_input(node, ("Fac",)), VALUE), positions=tuple(p for p, _ in stops),
                     colors=tuple(c for _, c in stops), interpolation=ramp.interpolation,
                     alpha=src.socket.identifier == "Alpha")


def _rgb_curves(node, sub):
    """RGB Curves: Blender's CurveMapping evaluated at CURVE_ROWS points over the x range of all four curves' points,
    each channel's curve after the combined one (curves R, G, B, C: C first)."""
    from restircl import RGBCurves

    mapping = node.mapping
    mapping.initialize()
    xs = [float(p.location[0]) for c in mapping.curves for p in c.points]
    lo, hi = min([0.0, *xs]), max([1.0, *xs])
    r, g, b, combined = mapping.curves[0], mapping.curves[1], mapping.curves[2], mapping.curves[3]
    rows = []
    for i in range(CURVE_ROWS):
        t = mapping.evaluate(combined, lo + (hi - lo) * i / (CURVE_ROWS - 1))
        rows.append((mapping.evaluate(r, t), mapping.evaluate(g, t), mapping.evaluate(b, t)))
    return RGBCurves(color=sub(find_input(node, ("Color",)), COLOR), factor=sub(find_input(node, ("Fac",)), VALUE),
                     table=tuple(rows), lo=lo, hi=hi, extrapolate=getattr(mapping, "extend", "") == "EXTRAPOLATED")
