"""Texture nodes -> the device's texture programs (TexNode records), image table (TexImage) and texel buffer
(opencl/textures/nodes.h, textures/image.h).

Every material input linked to a texture node gets a program: the node's sub-graph in post-order, contiguous in the
node table and ending at the node the input refers to (TexturePacker.index, material_pack's texture_index hook), so
the device evaluates it in one loop. A node graph with a loop is refused (SceneError naming the material). All
images share one float4 texel buffer, each with its mip chain; an image that cannot be used (a missing or unreadable
file, a 0x0 image, an unsupported colour space) renders magenta, as Blender shows a missing image, with a warning
naming the material and the image; NaN/Inf texels are counted, zeroed and warned about.
"""

from __future__ import annotations

import hashlib
import math
import os
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core import layouts as L
from ..io.image_load import LINEAR_COLORSPACES, ImageReadError, mip_chain, read_image_file, to_linear_rgba
from ..lights.textured_emission import sampled_emission
from ..materials import textures as tx
from ..materials.material import Material, material_inputs
from ..materials.textures import (
    CheckerTexture,
    ImageTexture,
    MixColor,
    NormalMap,
    constant_float,
    constant_rgb,
    is_texture,
)
from ..scene.errors import SceneError
from .attributes import attribute_names, texture_nodes

MAX_TEX_PROGRAM = 16  # nodes in one input's program, the registers it is evaluated into (opencl/codes.h)
MAGENTA = (1.0, 0.0, 1.0, 1.0)
#: the texture node kinds by their device code (TEXNODE_<NAME>, opencl/codes.h)
NODE_KINDS = (("IMAGE", ImageTexture), ("CHECKER", CheckerTexture), ("MIX", MixColor), ("NORMAL_MAP", NormalMap),
              ("SEPARATE_COLOR", tx.SeparateColor), ("COMBINE_COLOR", tx.CombineColor), ("MATH", tx.Math),
              ("VECTOR_MATH", tx.VectorMath), ("INVERT", tx.Invert), ("HSV", tx.HueSaturationValue),
              ("COLOR_RAMP", tx.ColorRamp), ("RGB_CURVES", tx.RGBCurves), ("ATTRIBUTE", tx.Attribute),
              ("BUMP", tx.Bump))
NODE_CODE = {cls: code for code, (_, cls) in enumerate(NODE_KINDS)}
MAX_TEXELS = 2**31 - 1  # int offsets on the device


@dataclass
class PackedTextures:
    nodes: np.ndarray  # L.TEX_NODE
    images: np.ndarray  # L.TEX_IMAGE
    texels: np.ndarray  # (N, 4) float32
    nonfinite_texels: int  # NaN/Inf texels zeroed


def node_inputs(node: object) -> list[object]:
    """The inputs of a texture node that may be nodes themselves (a, b, factor order for the device)."""
    if isinstance(node, MixColor):
        return [node.a, node.b, node.factor]
    if isinstance(node, CheckerTexture):
        return [node.color1, node.color2]
    if isinstance(node, NormalMap | tx.SeparateColor):
        return [node.color]
    if isinstance(node, tx.Bump):
        return [node.height]
    if isinstance(node, tx.CombineColor):
        return [node.r, node.g, node.b]
    if isinstance(node, tx.Math):
        return [node.a, node.b, node.c]
    if isinstance(node, tx.VectorMath):
        return [node.a, node.b, node.scale]
    if isinstance(node, tx.Invert):
        return [node.color, 0.0, node.factor]
    if isinstance(node, tx.HueSaturationValue):
        return [node.color, _hsv_vector(node), node.factor]
    if isinstance(node, tx.ColorRamp):
        return [0.0, 0.0, node.factor]
    if isinstance(node, tx.RGBCurves):
        return [node.color, 0.0, node.factor]
    return []


