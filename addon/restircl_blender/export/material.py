"""Blender materials -> restircl.Material: diffuse albedo and emitted radiance, read from the node tree.

What the node reader understands (Diffuse, Principled, Emission, Add and Mix shaders, reroutes, RGB and Value
inputs) is in docs/blender.md; anything else becomes a warning and the nearest diffuse colour."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from .convert import rgb

DEFAULT_ALBEDO = (0.8, 0.8, 0.8)  # Cycles' surface for objects without a material


class MaterialTable:
    """The scene's materials, each Blender material exported once, in the order the meshes first use them."""

    def __init__(self, warn: Callable[[str], None]):
        self._reader = MaterialReader(warn)
        self._index: dict[object, int] = {}
        self.materials: list = []  # restircl.Material

    def id_of(self, mat) -> int:
        """The restircl material index of a Blender material (None: the default surface)."""
        import restircl

        key = mat.original.name if mat is not None and mat.original is not None else (
            mat.name if mat is not None else None)
        if key not in self._index:
            albedo, colour, strength = self._reader.read(mat)
            self._index[key] = len(self.materials)
            self.materials.append(restircl.Material(name=key or "(none)", albedo=albedo, emission=colour,
                                                    emission_strength=strength))
        return self._index[key]

    @property
    def emissive_count(self) -> int:
        return sum(1 for m in self.materials if m.is_emissive)


class MaterialReader:
    """Diffuse albedo and emitted radiance of a Blender material, read from its node tree."""

    def __init__(self, warn: Callable[[str], None]):
        self.warn = warn

    def read(self, mat) -> tuple[tuple, tuple, float]:
        """(albedo, emission colour, emission strength)."""
        if mat is None:
            return DEFAULT_ALBEDO, (0.0, 0.0, 0.0), 0.0
        if mat.node_tree is None:  # (Material.use_nodes is deprecated in Blender 5: node trees always exist)
            return rgb(mat.diffuse_color), (0.0, 0.0, 0.0), 0.0
        tree = mat.node_tree
        out = None
        for target in ("CYCLES", "ALL"):
            try:
                out = tree.get_output_node(target)
            except (TypeError, RuntimeError):
                out = None
            if out is not None:
                break
        if out is None:
            self.warn(f"material {mat.name!r}: no Material Output node; rendered black")
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 0.0
        albedo, emission = self._shader(self._source(out.inputs["Surface"]), mat.name, depth=0)
        albedo = tuple(float(np.clip(a, 0.0, 1.0)) for a in albedo)
        emission = np.maximum(np.asarray(emission, dtype=np.float64), 0.0)
        strength = float(emission.max())
        colour = tuple(float(c / strength) for c in emission) if strength > 0 else (0.0, 0.0, 0.0)
        return albedo, colour, strength

    @staticmethod
    def _source(socket):
        """The node feeding `socket` (through reroutes), or None."""
        while socket is not None and socket.is_linked:
            link = socket.links[0]
            if not link.is_valid or link.is_muted:
                return None
            node = link.from_node
            if node.bl_idname == "NodeReroute":
                socket = node.inputs[0]
                continue
            return node
        return None

    def _colour(self, node, names: Sequence[str], mat_name: str) -> np.ndarray:
        for name in names:
            sock = node.inputs.get(name)
            if sock is None:
                continue
            if not sock.is_linked:
                v = sock.default_value
                return np.array([v[0], v[1], v[2]], dtype=np.float64) if hasattr(v, "__len__") else np.full(3, v)
            src = self._source(sock)
            if src is not None and src.bl_idname == "ShaderNodeRGB":
                v = src.outputs[0].default_value
                return np.array([v[0], v[1], v[2]], dtype=np.float64)
            v = sock.default_value
            self.warn(f"material {mat_name!r}: {node.name} input {name!r} is driven by "
                      f"{src.bl_idname if src else 'a link'}; its unlinked value is used")
            return np.array([v[0], v[1], v[2]], dtype=np.float64)
        return np.array(DEFAULT_ALBEDO)

    def _value(self, node, name: str, mat_name: str, default: float = 0.0) -> float:
        sock = node.inputs.get(name)
        if sock is None:
            return default
        if sock.is_linked:
            src = self._source(sock)
            if src is not None and src.bl_idname == "ShaderNodeValue":
                return float(src.outputs[0].default_value)
            self.warn(f"material {mat_name!r}: {node.name} input {name!r} is linked; its unlinked value is used")
        return float(sock.default_value)

    def _shader(self, node, mat_name: str, depth: int) -> tuple[np.ndarray, np.ndarray]:
        zero = np.zeros(3)
        if node is None or depth > 32:
            return zero, zero
        kind = node.bl_idname
        if node.mute:
            self.warn(f"material {mat_name!r}: muted node {node.name!r} is ignored")
            return zero, zero
        if kind == "ShaderNodeBsdfDiffuse":
            return self._colour(node, ("Color",), mat_name), zero
        if kind == "ShaderNodeBsdfPrincipled":
            albedo = self._colour(node, ("Base Color",), mat_name)
            emission = self._colour(node, ("Emission Color", "Emission"), mat_name) * self._value(
                node, "Emission Strength", mat_name, 1.0)
            for name in ("Metallic", "Transmission Weight", "Transmission"):
                if name in node.inputs and self._value(node, name, mat_name) > 0:
                    self.warn(f"material {mat_name!r}: Principled {name} is not supported; "
                              "the base colour is rendered as diffuse")
                    break
            return albedo, emission
        if kind == "ShaderNodeEmission":
            return zero, self._colour(node, ("Color",), mat_name) * self._value(node, "Strength", mat_name, 1.0)
        if kind == "ShaderNodeAddShader":
            a = self._shader(self._source(node.inputs[0]), mat_name, depth + 1)
            b = self._shader(self._source(node.inputs[1]), mat_name, depth + 1)
            return a[0] + b[0], a[1] + b[1]
        if kind == "ShaderNodeMixShader":
            fac = float(np.clip(self._value(node, "Fac", mat_name, 0.5), 0.0, 1.0))
            a = self._shader(self._source(node.inputs[1]), mat_name, depth + 1)
            b = self._shader(self._source(node.inputs[2]), mat_name, depth + 1)
            return (1 - fac) * a[0] + fac * b[0], (1 - fac) * a[1] + fac * b[1]
        if kind == "ShaderNodeGroup":
            self.warn(f"material {mat_name!r}: node group {node.name!r} is not supported; rendered grey")
            return np.array(DEFAULT_ALBEDO), zero
        names = [n for n in ("Color", "Base Color") if n in node.inputs]
        if names:
            self.warn(f"material {mat_name!r}: {node.bl_label or kind} is not supported; its colour is "
                      "rendered as diffuse")
            return self._colour(node, names, mat_name), zero
        self.warn(f"material {mat_name!r}: {node.bl_label or kind} is not supported; rendered grey")
        return np.array(DEFAULT_ALBEDO), zero
