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
    return tool.build_zips(tool.stage(build), build)[0]


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
    linux = ["linux-x64"]
    for name in ("restircl-0.1.0-py3-none-any.whl", "pyopencl-1.0-cp311-cp311-manylinux_2_28_x86_64.whl",
                 "pyopencl-1.0-cp313-cp313-manylinux_2_28_x86_64.whl",
                 "siphash24-1.0-cp311-cp311-manylinux2014_x86_64.whl"):
        _fake_wheel(tmp_path, name)
    with pytest.raises(SystemExit, match="siphash24: no wheel for linux-x64, CPython 3.13"):
        tool.check_wheels(tmp_path, ["3.11", "3.13"], linux)
    _fake_wheel(tmp_path, "siphash24-1.0-cp313-cp313-manylinux2014_x86_64.whl")
    assert len(tool.check_wheels(tmp_path, ["3.11", "3.13"], linux)) == 5
    with pytest.raises(SystemExit, match="cp313.*installs on none"):  # a wheel no target Python can use
        tool.check_wheels(tmp_path, ["3.11"], linux)
    _fake_wheel(tmp_path, "pyopencl-1.0-cp313-cp313-win_amd64.whl")
    with pytest.raises(SystemExit, match="win_amd64.*installs on none"):  # a wheel of a platform not built
        tool.check_wheels(tmp_path, ["3.11", "3.13"], linux)
    with pytest.raises(SystemExit, match="pyopencl: no wheel for windows-x64, CPython 3.11"):
        tool.check_wheels(tmp_path, ["3.11", "3.13"], linux + ["windows-x64"],
                          {"linux-x64": ["pyopencl"], "windows-x64": ["pyopencl"]})


def test_wheel_platforms_read_the_tags():
    tool = _tool()
    assert tool.wheel_platforms("a-1-py3-none-any.whl") == {"linux-x64", "windows-x64", "macos-arm64", "macos-x64"}
    assert tool.wheel_platforms("a-1-cp311-cp311-manylinux_2_17_x86_64.manylinux2014_x86_64.whl") == {"linux-x64"}
    assert tool.wheel_platforms("a-1-cp311-cp311-manylinux2014_aarch64.whl") == set()
    assert tool.wheel_platforms("a-1-cp311-cp311-win_amd64.whl") == {"windows-x64"}
    assert tool.wheel_platforms("a-1-cp311-cp311-win32.whl") == set()
    assert tool.wheel_platforms("a-1-py3-none-macosx_12_0_arm64.whl") == {"macos-arm64"}
    assert tool.wheel_platforms("a-1-cp313-cp313-macosx_10_13_x86_64.whl") == {"macos-x64"}
    assert tool.wheel_platforms("a-1-cp311-cp311-macosx_10_9_universal2.whl") == {"macos-arm64", "macos-x64"}
    assert tool.wheel_pythons("a-1-cp311-abi3-win_amd64.whl", ["3.11", "3.13"]) == {"3.11", "3.13"}
    assert tool.wheel_pythons("a-1-cp312-cp312-win_amd64.whl", ["3.11", "3.13"]) == set()


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
    assert (meta["wheels"], meta["platforms"]) == (wheels, ["linux-x64"])  # the default
    assert (meta["blender_version_min"], meta["blender_version_max"]) == ("4.2.0", "5.1.0")
    tool.write_manifest(staged, wheels, ["3.11", "3.13"])  # rewriting drops the max
    meta = tomllib.loads((staged / "blender_manifest.toml").read_text())
    assert meta["blender_version_min"] == tool.PER_PYTHON_WHEELS_MIN and "blender_version_max" not in meta


# The fake wheel set of a whole build: each platform's tag, the distributions built per CPython, the pure-Python
# ones, pyoidn (one wheel per platform for every Python 3) and PoCL (Linux only); plus decoys the build must leave
# out: an older pyopencl, a CPython 3.12 one, a Linux ARM one, a 32-bit Windows pillow.
FAKE_TAGS = {"linux-x64": "manylinux_2_28_x86_64", "windows-x64": "win_amd64", "macos-arm64": "macosx_11_0_arm64",
             "macos-x64": "macosx_10_15_x86_64"}
FAKE_DECOYS = ("pyopencl-1.0-cp311-cp311-win_amd64.whl", "pyopencl-2.0-cp312-cp312-win_amd64.whl",
               "pyopencl-2.0-cp311-cp311-manylinux2014_aarch64.whl", "pillow-2.0-cp311-cp311-win32.whl")


