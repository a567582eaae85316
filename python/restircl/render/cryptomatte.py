"""Cryptomatte (Settings.cryptomatte_levels; the object, material and asset layers Blender offers), written from the
Cryptomatte specification (Psyop, 2015): every name becomes a 32-bit MurmurHash3 (x86, seed 0) of its UTF-8 bytes,
stored as the float32 of the same bits (a hash whose exponent is 0 or 255, a denormal, infinity or NaN, has its
exponent's lowest bit flipped); per pixel the ids of what its samples showed are ranked by coverage (the share of
the samples), and rank k goes to layer k // 2, channels (r, g) for even k and (b, a) for odd ones: id, coverage.
The manifest maps each name to its hash as 8 hex digits (Cycles' manifest holds the hash before the exponent
rule, and so does ours: a name whose hash had its exponent bit flipped has the flipped float in the pixels and the
plain hash in the manifest, which decoders hash again anyway); the layer's metadata key is the first 7 hex digits of the
hash of the layer's name ("ViewLayer.CryptoObject").

The samples' ids come from opencl/film/cryptomatte.cl: per pixel and kind (object, material) `levels` slots of
(id + 1, samples) filled as the still's frames come; an id that finds every slot taken by others is not counted
(a pixel showing more objects than the levels keeps the first ones). Assets are objects merged by their asset name
(Mesh.asset: the root of its parent chain in Blender, else its own name)."""

from __future__ import annotations

import json
import struct

import numpy as np

from ..lights.linking import OBJECT_BITS

KINDS = ("object", "material", "asset")
LAYER_SUFFIX = {"object": "CryptoObject", "material": "CryptoMaterial", "asset": "CryptoAsset"}


def murmur3_32(data: bytes, seed: int = 0) -> int:
    """MurmurHash3 x86 32-bit of `data`."""
    c1, c2, mask = 0xCC9E2D51, 0x1B873593, 0xFFFFFFFF
    h = seed & mask
    n = len(data) // 4
    for k, in struct.iter_unpack("<I", data[:4 * n]):
        k = (k * c1) & mask
        k = ((k << 15) | (k >> 17)) & mask
        k = (k * c2) & mask
        h ^= k
        h = ((h << 13) | (h >> 19)) & mask
        h = (h * 5 + 0xE6546B64) & mask
    tail = data[4 * n:]
    if tail:
        k = int.from_bytes(tail, "little")
        k = (k * c1) & mask
        k = ((k << 15) | (k >> 17)) & mask
        k = (k * c2) & mask
        h ^= k
    h ^= len(data)
    h ^= h >> 16
    h = (h * 0x85EBCA6B) & mask
    h ^= h >> 13
    h = (h * 0xC2B2AE35) & mask
    h ^= h >> 16
    return h


def name_hash(name: str) -> int:
    """The id of `name` as uint32 bits, its exponent kept off 0 and 255."""
    h = murmur3_32(name.encode("utf-8"))
    exponent = (h >> 23) & 0xFF
    if exponent in (0, 255):
        h ^= 1 << 23
    return h


def name_id(name: str) -> float:
    """The id of `name` as the float32 the passes hold."""
    return float(np.array([name_hash(name)], np.uint32).view(np.float32)[0])


def manifest(names: list[str]) -> str:
    """The manifest: JSON of name -> 8 hex digits of its MurmurHash3, as Cycles writes it (the hash itself, before
    the exponent rule turns it into the pixels' float)."""
    return json.dumps({n: f"{murmur3_32(n.encode('utf-8')):08x}" for n in sorted(set(names))}, separators=(",", ":"))


def layer_key(layer_name: str) -> str:
    """The metadata key of a layer: cryptomatte/<this>/name, .../manifest, ..."""
    return f"{murmur3_32(layer_name.encode('utf-8')):08x}"[:7]


def metadata(layer_name: str, names: list[str]) -> dict[str, str]:
    """The metadata of one Cryptomatte layer (the render result's or the EXR's header)."""
    key = f"cryptomatte/{layer_key(layer_name)}"
    return {f"{key}/name": layer_name, f"{key}/hash": "MurmurHash3_32", f"{key}/conversion": "uint32_to_float32",
            f"{key}/manifest": manifest(names)}


def kind_names(scene, kind: str) -> list[str]:
    """The names of the ids of `kind` by index: objects (meshes), materials, or assets by object."""
    if kind == "object":
        return [m.name for m in scene.meshes]
    if kind == "material":
        return [m.name for m in scene.materials]
    return [m.asset or m.name for m in scene.meshes]


def ranked(slots: np.ndarray, total: int, names: list[str], levels: int) -> np.ndarray:
    """(H, W, 2 * levels) float32 of one kind from its slots ((H, W, S, 2) uint32: id + 1, samples), the ids
    mapped through `names` (ids of equal names merge: assets), ranked by coverage = samples / total."""
    h, w, s, _ = slots.shape
    ids = slots[..., 0].astype(np.int64) - 1
    counts = slots[..., 1].astype(np.float64)
    hashes = np.array([name_id(n) for n in names] or [0.0], np.float32)
    key = np.where(ids >= 0, hashes[np.clip(ids, 0, len(hashes) - 1)].view(np.uint32).astype(np.int64), -1)
    # merge slots of one hash (assets), then order by coverage, largest first
    for a in range(s):
        for b in range(a + 1, s):
            same = (key[..., a] >= 0) & (key[..., a] == key[..., b])
            counts[..., a] += np.where(same, counts[..., b], 0.0)
            counts[..., b] = np.where(same, 0.0, counts[..., b])
            key[..., b] = np.where(same, -1, key[..., b])
    counts = np.where(key >= 0, counts, 0.0)
    order = np.argsort(-counts, axis=-1, kind="stable")
    key = np.take_along_axis(key, order, axis=-1)
    cov = np.take_along_axis(counts, order, axis=-1) / max(total, 1)
    out = np.zeros((h, w, 2 * levels), np.float32)
    for k in range(min(levels, s)):
        valid = key[..., k] >= 0
        out[..., 2 * k] = np.where(valid, key[..., k], 0).astype(np.uint32).view(np.float32)
        out[..., 2 * k + 1] = np.where(valid, cov[..., k], 0.0)
    return out


def layers(scene, slots: np.ndarray, total: int, levels: int) -> dict[str, np.ndarray]:
    """Every kind's ranked ids (ranked) from the slots of objects and materials ((2, H, W, S, 2) uint32)."""
    return {"object": ranked(slots[0], total, kind_names(scene, "object"), levels),
            "material": ranked(slots[1], total, kind_names(scene, "material"), levels),
            "asset": ranked(slots[0], total, kind_names(scene, "asset"), levels)}


def from_gbuffer(g: np.ndarray, scene, levels: int) -> dict[str, np.ndarray]:
    """The layers of one frame's G-buffer (one sample per pixel: coverage 1 for what it hit)."""
    hit = g["normal"][..., 3].view(np.int32) >= 0
    obj = (g["albedo"][..., 3].view(np.int32) & ((1 << OBJECT_BITS) - 1)).astype(np.uint32) + 1
    mat = g["gnormal"][..., 3].view(np.int32).astype(np.uint32) + 1
    slots = np.zeros((2, *hit.shape, max(levels, 1), 2), np.uint32)
    for k, ids in enumerate((obj, mat)):
        slots[k, ..., 0, 0] = np.where(hit, ids, 0)
        slots[k, ..., 0, 1] = hit
    return layers(scene, slots, 1, levels)
