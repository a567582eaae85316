#!/usr/bin/env python3
"""Build the restircl Blender extension zip for linux-x64, with the Python wheels it needs bundled.

    python tools/build_extension.py [--output-dir dist] [--python-version 3.11] [--wheel-dir DIR]

Steps:
  1. stage addon/restircl_blender/ in build/extension/restircl_blender/;
  2. put the wheels in its wheels/ folder: restircl itself (built here with `pip wheel --no-deps`), pyopencl and
     its dependencies (pytools, platformdirs, typing_extensions, siphash24), pocl-binary-distribution (the CPU
     OpenCL driver), OpenEXR and Pillow (restircl's image I/O), downloaded unmodified from PyPI for CPython
     3.11 on manylinux x86_64 (`pip download --only-binary=:all:`); versions are pinned to the ones installed in
     the running Python when it has them, so the zip holds the combination that was tested;
  3. list them in the staged blender_manifest.toml (`wheels = [...]`, `platforms = ["linux-x64"]`);
  4. build the zip with Blender's own extension builder (`blender --command extension build`, or the same
     script, bl_pkg/cli/blender_ext.py, found in an installed bpy module), which also validates the manifest.

Blender's wheel rules (manual, "Python Wheels"): wheels in ./wheels/, unmodified from PyPI, including their
dependencies, with standard file names, listed with forward slashes. numpy is left out: Blender ships its own
numpy and every wheel here works with it (pass --include-numpy to bundle one anyway).
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


def collect_wheels(wheels: Path, python_version: str, include_numpy: bool, wheel_dir: Path | None) -> None:
    """restircl's wheel, then the dependencies (from --wheel-dir when given, else from PyPI)."""
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
    cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:", "--dest", str(wheels),
           "--python-version", python_version, "--implementation", "cp"]
    for tag in PLATFORM_TAGS:
        cmd += ["--platform", tag]
    run(cmd + [pinned(n) for n in names])


def check_wheels(wheels: Path, python_version: str) -> list[str]:
    """Every wheel must install on CPython `python_version` for linux x86_64; return their manifest paths."""
    cp = "cp" + python_version.replace(".", "")
    paths = []
    for whl in sorted(wheels.glob("*.whl")):
        parts = whl.name[:-4].split("-")
        if len(parts) < 5:
            raise SystemExit(f"{whl.name}: not a standard wheel file name")
        py, abi, plat = parts[-3], parts[-2], parts[-1]
        py_ok = any(t in ("py3", cp) or (t.startswith("cp3") and abi == "abi3" and int(t[3:]) <= int(cp[3:]))
                    for t in py.split("."))
        plat_ok = plat == "any" or any(p.endswith("x86_64") and p.startswith(("manylinux", "linux"))
                                        for p in plat.split("."))
        if not (py_ok and plat_ok):
            raise SystemExit(f"{whl.name}: does not install on {cp} linux x86_64")
        with zipfile.ZipFile(whl) as z:
            if not any(n.endswith(".dist-info/WHEEL") for n in z.namelist()):
                raise SystemExit(f"{whl.name}: no .dist-info/WHEEL inside")
        paths.append(f"./wheels/{whl.name}")
    if not any(Path(p).name.startswith("restircl-") for p in paths):
        raise SystemExit("the restircl wheel is missing")
    return paths


def write_manifest(staged: Path, wheel_paths: list[str]) -> None:
    manifest = staged / "blender_manifest.toml"
    text = manifest.read_text()
    listing = "wheels = [\n" + "".join(f'  "{p}",\n' for p in wheel_paths) + "]"
    text, n = re.subn(r"^wheels\s*=\s*\[[^\]]*\]", listing, text, flags=re.M)
    if n != 1:
        raise SystemExit("blender_manifest.toml: expected one `wheels = [...]` entry")
    text, n = re.subn(r"^platforms\s*=\s*\[[^\]]*\]", 'platforms = ["linux-x64"]', text, flags=re.M)
    if n != 1:
        raise SystemExit("blender_manifest.toml: expected one `platforms = [...]` entry")
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


def build_zip(staged: Path, output: Path) -> Path:
    import tomllib

    meta = tomllib.loads((staged / "blender_manifest.toml").read_text())
    out = output / f"{meta['id']}-{meta['version']}-linux_x64.zip"
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
    ap.add_argument("--python-version", default="3.11", help="Python of the target Blender (4.2-5.0: 3.11)")
    ap.add_argument("--wheel-dir", type=Path, default=None,
                    help="take the dependency wheels from this folder instead of downloading them")
    ap.add_argument("--include-numpy", action="store_true", help="bundle a numpy wheel too")
    args = ap.parse_args(argv)
    args.build_dir.mkdir(parents=True, exist_ok=True)
    args.output_dir.mkdir(parents=True, exist_ok=True)
    staged = stage(args.build_dir)
    collect_wheels(staged / "wheels", args.python_version, args.include_numpy, args.wheel_dir)
    paths = check_wheels(staged / "wheels", args.python_version)
    write_manifest(staged, paths)
    out = build_zip(staged, args.output_dir)
    size = out.stat().st_size / 2**20
    print(f"built {out} ({size:.1f} MiB, {len(paths)} wheels)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
