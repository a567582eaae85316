"""The errors a bad scene raises: each message names the offending object."""

from __future__ import annotations


class SceneError(ValueError):
    """The scene is invalid; the message names the offending object."""


class SceneFileError(SceneError):
    """A scene file is corrupt, foreign or of an unknown version."""
