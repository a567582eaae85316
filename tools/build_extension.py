#!/usr/bin/env python3
"""Build the restircl Blender extension zip for linux-x64, with the Python wheels it needs bundled.

    python tools/build_extension.py [--output-dir dist] [--python-version 3.11 --python-version 3.13] [--wheel-dir DIR]

Steps:
  1. stage addon/restircl_blender/ in build/extension/restircl_blender/;
  2. put the wheels in its wheels/ folder: restircl itself (built here with `pip wheel --no-deps`), pyopencl and
     its dependencies (pytools, platformdirs, typing_extensions, siphash24), pocl-binary-distribution (the CPU
     OpenCL driver), OpenEXR and Pillow (restircl's image I/O), downloaded unmodified from PyPI for each CPython
     the supported Blender releases embed (3.11: 4.2 LTS to 5.0; 3.13: 5.1 and newer) on manylinux x86_64
     (`pip download --only-binary=:all:`); versions are pinned to the ones installed in the running Python when it
     has them, so the zip holds the combination that was tested;
  3. list them in the staged blender_manifest.toml (`wheels = [...]`, `platforms = ["linux-x64"]`) and set
     `blender_version_min` / `blender_version_max` to the releases those Pythons cover (RELEASES below);
  4. build the zip with Blender's own extension builder (`blender --command extension build`, or the same
     script, bl_pkg/cli/blender_ext.py, found in an installed bpy module), which also validates the manifest.

Blender's wheel rules (manual, "Python Wheels"): wheels in ./wheels/, unmodified from PyPI, including their
dependencies, with standard file names, listed with forward slashes. At install time Blender keeps the wheels that
match its platform and Python, so one zip serves both Pythons. numpy is left out: Blender ships its own numpy and
every wheel here works with it (pass --include-numpy to bundle one anyway).
"""

from __future__ import annotations

import argparse
import glob
import importlib.metadata
import importlib.util
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ADDON = ROOT / "addon" / "restircl_blender"
PLATFORM_TAGS = ("manylinux_2_28_x86_64", "manylinux_2_27_x86_64", "manylinux_2_17_x86_64", "manylinux2014_x86_64",
                 "manylinux_2_5_x86_64", "manylinux1_x86_64", "linux_x86_64")
# The Blender releases whose embedded CPython is each version: [min, max) as the manifest's blender_version_min and
# blender_version_max read them (max is the first release that is not supported; None: no upper bound known).
RELEASES = {"3.11": ("4.2.0", "5.1.0"), "3.13": ("5.1.0", None)}
DEFAULT_PYTHONS = tuple(RELEASES)
# With wheels for two Pythons in one zip, Blender must choose per Python: 4.2.0 chooses by platform only (its
# bl_pkg keeps one wheel per distribution, the highest file name, so it would take the cp313 ones); 4.2.13, the
# oldest later 4.2 on PyPI, and every release since filter by Python version first.
PER_PYTHON_WHEELS_MIN = "4.2.13"
# Distribution names of the runtime dependencies (numpy is Blender's).
DEPENDENCIES = ("pyopencl", "pytools", "platformdirs", "typing_extensions", "siphash24", "pocl-binary-distribution",
                "OpenEXR", "pillow")


def run(cmd: list[str]) -> None:
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)


def pinned(name: str) -> str:
    try:
        return f"{name}=={importlib.metadata.version(name)}"
    except importlib.metadata.PackageNotFoundError:
        return name


def stage(build: Path) -> Path:
    dst = build / "restircl_blender"
    if dst.exists():
        shutil.rmtree(dst)
    shutil.copytree(ADDON, dst, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "wheels"))
    (dst / "wheels").mkdir()
    return dst


def collect_wheels(wheels: Path, python_versions: list[str], include_numpy: bool, wheel_dir: Path | None) -> None:
    """restircl's wheel, then the dependencies (from --wheel-dir when given, else from PyPI, per Python)."""
    run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", str(wheels), str(ROOT)])
    names = list(DEPENDENCIES) + (["numpy"] if include_numpy else [])
    if wheel_dir is not None:
        for name in names:
            pattern = re.sub(r"[-_.]+", "_", name).lower()
            found = [p for p in wheel_dir.glob("*.whl") if p.name.lower().startswith(pattern + "-")]
            if not found:
                raise SystemExit(f"no wheel for {name} in {wheel_dir}")
            for p in found:
                shutil.copy2(p, wheels / p.name)
        return
    for version in python_versions:
        cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:", "--dest", str(wheels),
               "--python-version", version, "--implementation", "cp"]
        for tag in PLATFORM_TAGS:
            cmd += ["--platform", tag]
        run(cmd + [pinned(n) for n in names])


def wheel_pythons(name: str, python_versions: list[str]) -> set[str]:
    """Which of `python_versions` (e.g. "3.11") the wheel file `name` installs on, for linux x86_64."""
    parts = name[:-4].split("-")
    if len(parts) < 5:
        raise SystemExit(f"{name}: not a standard wheel file name")
    py, abi, plat = parts[-3], parts[-2], parts[-1]
    if not (plat == "any" or any(p.endswith("x86_64") and p.startswith(("manylinux", "linux"))
                                 for p in plat.split("."))):
        return set()
    ok = set()
    for version in python_versions:
        cp = "cp" + version.replace(".", "")
        if any(t in ("py3", cp) or (t.startswith("cp3") and abi == "abi3" and int(t[3:]) <= int(cp[3:]))
               for t in py.split(".")):
            ok.add(version)
    return ok


