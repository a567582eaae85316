"""Materials and texture nodes in the scene file (scene/file.py): JSON-able dicts in its header, image arrays beside
the other arrays. Texture nodes go into one table per file so that a node shared by two inputs stays shared."""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np

from .material import Material
from .textures import TEXTURE_TYPES, is_texture

NODE_TYPES = {t.__name__: t for t in TEXTURE_TYPES}
_VALUE_FIELDS = ("albedo", "emission", "metallic", "roughness", "specular", "specular_tint", "normal", "mix",
                 "alpha")


class MaterialWriter:
    """Collects the node table and the image arrays while materials are encoded."""

    def __init__(self, arrays: dict[str, np.ndarray]) -> None:
        self.arrays = arrays
        self.nodes: list[dict] = []
        self._index: dict[int, int] = {}

    def material(self, m: Material) -> dict:
        d: dict = {"name": m.name, "kind": m.kind, "ior": float(m.ior), "distribution": m.distribution,
                   "emission_strength": float(m.emission_strength), "transmission": float(m.transmission)}
        if m.thin_wall:
            d["thin_wall"] = True
        if m.thin_film_thickness > 0:  # only where there is a film: files of materials without one stay as they were
            d["thin_film_thickness"] = float(m.thin_film_thickness)
            d["thin_film_ior"] = float(m.thin_film_ior)
        for name in _VALUE_FIELDS:
            d[name] = self.value(getattr(m, name))
        d["layers"] = [self.material(layer) for layer in m.layers]
        return d

    def value(self, v: object) -> object:
        """A constant as a number or a list, a node as {"node": index}, None as None."""
        if v is None:
            return None
        if is_texture(v):
            return {"node": self._node(v)}
        a = np.asarray(v, dtype=np.float64)
        return float(a) if a.ndim == 0 else a.tolist()

    def _node(self, node: object) -> int:
        if id(node) in self._index:
            return self._index[id(node)]
        k = len(self.nodes)
        self._index[id(node)] = k
        d: dict = {"type": type(node).__name__}
        self.nodes.append(d)  # before the inputs: a loop refers back to this index instead of recursing forever
        for f in fields(node):
            v = getattr(node, f.name)
            if f.name == "image":
                if isinstance(v, str | Path):
                    d["image_path"] = str(v)
                else:
                    self.arrays[f"image{k}"] = np.asarray(v)
            elif f.name == "mapping":
                d["mapping"] = None if v is None else np.asarray(v, np.float64).tolist()
            elif isinstance(v, str | bool | int) and not isinstance(v, float):
                d[f.name] = v
            else:
                d[f.name] = self.value(v)
        return k


class MaterialReader:
    """Rebuilds the nodes of a file's node table (shared and looping references included), then materials."""

    def __init__(self, table: list[dict], arrays: dict[str, np.ndarray]) -> None:
        self.nodes = [NODE_TYPES[d["type"]].__new__(NODE_TYPES[d["type"]]) for d in table]
        for k, (node, d) in enumerate(zip(self.nodes, table, strict=True)):
            for f in fields(node):
                if f.name == "image":
                    value = d["image_path"] if "image_path" in d else arrays[f"image{k}"]
                elif f.name == "mapping":
                    value = None if d.get("mapping") is None else np.asarray(d["mapping"], np.float64)
                elif f.name not in d:  # a field newer than the file: the class default stays
                    continue
                else:
                    value = self.value(d[f.name])
                setattr(node, f.name, value)

    def value(self, v: object) -> object:
        if isinstance(v, dict):
            return self.nodes[int(v["node"])]
        if isinstance(v, list):  # a colour, or a list of them (a Color Ramp's stops)
            return tuple(self.value(x) if isinstance(x, list) else float(x) for x in v)
        return v

    def material(self, d: dict) -> Material:
        m = Material(name=d["name"], emission_strength=d["emission_strength"])
        for key in ("kind", "ior", "distribution", "transmission", "thin_wall", "thin_film_thickness", "thin_film_ior"):
            if key in d:
                setattr(m, key, d[key])
        for name in _VALUE_FIELDS:
            if name in d:
                setattr(m, name, self.value(d[name]))
        m.layers = [self.material(layer) for layer in d.get("layers", [])]
        return m


