"""Blender materials -> restircl.Material, read from the node tree along the Material Output's Surface link.

    nodes.py    walking the graph: reroutes, muted nodes, node groups, socket names across Blender versions
    shaders.py  shader nodes -> weighted closures and emissions (Principled, Diffuse, Glossy, Metallic, Emission,
                Mix Shader, Add Shader)
    layers.py   those terms -> one Material of at most MAX_LAYERS closures
    inputs.py   colour and value inputs -> constants or texture nodes (coords.py: texture coordinates and the
                Mapping node; images.py: Blender images)
    bake.py     any other node graph feeding an input, baked to an image with Cycles
    notes.py    what could not be represented, said once per material

docs/blender.md lists which node types are native, baked or ignored."""

from __future__ import annotations

from collections.abc import Callable

from ..compat import uses_nodes
from .convert import rgb
from .inputs import InputReader
from .layers import assemble
from .nodes import find_input, output_node
from .notes import Notes
from .shaders import ShaderReader

DEFAULT_ALBEDO = (0.8, 0.8, 0.8)  # Cycles' surface for objects without a material


class MaterialTable:
    """The scene's materials, each Blender material exported once, in the order the meshes first use them; once
    more for objects without a UV map when its textures need one, and once per object when it bakes (a bake is
    laid out on the object's own UV map)."""

    def __init__(self, warn: Callable[[str], None], bake_resolution: int = 0):
        self.warn = warn
        self.bake_resolution = bake_resolution  # 0: no baking
        self._index: dict[tuple, int] = {}
        self._per_object: set[str] = set()  # materials that bake
        self.materials: list = []  # restircl.Material
        self.uses_uv: list[bool] = []  # per material: some texture reads the UV map
        self.uv_maps: list[set[str]] = []  # per material: UV maps its nodes name
        self._reads: list[tuple[str | None, bool, str | None]] = []  # per material: id_of's (name, has_uv, object)

    def id_of(self, mat, ob=None, has_uv: bool = True) -> int:
        """The restircl material index of a Blender material (None: the default surface) on object `ob`."""
        name = _key(mat)
        key: tuple = (name, has_uv)
        if name in self._per_object:
            key = (name, has_uv, ob.name if ob is not None else "")
        if key not in self._index:
            m, inputs, baked = self._read(mat, name, ob, has_uv)
            if mat is not None and hasattr(m, "pass_index"):
                m.pass_index = int(getattr(mat, "pass_index", 0))
            if baked:
                self._per_object.add(name)
                key = (name, has_uv, ob.name if ob is not None else "")
            self._index[key] = len(self.materials)
            self.materials.append(m)
            self.uses_uv.append(inputs is not None and inputs.uses_uv)
            self.uv_maps.append(inputs.uv_maps if inputs is not None else set())
            self._reads.append((name, has_uv, ob.name if ob is not None else None))
        return self._index[key]

    @property
    def reads(self) -> list[tuple]:
        """Per material: (Blender material name, the object has a UV map, the object it was read for, it reads the
        UV map, the UV maps it names): what read_again needs, and what the meshes' export depends on."""
        return [(*r, uses, frozenset(maps)) for r, uses, maps in zip(self._reads, self.uses_uv, self.uv_maps,
                                                                       strict=True)]

    def read_again(self, reads: list[tuple], materials: dict, objects: dict) -> bool:
        """Read the materials of an earlier table's `reads` again, in its order (a viewport edit of materials
        alone): `materials` and `objects` by name. False when that table's layout no longer holds (a material is
        gone, starts or stops reading the UV map or baking): the meshes must be exported again."""
        for name, has_uv, ob_name, _uses, _maps in reads:
            if (name is not None and name not in materials) or (ob_name is not None and ob_name not in objects):
                return False
            self.id_of(materials.get(name), objects.get(ob_name), has_uv)
        return self.reads == reads

    @property
    def emissive_count(self) -> int:
        return sum(1 for m in self.materials if m.is_emissive)

    def _read(self, mat, name: str, ob, has_uv: bool):
        """(Material, its InputReader (None without a node tree), was baked)."""
        import restircl

        if mat is None:
            return restircl.Material(name="(none)", kind="diffuse", albedo=DEFAULT_ALBEDO), None, False
        tree = mat.node_tree if uses_nodes(mat) else None
        if tree is None:  # Cycles renders a material without nodes as a diffuse of its viewport colour
            return restircl.Material(name=name, kind="diffuse", albedo=rgb(mat.diffuse_color)), None, False
        out = output_node(tree)
        if out is None:
            self.warn(f"material {name!r}: no Material Output node; rendered black")
            return restircl.Material(name=name, kind="diffuse", albedo=(0.0, 0.0, 0.0)), None, False
        notes = Notes(name, self.warn)
        baker = None
        if self.bake_resolution > 0 and ob is not None:
            from .bake import Baker

            baker = Baker(mat, ob, self.bake_resolution, notes)
        inputs = InputReader(notes, has_uv, baker)
        terms = ShaderReader(inputs, notes).terms(find_input(out, ("Surface",)))
        for what in ("Volume", "Displacement"):
            sock = find_input(out, (what,))
            if sock is not None and sock.is_linked:
                notes.lobe(f"{what.lower()} (Material Output)")
        m = assemble(name, terms, notes)
        notes.flush()
        return m, inputs, baker is not None and baker.count > 0


def _key(mat) -> str | None:
    if mat is None:
        return None
    return mat.original.name if mat.original is not None else mat.name


def scene_bake_resolution(scene) -> int:
    """The scene's `bake_resolution` setting (the settings table's default where the add-on is not registered)."""
    from restircl import Settings

    props = getattr(scene, "restircl", None)
    return int(getattr(props, "bake_resolution", Settings.bake_resolution))