def _hsv_vector(node: tx.HueSaturationValue) -> object:
    """The node's (hue, saturation, value) as the device reads them, in b: constants as they are, else one Combine
    Color of the three, made once per node while they stay the same (node ids identify a program's nodes)."""
    hsv = (node.hue, node.saturation, node.value)
    if not any(is_texture(v) for v in hsv):
        return tuple(constant_float(v) for v in hsv)
    kept = node.__dict__.get("_combined")
    if kept is None or any(x is not y for x, y in zip((kept.r, kept.g, kept.b), hsv, strict=True)):
        kept = node.__dict__["_combined"] = tx.CombineColor(*hsv)
    return kept


@dataclass
class LoadedImage:
    """An image as the texel buffer holds it: its mip chain, and whether its texels are still sRGB-encoded."""

    levels: list[np.ndarray]
    encoded: bool
    nonfinite: int = 0  # NaN/Inf texels zeroed when it was read


def image_key(node: ImageTexture) -> tuple:
    """What identifies an image's texels from one packing to the next (an interactive edit packs the materials
    again): a file by its path, size and modification time, an array by its content; and the colour space."""
    src = node.image
    if isinstance(src, str | Path):
        path = str(Path(src).resolve())
        try:
            st = os.stat(path)
            stamp: tuple = (st.st_size, st.st_mtime_ns)
        except OSError:  # missing: magenta, with the warning of _load
            stamp = ()
        return ("path", path, *stamp, node.colorspace)
    try:
        arr = np.ascontiguousarray(src)
        digest = hashlib.blake2b(arr.view(np.uint8).reshape(-1), digest_size=16).hexdigest()
    except (TypeError, ValueError):  # not a numeric array: _load says why; this object only
        return ("object", id(src), node.colorspace)
    return ("array", arr.dtype.str, arr.shape, digest, node.colorspace)


def image_label(node: ImageTexture) -> str:
    if node.name:
        return repr(node.name)
    if isinstance(node.image, str | Path):
        return repr(str(node.image))
    return f"(array {np.shape(node.image)})"