def _fake_wheel_set(folder: Path) -> Path:
    folder.mkdir()
    for tag in FAKE_TAGS.values():
        for cp in ("cp311", "cp313"):
            for dist in ("pyopencl", "siphash24", "openexr", "pillow", "cffi"):
                _fake_wheel(folder, f"{dist}-2.0-{cp}-{cp}-{tag}.whl")
        _fake_wheel(folder, f"pyoidn-2.0-py3-none-{tag}.whl")
    _fake_wheel(folder, "pocl_binary_distribution-2.0-py2.py3-none-manylinux_2_17_x86_64.manylinux2014_x86_64.whl")
    for dist in ("pytools", "platformdirs", "typing_extensions", "pycparser"):
        _fake_wheel(folder, f"{dist}-2.0-py3-none-any.whl")
    for name in FAKE_DECOYS:
        _fake_wheel(folder, name)
    restircl = folder.parent / "restircl-0.1.0-py3-none-any.whl"
    _fake_wheel(folder.parent, restircl.name)
    return restircl


@pytest.fixture(scope="module")
def split_zips(tmp_path_factory) -> dict[str, Path]:
    """The four platforms' zips of the fake wheel set, built and validated by Blender's builder (bpy's)."""
    tool = _tool()
    if tool.find_builder() is None:
        pytest.skip("Blender's extension builder not found (no blender, no bpy)")
    base = tmp_path_factory.mktemp("split")
    restircl = _fake_wheel_set(base / "wheels")
    assert tool.main(["--wheel-dir", str(base / "wheels"), "--restircl-wheel", str(restircl), "--output-dir",
                      str(base / "dist"), "--build-dir", str(base / "build")]) == 0
    zips = {tool.zip_platform(p): p for p in (base / "dist").glob("*.zip")}
    assert sorted(p.name for p in zips.values()) == ["restircl-0.1.0-linux_x64.zip", "restircl-0.1.0-macos_arm64.zip",
                                                     "restircl-0.1.0-macos_x64.zip", "restircl-0.1.0-windows_x64.zip"]
    return zips


def _wheels_in(path: Path) -> set[str]:
    return {n.removeprefix("wheels/") for n in zipfile.ZipFile(path).namelist() if n.endswith(".whl")}


def test_each_platform_zip_holds_its_wheels_for_both_pythons(split_zips):
    windows = {"cffi-2.0-cp311-cp311-win_amd64.whl", "cffi-2.0-cp313-cp313-win_amd64.whl",
               "openexr-2.0-cp311-cp311-win_amd64.whl", "openexr-2.0-cp313-cp313-win_amd64.whl",
               "pillow-2.0-cp311-cp311-win_amd64.whl", "pillow-2.0-cp313-cp313-win_amd64.whl",
               "pyopencl-2.0-cp311-cp311-win_amd64.whl", "pyopencl-2.0-cp313-cp313-win_amd64.whl",
               "siphash24-2.0-cp311-cp311-win_amd64.whl", "siphash24-2.0-cp313-cp313-win_amd64.whl",
               "pyoidn-2.0-py3-none-win_amd64.whl", "platformdirs-2.0-py3-none-any.whl",
               "pycparser-2.0-py3-none-any.whl", "pytools-2.0-py3-none-any.whl",
               "typing_extensions-2.0-py3-none-any.whl", "restircl-0.1.0-py3-none-any.whl"}
    assert _wheels_in(split_zips["windows-x64"]) == windows
    mac_arm = {n.replace("win_amd64", "macosx_11_0_arm64") for n in windows}
    assert _wheels_in(split_zips["macos-arm64"]) == mac_arm
    assert _wheels_in(split_zips["macos-x64"]) == {n.replace("win_amd64", "macosx_10_15_x86_64") for n in windows}
    linux = {n.replace("win_amd64", "manylinux_2_28_x86_64") for n in windows}
    linux.add("pocl_binary_distribution-2.0-py2.py3-none-manylinux_2_17_x86_64.manylinux2014_x86_64.whl")
    assert _wheels_in(split_zips["linux-x64"]) == linux


def test_each_platform_zip_has_a_manifest_for_that_platform(split_zips):
    tool = _tool()
    for platform, path in split_zips.items():
        meta = tool.zip_manifest(path)
        assert meta["platforms"] == [platform], path.name
        assert sorted(w.removeprefix("./wheels/") for w in meta["wheels"]) == sorted(_wheels_in(path))
        assert (meta["id"], meta["blender_version_min"]) == ("restircl", tool.PER_PYTHON_WHEELS_MIN)
        assert "blender_version_max" not in meta
        names = set(zipfile.ZipFile(path).namelist())
        assert {"__init__.py", "engine.py", "export/scene.py"} <= names


