"""tools/build_extension.py packs the whole add-on, its export/ package included, into a zip that imports."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
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



def _fake_wheel(folder: Path, name: str) -> None:
    with zipfile.ZipFile(folder / name, "w") as z:
        z.writestr(name.split("-")[0] + "-1.0.dist-info/WHEEL", "Wheel-Version: 1.0\n")


def test_each_distribution_needs_a_wheel_for_every_python(tmp_path):
    tool = _tool()
    for name in ("restircl-0.1.0-py3-none-any.whl", "pyopencl-1.0-cp311-cp311-manylinux_2_28_x86_64.whl",
                 "pyopencl-1.0-cp313-cp313-manylinux_2_28_x86_64.whl",
                 "siphash24-1.0-cp311-cp311-manylinux2014_x86_64.whl"):
        _fake_wheel(tmp_path, name)
    with pytest.raises(SystemExit, match="siphash24: no wheel for CPython 3.13"):
        tool.check_wheels(tmp_path, ["3.11", "3.13"])
    _fake_wheel(tmp_path, "siphash24-1.0-cp313-cp313-manylinux2014_x86_64.whl")
    assert len(tool.check_wheels(tmp_path, ["3.11", "3.13"])) == 5
    with pytest.raises(SystemExit, match="cp313.*installs on none"):  # a wheel no target Python can use
        tool.check_wheels(tmp_path, ["3.11"])
    _fake_wheel(tmp_path, "pyopencl-1.0-cp313-cp313-win_amd64.whl")
    with pytest.raises(SystemExit, match="win_amd64.*installs on none"):
        tool.check_wheels(tmp_path, ["3.11", "3.13"])


def test_blender_range_follows_the_pythons():
    """3.11 alone: 4.2.0 up to (not including) 5.1.0; 3.13 alone: 5.1.0 on; both: from the first release that
    picks wheels per Python."""
    tool = _tool()
    assert tool.blender_range(["3.11"]) == ("4.2.0", "5.1.0")
    assert tool.blender_range(["3.13"]) == ("5.1.0", None)
    assert tool.blender_range(["3.11", "3.13"]) == (tool.PER_PYTHON_WHEELS_MIN, None)
    with pytest.raises(SystemExit, match="3.12"):
        tool.blender_range(["3.12"])


def test_manifest_gets_the_wheels_and_the_range(tmp_path):
    import tomllib

    tool = _tool()
    staged = tool.stage(tmp_path)
    wheels = ["./wheels/restircl-0.1.0-py3-none-any.whl"]
    tool.write_manifest(staged, wheels, ["3.11"])
    meta = tomllib.loads((staged / "blender_manifest.toml").read_text())
    assert (meta["wheels"], meta["platforms"]) == (wheels, ["linux-x64"])
    assert (meta["blender_version_min"], meta["blender_version_max"]) == ("4.2.0", "5.1.0")
    tool.write_manifest(staged, wheels, ["3.11", "3.13"])  # rewriting drops the max
    meta = tomllib.loads((staged / "blender_manifest.toml").read_text())
    assert meta["blender_version_min"] == tool.PER_PYTHON_WHEELS_MIN and "blender_version_max" not in meta