class TexturePacker:
    """The texture programs of a scene's materials, built once; index(node) is material_pack's texture_index.
    `loaded`: images a packing before loaded (its `images`), by image_key, taken as they are instead of being
    read again."""

    def __init__(self, materials: list[Material], loaded: dict[tuple, LoadedImage] | None = None) -> None:
        self._roots: dict[int, int] = {}  # id(node) -> index of the last node of its program
        self._alive: list[object] = []  # the nodes indexed by id, kept alive so ids stay unique
        self._nodes: list[np.void] = []
        self._loaded = loaded or {}
        self.images: dict[tuple, LoadedImage] = {}  # this packing's images by image_key, in image-table order
        self._slot: dict[tuple, int] = {}  # image_key -> index in the image table
        self._by_id: dict[tuple, tuple] = {}  # (id of the source, colour space) -> image_key: each array hashed once
        self.attribute_names = attribute_names(materials)  # Attribute nodes' names, by their index on the device
        for i, m in enumerate(materials):
            label = f"material {i} {m.name!r}"
            for value in material_inputs(m):
                if is_texture(value):
                    self._program(value, label)

    def index(self, node: object) -> int:
        return self._roots[id(node)]

    @property
    def nonfinite_texels(self) -> int:
        return sum(img.nonfinite for img in self.images.values())

    @property
    def image_keys(self) -> list[tuple]:
        """The image_key of each image of the image table: equal lists mean equal image tables and texels."""
        return list(self.images)

    def packed(self, texels: bool = True) -> PackedTextures:
        """The packed tables; texels=False leaves the texel buffer empty (the caller keeps the one it has)."""
        nodes = np.zeros(max(len(self._nodes), 1), L.TEX_NODE)
        for k, r in enumerate(self._nodes):
            nodes[k] = r
        images = np.zeros(max(len(self.images), 1), L.TEX_IMAGE)
        chunks, offset = [], 0
        for k, img in enumerate(self.images.values()):
            levels = img.levels
            images[k] = (offset, levels[0].shape[1], levels[0].shape[0], len(levels))
            for lv in levels:
                if texels:
                    chunks.append(lv.reshape(-1, 4))
                offset += lv.shape[0] * lv.shape[1]
        if offset > MAX_TEXELS:
            raise SceneError(f"textures: {offset} texels with their mip chains exceed the device limit {MAX_TEXELS}")
        buf = np.concatenate(chunks) if chunks else np.zeros((1 if texels else 0, 4), np.float32)
        return PackedTextures(nodes, images, np.ascontiguousarray(buf, np.float32), self.nonfinite_texels)

    # ---- programs ------------------------------------------------------------------------------------

    def _program(self, root: object, label: str) -> None:
        if id(root) in self._roots:
            return
        order: list[object] = []
        _post_order(root, order, set(), [], label)
        if len(order) > MAX_TEX_PROGRAM:
            raise SceneError(f"{label}: an input's texture graph has {len(order)} nodes, at most {MAX_TEX_PROGRAM}")
        first = len(self._nodes)
        where: dict[int, int] = {}
        for node in order:
            where[id(node)] = len(self._nodes)
            self._nodes.append(self._record(node, where, first, label))
        self._roots[id(root)] = len(self._nodes) - 1
        self._alive.append(root)

    def _record(self, node: object, where: dict[int, int], first: int, label: str) -> np.void:
        r = np.zeros((), L.TEX_NODE)
        r["op"] = (NODE_CODE[type(node)], 0, 0, 0)
        r["in"] = (-1, -1, -1, -1)
        r["blk"] = (first, 0, 0, 0)
        r["m0"], r["m1"], r["m2"] = np.eye(4, dtype=np.float32)[:3]
        for k, value in enumerate(node_inputs(node)):
            if is_texture(value):
                r["in"][k] = where[id(value)]
            elif k < 2:
                r["a" if k == 0 else "b"][:3] = constant_rgb(value)
            else:
                r["p"][0] = constant_float(value)
        if isinstance(node, ImageTexture | CheckerTexture):
            self._coords(r, node)
        if isinstance(node, ImageTexture):
            r["op"][1] = tx.INTERPOLATIONS.index(node.interpolation)
            r["op"][2] = tx.EXTENSIONS.index(node.extension)
            r["in"][3], encoded = self._image(node, label)
            r["blk"][2] = int(encoded)
            r["blk"][3] = int(tx.gives_number(node))  # the Alpha output
        elif isinstance(node, CheckerTexture):
            r["p"][0] = float(node.scale)
        elif isinstance(node, MixColor):
            r["op"][1] = tx.MIX_BLENDS.index(node.blend)
            r["blk"][1] = int(bool(node.clamp_factor))
            r["blk"][2] = int(bool(node.clamp_result))
        elif isinstance(node, NormalMap):
            r["p"][0] = float(node.strength)
        elif isinstance(node, tx.Bump):  # p.x strength, p.z distance (negated by invert)
            r["p"][0], r["p"][2] = float(node.strength), -float(node.distance) if node.invert else float(node.distance)
        elif isinstance(node, tx.ColorRamp):
            r["op"][1] = tx.RAMP_INTERPOLATIONS.index(node.interpolation)
            r["in"][3] = self._ramp(node)
            r["blk"][3] = int(tx.gives_number(node))
        elif isinstance(node, tx.Attribute):
            r["op"][1] = self.attribute_names.index(node.name)
            r["op"][2] = tx.ATTRIBUTE_OUTPUTS.index(node.output)
            r["blk"][3] = int(tx.gives_number(node))
        elif isinstance(node, tx.RGBCurves):
            r["in"][3] = self._curves(node)
            r["p"][1], r["p"][2] = float(node.lo), float(node.hi)
            r["blk"][1] = int(bool(node.extrapolate))
        else:
            self._converter(r, node)
        return r

    @staticmethod
    def _converter(r: np.void, node: object) -> None:
        """op.y: the mode or operation; op.z: Separate Color's channel; blk.y: Math's clamp; blk.w: gives a number."""
        if isinstance(node, tx.SeparateColor | tx.CombineColor):
            r["op"][1] = tx.COLOR_MODES.index(node.mode)
        if isinstance(node, tx.SeparateColor):
            r["op"][2] = int(node.channel)
        elif isinstance(node, tx.Math):
            r["op"][1] = tx.MATH_OPS.index(node.op)
            r["blk"][1] = int(bool(node.clamp))
        elif isinstance(node, tx.VectorMath):
            r["op"][1] = tx.VECTOR_OPS.index(node.op)
        r["blk"][3] = int(tx.gives_number(node))

    @staticmethod
    def _coords(r: np.void, node: ImageTexture | CheckerTexture) -> None:
        r["op"][3] = tx.COORDS.index(node.coords)
        if node.mapping is None:
            return
        m = np.asarray(node.mapping, dtype=np.float64)
        r["m0"], r["m1"], r["m2"] = m[:3].astype(np.float32)
        # the mapping scales the footprint: by the square root of its area scale on the UV plane, else the cube
        # root of its volume scale
        det = abs(np.linalg.det(m[:2, :2])) ** 0.5 if node.coords == "uv" else abs(np.linalg.det(m[:3, :3])) ** (1 / 3)
        r["p"][1] = math.log2(max(float(det), 1e-30))

    def _ramp(self, node: tx.ColorRamp) -> int:
        """The image-table slot of a ramp's stops: a 2-row "image" in the texel buffer, its rgba colours in the first
        row and positions in the second (x), sorted by position (stably, as Blender keeps them)."""
        order = sorted(range(len(node.positions)), key=lambda k: float(node.positions[k]))
        stops = np.zeros((2, len(order), 4), np.float32)
        for j, k in enumerate(order):
            c = tuple(float(x) for x in node.colors[k])
            stops[0, j] = (*c[:3], c[3] if len(c) > 3 else 1.0)
            stops[1, j, 0] = float(node.positions[k])
        return self._table(("ramp", stops.tobytes()), stops)

    def _curves(self, node: tx.RGBCurves) -> int:
        """The image-table slot of an RGB Curves table: a 1-row "image" of its (r, g, b) rows in the texel buffer."""
        rows = np.asarray(node.table, np.float32).reshape(-1, 3)
        table = np.zeros((1, len(rows), 4), np.float32)
        table[0, :, :3] = rows
        return self._table(("curves", table.tobytes()), table)

    def _table(self, key: tuple, texels: np.ndarray) -> int:
        if key not in self.images:
            self._slot[key] = len(self.images)
            self.images[key] = LoadedImage([texels], False)
        return self._slot[key]

    # ---- images --------------------------------------------------------------------------------------

    def _image(self, node: ImageTexture, label: str) -> tuple[int, bool]:
        """(index in the image table, texels kept sRGB-encoded) of the node's image, loaded once per packing."""
        src = node.image
        by_id = (id(src), node.colorspace)
        key = self._by_id.get(by_id)
        if key is None:
            key = self._by_id[by_id] = image_key(node)
            self._alive.append(src)
        if key not in self.images:
            img = self._loaded.get(key)
            if img is None:
                texels, encoded, nonfinite = self._load(node, label)
                img = LoadedImage(mip_chain(texels, encoded), encoded, nonfinite)
            self._slot[key] = len(self.images)
            self.images[key] = img
        return self._slot[key], self.images[key].encoded

    def _load(self, node: ImageTexture, label: str) -> tuple[np.ndarray, bool, int]:
        """Linear RGBA texels, bottom row first, whether they are still sRGB-encoded, and how many texels held NaN
        or Inf (zeroed, with a warning). An 8-bit sRGB image is filtered (bilinear, mips) in its encoding and
        decoded after, as Cycles does with byte images (measured on the plane of tests/blender/test_blender_textures.py,
        random 8-bit texels magnified, Linear, 64x48: decoded first, relMSE 5.8 % against Cycles and 21 % brighter;
        decoded after, 0.02 %); other images are decoded on upload."""
        name = image_label(node)
        magenta = np.array(MAGENTA, np.float32).reshape(1, 1, 4)
        if node.colorspace != "sRGB" and node.colorspace not in LINEAR_COLORSPACES:
            warnings.warn(f"{label}: image {name}: colour space {node.colorspace!r} is not supported (sRGB, "
                          f"{', '.join(LINEAR_COLORSPACES)}); it renders magenta", stacklevel=4)
            return magenta, False, 0
        try:
            pixels = read_image_file(node.image) if isinstance(node.image, str | Path) else np.asarray(node.image)
            if pixels.ndim < 2 or pixels.shape[0] == 0 or pixels.shape[1] == 0:
                raise ImageReadError(f"the image is empty ({pixels.shape[1] if pixels.ndim >= 2 else 0}x"
                                     f"{pixels.shape[0] if pixels.ndim >= 1 else 0})")
            encoded = node.colorspace == "sRGB" and pixels.dtype == np.uint8
            texels = to_linear_rgba(pixels, "Non-Color" if encoded else node.colorspace)
        except ImageReadError as exc:
            warnings.warn(f"{label}: image {name}: {exc}; it renders magenta", stacklevel=4)
            return magenta, False, 0
        bad = ~np.isfinite(texels)
        n = 0
        if bad.any():
            n = int(bad.any(axis=2).sum())
            texels[bad] = 0.0
            warnings.warn(f"{label}: image {name}: {n} texels hold NaN or Inf; they are set to 0", stacklevel=4)
        return texels, encoded, n


