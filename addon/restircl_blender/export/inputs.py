"""A colour or value input of a shader node -> a restircl Input: a constant, or a texture node of
restircl.materials.textures (Image Texture, Checker Texture, Mix Color, Normal Map, and the converters of
converters.py: Separate / Combine Color, Math, Vector Math, Invert) whose own inputs are read the same way.
Whatever else feeds an input is handed to the baker (bake.py); where that cannot be done, the input's own (unlinked)
value is used, with a note."""

from __future__ import annotations

from collections.abc import Callable

from .converters import KINDS as CONVERTERS
from .converters import converter
from .coords import Coords, coords_of
from .images import image_data
from .nodes import NodeLoop, Source, default_float, default_rgb, find_input, node_label, resolve
from .notes import Notes

COLOR, VALUE = "color", "value"
INTERPOLATIONS = {"Linear": "Linear", "Closest": "Closest", "Cubic": "Linear", "Smart": "Linear"}
EXTENSIONS = {"REPEAT": "REPEAT", "EXTEND": "EXTEND", "CLIP": "CLIP", "MIRROR": "REPEAT"}
MIX_SOCKETS = {"RGBA": ("A_Color", "B_Color", "Result_Color"), "FLOAT": ("A_Float", "B_Float", "Result_Float")}

USE_VALUE = object()  # a texture node that cannot be read (no image, no UV map): the input's own value is used
# bake(source, want) -> an ImageTexture of what `source` outputs, or None (the baker has noted why)
Baker = Callable[[Source, str], object]


