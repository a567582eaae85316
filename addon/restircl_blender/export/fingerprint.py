"""A hash of an exported scene, walked through its dataclass fields.

The engine keeps a still render's Renderer (uploaded scene, compiled kernels) when the next export has the same
fingerprint, so whatever the renderer reads must be in it. Deriving it from `dataclasses.fields` rather than a
list of names means a field added to Scene, Mesh, Material, Light or Camera is covered without touching this
file. It covers what dataclass equality compares (fields declared with compare=False are left out), names
included: a renamed object builds a new renderer, which costs time but never shows a stale image."""

from __future__ import annotations

import dataclasses
import hashlib

import numpy as np


def fingerprint(**parts) -> str:
    """A hex digest of the named parts (dataclasses, arrays, sequences and plain values, nested)."""
    h = hashlib.blake2b(digest_size=16)
    for name, value in parts.items():
        h.update(f"{name}=".encode())
        _feed(h, value, name)
    return h.hexdigest()


def _feed(h, value, where: str) -> None:
    """Add `value` to the hash, its type and structure included (so [1], [2] and [1, 2] differ); `where` names
    it in the error for a value that has no stable hash."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        h.update(f"<{type(value).__name__}>".encode())
        for f in dataclasses.fields(value):
            if f.compare:
                h.update(f"{f.name}=".encode())
                _feed(h, getattr(value, f.name), f"{where}.{f.name}")
    elif isinstance(value, np.ndarray):
        if value.dtype.hasobject:
            raise TypeError(f"fingerprint: {where} is an array of Python objects, which has no stable hash")
        h.update(f"ndarray{value.dtype.str}{value.shape}".encode())
        h.update(np.ascontiguousarray(value).tobytes())
    elif isinstance(value, list | tuple):
        h.update(f"{type(value).__name__}{len(value)}(".encode())
        for i, item in enumerate(value):
            _feed(h, item, f"{where}[{i}]")
        h.update(b")")
    elif isinstance(value, dict):
        h.update(f"dict{len(value)}(".encode())
        for key in sorted(value):
            _feed(h, key, f"{where} key")
            _feed(h, value[key], f"{where}[{key!r}]")
        h.update(b")")
    elif value is None or isinstance(value, bool | int | float | str | np.generic):
        h.update(f"{type(value).__name__}:{value!r};".encode())
    else:
        raise TypeError(f"fingerprint: {where} is a {type(value).__name__}, which has no stable hash")