def test_zip_check_refuses_another_platforms_wheel(split_zips, tmp_path):
    """check_zip (run by the build on every zip) fails on a Windows zip that also carries a Linux wheel."""
    tool = _tool()
    src = split_zips["windows-x64"]
    bad = tmp_path / src.name
    with zipfile.ZipFile(src) as z, zipfile.ZipFile(bad, "w") as out:
        for item in z.infolist():
            data = z.read(item)
            if item.filename == "blender_manifest.toml":  # the split build's list ([build.generated]) is the last
                head, _, tail = data.rpartition(b'wheels = [')
                data = head + b'wheels = ["./wheels/x-1-py3-none-manylinux1_x86_64.whl", ' + tail
            out.writestr(item, data)
        out.writestr("wheels/x-1-py3-none-manylinux1_x86_64.whl", b"")
    assert tool.check_zip(src, ["3.11", "3.13"])
    with pytest.raises(SystemExit, match="manylinux1_x86_64.*installs on none"):
        tool.check_zip(bad, ["3.11", "3.13"])


def _other_validators() -> list[tuple[str, list[str]]]:
    """Blender's validator of the other releases tools/blender_tests.py installs (.venv-blender/<release>)."""
    tool = _tool()
    found = []
    for venv in sorted((ROOT / ".venv-blender").glob("*")):
        for site in venv.glob("lib/python3.*/site-packages"):
            script = tool.blender_ext_script([str(site / "bpy")])
            if script is not None:
                found.append((venv.name, [str(venv / "bin" / "python"), str(script)]))
    return found


def test_other_releases_validators_accept_the_zips(split_zips):
    validators = _other_validators()
    if not validators:
        pytest.skip("no other Blender release under .venv-blender (tools/blender_tests.py makes them)")
    for release, cmd in validators:
        for path in split_zips.values():
            out = subprocess.run([*cmd, "validate", str(path)], capture_output=True, text=True, timeout=120)
            assert out.returncode == 0 and "Success" in out.stdout, (release, path.name, out.stdout, out.stderr)


def test_built_zips_in_dist_hold_only_their_platform(request):
    """The zips a real build left in dist/ (PyPI's wheels): only their platform's wheels, every distribution the
    build bundles for CPython 3.11 and 3.13, pyoidn among them."""
    tool = _tool()
    zips = sorted((ROOT / "dist").glob("restircl-*_*.zip"))
    zips = [p for p in zips if not p.stem.endswith(("-cp311", "-cp313"))]
    if not zips:
        pytest.skip("no built zip in dist/ (python tools/build_extension.py)")
    for path in zips:
        platform = tool.zip_platform(path)
        names = tool.distributions(platform, denoiser=True)
        files = tool.check_zip(path, ["3.11", "3.13"], names)
        assert any(f.startswith("pyoidn-") for f in files), path.name
        assert any(f.startswith("pocl_binary_distribution-") for f in files) == (platform == "linux-x64")


def test_selection_takes_the_tested_version_over_a_newer_cached_one(tmp_path):
    """The cache keeps every version downloaded: the zip gets the one installed here (the tested combination)
    where the cache has it, else the newest; for each Python, never another platform's."""
    import importlib.metadata

    tool = _tool()
    here = importlib.metadata.version("pyopencl")
    for version in (here, "9999.0"):
        for cp in ("cp311", "cp313"):
            _fake_wheel(tmp_path, f"pyopencl-{version}-{cp}-{cp}-win_amd64.whl")
    for version in ("1.0", "3.0", "2.0"):  # a distribution not installed here: the newest
        _fake_wheel(tmp_path, f"not_installed_here-{version}-py3-none-any.whl")
    chosen = tool.select_wheels(tmp_path, "windows-x64", ["3.11", "3.13"], ["pyopencl", "not-installed-here"])
    assert [p.name for p in chosen] == [f"pyopencl-{here}-cp311-cp311-win_amd64.whl",
                                        f"pyopencl-{here}-cp313-cp313-win_amd64.whl",
                                        "not_installed_here-3.0-py3-none-any.whl"]
    with pytest.raises(SystemExit, match="no wheel of pyopencl for macos-arm64, CPython 3.11"):
        tool.select_wheels(tmp_path, "macos-arm64", ["3.11"], ["pyopencl"])
