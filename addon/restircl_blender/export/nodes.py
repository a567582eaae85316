"""Walking a Blender shader node graph: what feeds a socket, through reroutes, muted nodes and node groups.

Socket names differ between Blender versions (Principled's "Emission" became "Emission Color" in 4.0, the Mix
node's sockets carry a type suffix in their identifiers), so inputs are looked up by a list of identifiers and
names, first match wins."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

MAX_DEPTH = 48  # nested groups or chained nodes deeper than this are taken for a loop


class NodeLoop(Exception):
    """The graph links back into itself (or is deeper than MAX_DEPTH)."""


@dataclass(frozen=True)
class Source:
    """What feeds an input: the output socket `socket` of `node` (groups entered are on `stack`), or, when
    `node` is None, nothing: `socket` is then the unlinked input whose default value applies."""

    socket: object
    node: object | None
    stack: tuple = ()

    @property
    def linked(self) -> bool:
        return self.node is not None

    @property
    def kind(self) -> str:
        return self.node.bl_idname if self.node is not None else ""

    def label(self) -> str:
        return node_label(self.node) if self.node is not None else "a value"


def node_label(node) -> str:
    return (getattr(node, "bl_label", "") or node.bl_idname) if node is not None else "?"


def find_input(node, names: Sequence[str]):
    """The first enabled input of `node` whose identifier or name is in `names` (None if there is none)."""
    for name in names:
        for sock in node.inputs:
            if sock.identifier == name and getattr(sock, "enabled", True):
                return sock
    for name in names:
        for sock in node.inputs:
            if sock.name == name and getattr(sock, "enabled", True):
                return sock
    return None


def _group_output(tree):
    outs = [n for n in tree.nodes if n.bl_idname == "NodeGroupOutput"]
    for n in outs:
        if getattr(n, "is_active_output", False):
            return n
    return outs[0] if outs else None


def _index(sockets, sock) -> int:
    for i, s in enumerate(sockets):
        if s == sock:
            return i
    return -1


def resolve(socket, stack: tuple = ()) -> Source:
    """The node output feeding input `socket`, passing through reroutes, muted nodes (by their internal links),
    node groups (into the group's output) and group inputs (back out to the group node's input). An invalid or
    muted link counts as no link (Blender's own rule). Raises NodeLoop on a cycle."""
    seen = 0
    while True:
        seen += 1
        if seen > 4 * MAX_DEPTH or len(stack) > MAX_DEPTH:
            raise NodeLoop
        if not socket.is_linked:
            return Source(socket, None, stack)
        link = socket.links[0]
        if not link.is_valid:
            raise NodeLoop
        if link.is_muted:
            return Source(socket, None, stack)
        node, out = link.from_node, link.from_socket
        if node.bl_idname == "NodeReroute":
            socket = node.inputs[0]
        elif node.mute:
            inner = next((lk.from_socket for lk in node.internal_links if lk.to_socket == out), None)
            if inner is None:
                return Source(out, node, stack)  # a muted node with nothing passed through: the caller's zero
            socket = inner
        elif node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
            gout = _group_output(node.node_tree)
            i = _index(node.outputs, out)
            if gout is None or i < 0 or i >= len(gout.inputs):
                return Source(out, node, stack)
            if any(g == node.node_tree for g in (s.node_tree for s in stack)):
                raise NodeLoop
            socket, stack = gout.inputs[i], (*stack, node)
        elif node.bl_idname == "NodeGroupInput" and stack:
            i = _index(node.outputs, out)
            group = stack[-1]
            if i < 0 or i >= len(group.inputs):
                return Source(socket, None, stack)
            socket, stack = group.inputs[i], stack[:-1]
        else:
            return Source(out, node, stack)


def default_rgb(socket) -> tuple[float, float, float]:
    v = socket.default_value
    if hasattr(v, "__len__"):
        if len(v) >= 3:
            return float(v[0]), float(v[1]), float(v[2])
        return (float(v[0]),) * 3
    return (float(v),) * 3


def default_float(socket) -> float:
    v = socket.default_value
    if hasattr(v, "__len__"):  # a colour used as a number: Blender's grey (Rec. 709 luminance)
        return 0.2126 * float(v[0]) + 0.7152 * float(v[1]) + 0.0722 * float(v[2])
    return float(v)


def output_node(tree):
    """The Material Output that Cycles uses (the active one for Cycles, else for all engines)."""
    for target in ("CYCLES", "ALL"):
        try:
            out = tree.get_output_node(target)
        except (TypeError, RuntimeError):
            out = None
        if out is not None:
            return out
    return None
