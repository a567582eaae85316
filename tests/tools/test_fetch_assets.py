"""tools/fetch_assets.py and restircl.eval.assets: assets are found in $RESTIRCL_ASSETS, a copy is kept only when
its sha256 is a recorded (or accepted) one, and the recorded helmet is the file at hand when there is one."""

from __future__ import annotations

import hashlib
import importlib.util
from pathlib import Path

import pytest
from restircl.eval import assets

ROOT = Path(__file__).resolve().parents[2]


def _tool():
    spec = importlib.util.spec_from_file_location("fetch_assets", ROOT / "tools" / "fetch_assets.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_assets_are_looked_for_in_the_folder_the_environment_names(tmp_path, monkeypatch):
    monkeypatch.setenv("RESTIRCL_ASSETS", str(tmp_path))
    path, why = assets.find("DamagedHelmet.glb")
    assert path is None and str(tmp_path) in why and "fetch_assets.py" in why
    (tmp_path / "DamagedHelmet.glb").write_bytes(b"x")
    assert assets.find("DamagedHelmet.glb") == (tmp_path / "DamagedHelmet.glb", "")
    monkeypatch.delenv("RESTIRCL_ASSETS")
    assert assets.folder() == Path.home() / ".cache" / "restircl" / "assets"
    with pytest.raises(KeyError):
        assets.find("NoSuchModel.glb")


def test_a_copy_is_kept_only_with_a_known_digest(tmp_path, monkeypatch):
    monkeypatch.setenv("RESTIRCL_ASSETS", str(tmp_path / "store"))
    src = tmp_path / "helmet.glb"
    src.write_bytes(b"not the helmet")
    tool = _tool()
    assert tool.main(["DamagedHelmet.glb", "--from", str(src)]) == 1
    assert not (tmp_path / "store" / "DamagedHelmet.glb").exists()
    digest = hashlib.sha256(b"not the helmet").hexdigest()
    assert tool.main(["DamagedHelmet.glb", "--from", str(src), "--accept", digest]) == 0
    assert (tmp_path / "store" / "DamagedHelmet.glb").read_bytes() == b"not the helmet"
    assert list((tmp_path / "store").iterdir()) == [tmp_path / "store" / "DamagedHelmet.glb"]


def test_the_recorded_helmet_is_the_file_at_hand():
    path, why = assets.find("DamagedHelmet.glb")
    if path is None:
        pytest.skip(why)
    assert assets.sha256(path) in assets.ASSETS["DamagedHelmet.glb"].sha256
