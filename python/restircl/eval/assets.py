"""Real assets that nobody here made (Khronos' glTF sample models and models users share), kept out of the repository:
the tests that use one find it in the folder `$RESTIRCL_ASSETS` names, else in ~/.cache/restircl/assets, and skip
with the reason when it is absent; tools/fetch_assets.py downloads them there, or copies a file given by path,
checking its sha256."""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

KHRONOS = "https://raw.githubusercontent.com/KhronosGroup/glTF-Sample-Assets/main/Models"
RAW = "https://raw.githubusercontent.com"


@dataclass(frozen=True)
class Asset:
    """A file the tests know by name: where it is published, and the sha256 digests of the copies accepted (the
    published file's digest is added once it has been seen; a re-export of the same model is recorded with its own
    digest and size, since its bytes differ)."""

    name: str
    url: str
    sha256: tuple[str, ...]
    note: str = ""


ASSETS: dict[str, Asset] = {a.name: a for a in (
    Asset("DamagedHelmet.glb", f"{KHRONOS}/DamagedHelmet/glTF-Binary/DamagedHelmet.glb",
          ("2822d55c9e75e3015fb3f7f810e6b9b827284f1c9f838f984cb21ebabc7bbf4d",),
          "the copy at hand is a re-export by THREE.GLTFExporter: 3439796 bytes, five 2048x2048 JPEG images"),
    Asset("WaterBottle.glb", f"{RAW}/shosuz-evangelist/3dObjects4Apps/3597e0e061de3b5e114570a978c24e729bb654ed/"
          "WaterBottle.glb", ("b5e9cddca3c630c06c9a9c3eccf208f320f8e886e2612027c5c310e6d8ea32e5",),
          "Khronos' WaterBottle as a user re-exported it (Blender glTF I/O 0.9.36): 1166024 bytes, base colour, "
          "packed occlusion-roughness-metallic and normal PNG images, no emissive map"),
    Asset("Avocado.glb", f"{RAW}/LettersDev/3d/d8999ffac207c34288d3d2011b247241d8244261/Avocado.glb",
          ("064847b81a70715af9de7607a02b8e7fb8df8e1fc4aa6aa0da2646e124fcc6d8",),
          "a user's model named Avocado (a card with a front and a back image; Blender glTF I/O 5.1.19, not "
          "Khronos' Avocado): 484268 bytes, two materials with a base colour image each, the back's mirrored by "
          "KHR_texture_transform (a Mapping node)"),
)}


def folder() -> Path:
    """Where assets are looked for and fetched to."""
    env = os.environ.get("RESTIRCL_ASSETS")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "restircl" / "assets"


def sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def find(name: str) -> tuple[Path | None, str]:
    """(the asset's path, "") when it is in folder(), else (None, why not): a sentence for a test's skip."""
    if name not in ASSETS:
        raise KeyError(f"unknown asset {name!r}: known are {sorted(ASSETS)}")
    path = folder() / name
    if not path.is_file():
        return None, (f"asset {name} is not in {folder()} (set RESTIRCL_ASSETS to its folder, or run "
                      f"tools/fetch_assets.py {name})")
    return path, ""
