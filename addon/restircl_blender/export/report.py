"""How the export tells what it cannot do: ExportError when the scene cannot be rendered at all, Warnings for
what is rendered differently (the engine shows them with RenderEngine.report)."""

from __future__ import annotations


class ExportError(Exception):
    """The Blender scene cannot be exported (no camera, unsupported camera type, ...)."""


class Warnings(list[str]):
    """Warning messages in the order they were first given; a message given again is not repeated (a setting
    shared by many objects would otherwise fill the report)."""

    def add(self, msg: str) -> None:
        if msg not in self:
            self.append(msg)