def _post_order(node: object, out: list[object], done: set[int], path: list[object], label: str) -> None:
    """Append node's sub-graph to out, inputs first, each node once; a node reached again through its own inputs is
    a loop."""
    if id(node) in done:
        return
    if any(p is node for p in path):
        start = next(k for k, p in enumerate(path) if p is node)
        names = " -> ".join(type(p).__name__ for p in [*path[start:], node])
        raise SceneError(f"{label}: its texture nodes form a loop ({names})")
    path.append(node)
    for value in node_inputs(node):
        if is_texture(value):
            _post_order(value, out, done, path, label)
    path.pop()
    done.add(id(node))
    out.append(node)


def uses_uv_map(m: Material) -> bool:
    """Whether some texture node of m reads the UV map (an Image or Checker on "uv", or a Normal Map)."""
    return any(isinstance(n, NormalMap) or (isinstance(n, ImageTexture | CheckerTexture) and n.coords == "uv")
               for n in texture_nodes(m))


def warn_missing_uv_maps(meshes: list, materials: list[Material]) -> None:
    """A mesh without a UV map whose material reads one: its UVs are (0, 0), as in Blender, and a normal map leaves
    its normal unchanged; worth a warning naming both, once each."""
    for mesh in meshes:
        if mesh.uvs is not None or len(mesh.material_ids) == 0:
            continue
        for i in np.unique(mesh.material_ids):
            m = materials[int(i)]
            if uses_uv_map(m):
                warnings.warn(f"mesh {mesh.name!r} has no UV map but material {int(i)} {m.name!r} reads one: its "
                              f"UV textures read (0, 0) there and its normal map does nothing", stacklevel=3)


def warn_textured_emission(meshes: list, materials: list[Material]) -> None:
    """A mesh whose material has a textured emission that the host cannot average (another node than an Image
    Texture on the UV map: lights/textured_emission.py): camera rays see the texture, but as a light each of its
    triangles shines with the constant bound, white times Emission Strength (Material.radiance): it lights other
    surfaces as if it were white (docs/textures.md). Worth a warning naming the material, once each."""
    used = {int(i) for mesh in meshes for i in np.unique(mesh.material_ids)}
    for i in sorted(used):
        m = materials[i]
        if is_texture(m.emission) and m.emission_strength > 0 and sampled_emission(m) is None:
            warnings.warn(f"material {i} {m.name!r} has a textured emission: the camera sees the texture, but it "
                          f"lights other surfaces as if it were white, with strength {m.emission_strength:g} (only "
                          f"an Image Texture on the UV map lights them by its texels)", stacklevel=3)