def check_wheels(wheels: Path, python_versions: list[str]) -> list[str]:
    """Every wheel installs on one of the Pythons, every distribution has a wheel for each; the manifest paths."""
    paths = []
    covered: dict[str, set[str]] = {}
    for whl in sorted(wheels.glob("*.whl")):
        pythons = wheel_pythons(whl.name, python_versions)
        if not pythons:
            raise SystemExit(f"{whl.name}: installs on none of CPython {', '.join(python_versions)} linux x86_64")
        with zipfile.ZipFile(whl) as z:
            if not any(n.endswith(".dist-info/WHEEL") for n in z.namelist()):
                raise SystemExit(f"{whl.name}: no .dist-info/WHEEL inside")
        covered.setdefault(whl.name.split("-")[0].lower(), set()).update(pythons)
        paths.append(f"./wheels/{whl.name}")
    if "restircl" not in covered:
        raise SystemExit("the restircl wheel is missing")
    for dist, pythons in sorted(covered.items()):
        missing = [v for v in python_versions if v not in pythons]
        if missing:
            raise SystemExit(f"{dist}: no wheel for CPython {', '.join(missing)}")
    return paths


def blender_range(python_versions: list[str]) -> tuple[str, str | None]:
    """blender_version_min and _max for a zip with wheels for these Pythons."""
    unknown = [v for v in python_versions if v not in RELEASES]
    if unknown:
        raise SystemExit(f"no Blender release embeds CPython {', '.join(unknown)} (known: {', '.join(RELEASES)})")
    key = _version_key
    lo = min((RELEASES[v][0] for v in python_versions), key=key)
    highs = [RELEASES[v][1] for v in python_versions]
    hi = None if None in highs else max((h for h in highs if h is not None), key=key)
    if len(set(python_versions)) > 1:
        lo = max(lo, PER_PYTHON_WHEELS_MIN, key=key)
    return lo, hi


def _version_key(version: str) -> tuple[int, ...]:
    return tuple(int(x) for x in version.split("."))


def write_manifest(staged: Path, wheel_paths: list[str], python_versions: list[str]) -> None:
    manifest = staged / "blender_manifest.toml"
    text = manifest.read_text()
    listing = "wheels = [\n" + "".join(f'  "{p}",\n' for p in wheel_paths) + "]"
    lo, hi = blender_range(python_versions)
    versions = f'blender_version_min = "{lo}"' + (f'\nblender_version_max = "{hi}"' if hi else "")
    for key, value in (("wheels", listing), ("platforms", 'platforms = ["linux-x64"]')):
        text, n = re.subn(rf"^{key}\s*=\s*\[[^\]]*\]", value, text, flags=re.M)
        if n != 1:
            raise SystemExit(f"blender_manifest.toml: expected one `{key} = [...]` entry")
    text = re.sub(r"^blender_version_max\s*=.*\n", "", text, flags=re.M)
    text, n = re.subn(r"^blender_version_min\s*=.*$", versions, text, flags=re.M)
    if n != 1:
        raise SystemExit("blender_manifest.toml: expected one `blender_version_min` entry")
    manifest.write_text(text)


def find_builder() -> list[str] | None:
    """The command that runs Blender's extension builder: a `blender` binary, or blender_ext.py from bpy."""
    blender = shutil.which("blender")
    if blender:
        return [blender, "--factory-startup", "--command", "extension"]
    spec = importlib.util.find_spec("bpy")
    roots = []
    if spec is not None and spec.submodule_search_locations:
        roots += list(spec.submodule_search_locations)
    for root in roots:
        hits = glob.glob(str(Path(root) / "*" / "scripts" / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"))
        if hits:
            return [sys.executable, hits[0]]
    return None


def build_zip(staged: Path, output: Path, suffix: str = "") -> Path:
    import tomllib

    meta = tomllib.loads((staged / "blender_manifest.toml").read_text())
    out = output / f"{meta['id']}-{meta['version']}-linux_x64{suffix}.zip"
    builder = find_builder()
    if builder is not None:
        run(builder + ["build", "--source-dir", str(staged), "--output-filepath", str(out)])
        run(builder + ["validate", str(out)])
        return out
    print("Blender's extension builder not found (no `blender` on PATH, no bpy module): zipping directly",
          flush=True)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for path in sorted(staged.rglob("*")):
            if path.is_file():
                z.write(path, path.relative_to(staged).as_posix())
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--output-dir", type=Path, default=ROOT / "dist")
    ap.add_argument("--build-dir", type=Path, default=ROOT / "build" / "extension")
    ap.add_argument("--python-version", action="append", choices=list(RELEASES), default=None,
                    help="CPython of the target Blender, repeatable (3.11: 4.2 LTS-5.0; 3.13: 5.1+; default both)")
    ap.add_argument("--wheel-dir", type=Path, default=None,
                    help="take the dependency wheels from this folder instead of downloading them")
    ap.add_argument("--include-numpy", action="store_true", help="bundle a numpy wheel too")
    args = ap.parse_args(argv)
    pythons = sorted(set(args.python_version or DEFAULT_PYTHONS), key=_version_key)
    args.build_dir.mkdir(parents=True, exist_ok=True)
    args.output_dir.mkdir(parents=True, exist_ok=True)
    staged = stage(args.build_dir)
    collect_wheels(staged / "wheels", pythons, args.include_numpy, args.wheel_dir)
    paths = check_wheels(staged / "wheels", pythons)
    write_manifest(staged, paths, pythons)
    suffix = "" if pythons == list(DEFAULT_PYTHONS) else "-" + "-".join("cp" + v.replace(".", "") for v in pythons)
    out = build_zip(staged, args.output_dir, suffix)
    lo, hi = blender_range(pythons)
    size = out.stat().st_size / 2**20
    print(f"built {out} ({size:.1f} MiB, {len(paths)} wheels, CPython {', '.join(pythons)}: Blender {lo} to "
          f"{'any newer' if hi is None else 'before ' + hi})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