class InputReader:
    def __init__(self, notes: Notes, has_uv: bool, bake: Baker | None):
        self.notes = notes
        self.has_uv = has_uv
        self._bake = bake
        self.uses_uv = False  # some texture read reads the UV map
        self.uv_maps: set[str] = set()  # UV maps named by UV Map / Normal Map nodes

    # ---- the three kinds of input ---------------------------------------------------------------------

    def color(self, socket, stack: tuple = ()):
        return self._read(socket, stack, COLOR, 0)

    def value(self, socket, stack: tuple = ()):
        return self._read(socket, stack, VALUE, 0)

    def unit(self, socket, stack: tuple, what: str):
        """A value input that Cycles clamps to [0, 1] (Metallic, Roughness, Specular IOR Level, Mix factors)."""
        v = self.value(socket, stack)
        if isinstance(v, float) and not 0.0 <= v <= 1.0:
            self.notes.note(f"{what} {v:g} is outside [0, 1]; clamped")
            v = min(max(v, 0.0), 1.0)
        return v

    def constant(self, socket, stack: tuple, what: str) -> float:
        """An input the renderer takes as a number only (IOR, strengths, scales)."""
        try:
            src = resolve(socket, stack)
        except NodeLoop:
            self.notes.note(f"{what} is linked in a loop; its value is used")
            return default_float(socket)
        if not src.linked:
            return default_float(src.socket)
        if src.kind == "ShaderNodeValue":
            return float(src.node.outputs[0].default_value)
        self.notes.note(f"{what} is driven by {src.label()}, which is not supported there; its value is used")
        return default_float(socket)

    def normal(self, socket, stack: tuple, what: str):
        """A Normal input: a restircl NormalMap, or None (the mesh's shading normal)."""
        if socket is None:
            return None
        try:
            src = resolve(socket, stack)
        except NodeLoop:
            self.notes.note(f"{what} is linked in a loop; ignored")
            return None
        if not src.linked:
            return None
        if src.kind == "ShaderNodeBump":
            return self._bump(src)
        if src.kind != "ShaderNodeNormalMap":
            self.notes.note(f"{what} is driven by {src.label()}, which is not supported (only a tangent-space "
                            "Normal Map or a Bump); ignored")
            return None
        node = src.node
        if node.space != "TANGENT":
            self.notes.note(f"Normal Map {node.name!r} in {node.space} space is not supported; ignored")
            return None
        if not self._uv_ok(f"Normal Map {node.name!r}", node.uv_map):
            return None
        from restircl import NormalMap

        strength = self.constant(find_input(node, ("Strength",)), src.stack, f"Normal Map {node.name!r} Strength")
        return NormalMap(color=self.color(find_input(node, ("Color",)), src.stack), strength=strength)

    def _bump(self, src: Source):
        """A Bump node: its Height read as any value input; Strength and Distance as numbers."""
        from restircl import Bump

        node = src.node
        what = f"Bump {node.name!r}"
        if find_input(node, ("Normal",)) is not None and find_input(node, ("Normal",)).is_linked:
            self.notes.note(f"{what}: its Normal input is not supported; the surface's normal is bumped")
        return Bump(height=self.value(find_input(node, ("Height",)), src.stack),
                    strength=self.constant(find_input(node, ("Strength",)), src.stack, f"{what} Strength"),
                    distance=self.constant(find_input(node, ("Distance",)), src.stack, f"{what} Distance"),
                    invert=bool(node.invert))

    # ---- one input ------------------------------------------------------------------------------------

    def _default(self, socket, want: str):
        if want == COLOR:
            return tuple(max(c, 0.0) for c in default_rgb(socket))
        return default_float(socket)

    def _read(self, socket, stack: tuple, want: str, depth: int):
        if depth > 16:
            self.notes.note(f"a texture graph feeding {socket.name!r} is nested too deeply; its value is used")
            return self._default(socket, want)
        try:
            src = resolve(socket, stack)
        except NodeLoop:
            self.notes.note(f"input {socket.name!r} is linked in a loop (or nested too deeply); its value is used")
            return self._default(socket, want)
        if not src.linked:
            return self._default(src.socket, want)
        value = self._node(src, want, depth)
        if value is None:
            value = self._baked(src, want)
        value = self._default(socket, want) if value is None or value is USE_VALUE else value
        if want == COLOR and isinstance(value, tuple) and min(value) < 0:  # Cycles clamps colours at 0
            value = tuple(max(c, 0.0) for c in value)
        return value

    def _node(self, src: Source, want: str, depth: int):
        """A node we evaluate natively, or None (to bake)."""
        kind, node = src.kind, src.node
        if kind == "ShaderNodeRGB":
            return default_rgb(node.outputs[0]) if want == COLOR else default_float(node.outputs[0])
        if kind == "ShaderNodeValue":
            v = float(node.outputs[0].default_value)
            return (v, v, v) if want == COLOR else v
        if kind == "ShaderNodeTexImage" and src.socket.identifier in ("Color", "Alpha"):
            return self._image(src)
        if kind == "ShaderNodeTexChecker":
            return self._checker(src, depth)
        if kind in ("ShaderNodeMix", "ShaderNodeMixRGB"):
            return self._mix(src, depth)
        if kind in CONVERTERS:
            return converter(src, self._read, depth)
        if kind in ("ShaderNodeVertexColor", "ShaderNodeAttribute"):
            return _attribute(src)
        return None

    def _uv_ok(self, what: str, uv_map: str = "") -> bool:
        if not self.has_uv:
            self.notes.note(f"{what} needs a UV map, which the object has not; the input's value is used")
            return False
        self.uses_uv = True
        if uv_map:
            self.uv_maps.add(uv_map)
        return True

    def _coords(self, src: Source, default: str):
        """The node's Coords; None to bake it; USE_VALUE without the UV map it needs."""
        vec = find_input(src.node, ("Vector",))
        c = Coords(default) if vec is None else coords_of(vec, src.stack, default)
        if c is not None and c.coords == "uv" and not self._uv_ok(f"{node_label(src.node)} {src.node.name!r}",
                                                                   c.uv_map):
            return USE_VALUE
        return c

    def _image(self, src: Source):
        from restircl import ImageTexture

        node = src.node
        what = f"Image Texture {node.name!r}"
        if getattr(node, "projection", "FLAT") != "FLAT":
            return None
        c = self._coords(src, "uv")
        if c is None or c is USE_VALUE:
            return c
        if node.image is None:
            self.notes.note(f"{what} has no image; the input's value is used")
            return USE_VALUE
        data = image_data(node.image, self.notes.note, what)
        if data is None:
            return USE_VALUE
        for prop, table in (("interpolation", INTERPOLATIONS), ("extension", EXTENSIONS)):
            v = getattr(node, prop)
            if table.get(v, "") != v:
                self.notes.note(f"{what}: {prop} {v} is not supported; {table.get(v, list(table)[0])} is used")
        return ImageTexture(image=data[0], colorspace=data[1], interpolation=INTERPOLATIONS.get(
            node.interpolation, "Linear"), extension=EXTENSIONS.get(node.extension, "REPEAT"), coords=c.coords,
            mapping=c.mapping, name=node.image.name, alpha=src.socket.identifier == "Alpha")

    def _checker(self, src: Source, depth: int):
        from restircl import CheckerTexture

        node = src.node
        scale = find_input(node, ("Scale",))
        if scale is not None and scale.is_linked:
            return None
        c = self._coords(src, "generated")
        if c is None or c is USE_VALUE:
            return c
        if src.socket.identifier == "Fac":
            a, b = (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)
        else:
            a = self._read(find_input(node, ("Color1",)), src.stack, COLOR, depth + 1)
            b = self._read(find_input(node, ("Color2",)), src.stack, COLOR, depth + 1)
        return CheckerTexture(color1=a, color2=b, scale=default_float(scale) if scale is not None else 5.0,
                              coords=c.coords, mapping=c.mapping)

    def _mix(self, src: Source, depth: int):
        from restircl import MixColor
        from restircl.materials.textures import MIX_BLENDS

        node = src.node
        if node.bl_idname == "ShaderNodeMixRGB":
            names, fac, clamp_factor, clamp_result = ("Color1", "Color2"), "Fac", True, node.use_clamp
        else:
            sockets = MIX_SOCKETS.get(node.data_type)
            if sockets is None or src.socket.identifier != sockets[2]:
                return None
            names, fac, clamp_factor, clamp_result = sockets[:2], "Factor_Float", node.clamp_factor, node.clamp_result
        blend = "MIX" if node.bl_idname == "ShaderNodeMix" and node.data_type == "FLOAT" else node.blend_type
        if blend not in MIX_BLENDS:
            return None
        # a float mix too: its a and b as grey colours (a texture node's inputs are colours)
        a, b = (self._read(find_input(node, (n,)), src.stack, COLOR, depth + 1) for n in names)
        f = self._read(find_input(node, (fac, "Fac", "Factor")), src.stack, VALUE, depth + 1)
        if isinstance(f, float) and f < 0:
            self.notes.note(f"{node_label(node)} {node.name!r}: factor {f:g} is below 0; 0 is used")
            f = 0.0
        return MixColor(a=a, b=b, factor=f, blend=blend, clamp_factor=bool(clamp_factor),
                        clamp_result=bool(clamp_result))

    def _baked(self, src: Source, want: str):
        what = f"{src.label()} {src.node.name!r}"
        if self._bake is None:
            self.notes.note(f"{what} cannot be baked here; the input's value is used")
            return None
        if src.stack:
            self.notes.note(f"{what} inside a node group cannot be baked; the input's value is used")
            return None
        if not self._uv_ok(f"baking {what}"):
            return None
        for label in upstream_labels(src.node):
            self.notes.bake(label)
        return self._bake(src, want)


