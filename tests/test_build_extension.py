"""tools/build_extension.py packs the whole add-on, its export/ package included, into a zip that imports."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
ADDON = ROOT / "addon" / "restircl_blender"


def _tool():
    spec = importlib.util.spec_from_file_location("build_extension", ROOT / "tools" / "build_extension.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def built_zip(tmp_path_factory) -> Path:
    """The zip without wheels (those need pip downloads): what the extension builder makes of the add-on."""
    tool = _tool()
    build = tmp_path_factory.mktemp("build")
    return tool.build_zip(tool.stage(build), build)


def test_zip_holds_every_addon_source(built_zip):
    sources = {p.relative_to(ADDON).as_posix() for p in ADDON.rglob("*")
               if p.is_file() and "__pycache__" not in p.parts and p.suffix in (".py", ".toml")}
    names = set(zipfile.ZipFile(built_zip).namelist())
    assert {"export/__init__.py", "export/scene.py", "export/mesh.py", "export/light.py"} <= sources
    assert sources <= names, sorted(sources - names)
    assert not [n for n in names if "__pycache__" in n or n.endswith(".pyc")]


def test_zipped_addon_imports_its_export(built_zip, tmp_path):
    pytest.importorskip("bpy")
    pkg = tmp_path / "restircl_blender"
    zipfile.ZipFile(built_zip).extractall(pkg)
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import restircl_blender.export as e; "
            "assert e.__file__.startswith(sys.argv[1]), e.__file__; "
            "print(e.export_scene.__name__, e.Export.__name__, e.ExportError.__name__, e.render_resolution.__name__)")
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    # the last line: Blender 5.3 may log its colour management set-up to stdout first
    assert out.stdout.splitlines()[-1].split() == ["export_scene", "Export", "ExportError", "render_resolution"]
