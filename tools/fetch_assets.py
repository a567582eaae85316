"""Fetch the real assets the tests name (restircl.eval.assets.ASSETS) into the assets folder ($RESTIRCL_ASSETS, else
~/.cache/restircl/assets), each checked against its recorded sha256 digests; a file that fails the check is not kept.

    python tools/fetch_assets.py                          # every known asset, from its public URL
    python tools/fetch_assets.py DamagedHelmet.glb        # the ones named
    python tools/fetch_assets.py DamagedHelmet.glb --from /path/to/DamagedHelmet.glb   # a copy at hand
    python tools/fetch_assets.py DamagedHelmet.glb --accept SHA256   # a digest not recorded yet (say it in ASSETS)
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import urllib.request
from pathlib import Path

from restircl.eval.assets import ASSETS, folder, sha256


def _download(url: str, to: Path) -> None:
    with urllib.request.urlopen(url, timeout=60) as r, open(to, "wb") as f:  # noqa: S310 (a fixed https URL)
        shutil.copyfileobj(r, f)


def fetch(name: str, source: Path | None = None, accept: tuple[str, ...] = ()) -> Path:
    """The asset `name` in folder(), from `source` (a local file) or its URL; ValueError when its digest is not one
    recorded (or accepted)."""
    asset = ASSETS[name]
    dest = folder() / name
    dest.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=dest.parent) as tmp:
        part = Path(tmp) / name
        if source is not None:
            shutil.copyfile(source, part)
        else:
            _download(asset.url, part)
        digest = sha256(part)
        if digest not in asset.sha256 + tuple(accept):
            raise ValueError(f"{name}: sha256 {digest} ({part.stat().st_size} bytes) is not a recorded digest "
                             f"{list(asset.sha256)}; if the file is right, pass --accept {digest} and record it")
        part.replace(dest)
    return dest


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("names", nargs="*", help=f"assets to fetch (default: all of {sorted(ASSETS)})")
    ap.add_argument("--from", dest="source", type=Path, help="copy this local file instead of downloading (one name)")
    ap.add_argument("--accept", action="append", default=[], help="another sha256 to accept")
    args = ap.parse_args(argv)
    names = args.names or sorted(ASSETS)
    unknown = [n for n in names if n not in ASSETS]
    if unknown or (args.source is not None and len(names) != 1):
        ap.error(f"unknown assets {unknown}" if unknown else "--from takes exactly one asset name")
    failed = 0
    for name in names:
        try:
            print(f"{name}: {fetch(name, args.source, tuple(args.accept))}")
        except (OSError, ValueError) as exc:
            print(f"{name}: not fetched: {exc}", file=sys.stderr)
            failed += 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