ATTRIBUTE_OUTPUTS = {"Color": "color", "Vector": "color", "Fac": "fac", "Alpha": "alpha"}


def _attribute(src: Source):
    """A Color Attribute node, or an Attribute node of a geometry attribute: a restircl Attribute (the meshes export
    their colour attributes of that name; mesh.py warns where an object has none); other kinds: None (baked)."""
    from restircl import Attribute

    node = src.node
    if node.bl_idname == "ShaderNodeAttribute" and node.attribute_type != "GEOMETRY":
        return None
    name = node.layer_name if node.bl_idname == "ShaderNodeVertexColor" else node.attribute_name
    output = ATTRIBUTE_OUTPUTS.get(src.socket.identifier)
    return None if output is None else Attribute(name=name, output=output)


def upstream_labels(node, limit: int = 64) -> list[str]:
    """The node types of `node` and everything that feeds it (for the bake warning)."""
    out: list[str] = []
    todo, seen = [node], set()
    while todo and len(seen) < limit:
        n = todo.pop()
        if n.as_pointer() in seen:
            continue
        seen.add(n.as_pointer())
        if n.bl_idname not in ("NodeReroute",) and node_label(n) not in out:
            out.append(node_label(n))
        todo.extend(lk.from_node for s in n.inputs if s.is_linked for lk in s.links)
    return out
