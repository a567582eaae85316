#!/usr/bin/env python3
"""Run the Blender tests on the supported Blender releases other than the one the running Python has.

    python tools/blender_tests.py [--releases 5.3,4.2] [--venv-root .venv-blender] [--skip-missing-python]

Each release is a `bpy` module from PyPI for the CPython that release embeds, in a virtual environment of its own
under --venv-root (made once, then reused while its requirements are unchanged), with restircl installed editable
from this checkout. The extension zip is built once here (tools/build_extension.py) and installed by each
release's own installer (tests/blender/test_blender_extension.py). What runs where (RELEASES):

  - 5.3, the current release (CPython 3.13): every Blender test (the viewport's in bpy too), as the main run
    does on 5.0;
  - 4.2, the oldest supported LTS (CPython 3.11, numpy < 2 as Blender 4.2 ships): the zip installed into an empty
    user folder + enable + F12 agreeing with Cycles, registration and settings (blender/test_blender_addon.py), the
    export of every data-block type (blender/test_blender_export.py: where 4.2's API differs) and the mixed-light Cycles
    comparison; the renders of the material and texture features are the same code on every release and run on
    5.0 and 5.3.

A release whose bpy is the one in the running Python is skipped (the main pytest run covers it). Exit status 1 if
any release fails or, without --skip-missing-python, if its CPython is not found.
"""

from __future__ import annotations

import argparse
import glob
import importlib.metadata
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


@dataclass(frozen=True)
class Release:
    python: str
    bpy: str
    extra: tuple[str, ...]  # further requirements of the test environment
    tests: tuple[str, ...]  # pytest arguments


# every Blender test file (those of new features included), the viewport's in bpy, and the zip builder's
ALL_BLENDER_TESTS = (*sorted(str(p.relative_to(ROOT)) for p in (ROOT / "tests" / "blender").glob("test_blender_*.py")),
                     "tests/blender/test_viewport_blender.py", "tests/blender/test_viewport_draw.py",
                     "tests/blender/test_ortho_blender.py", "tests/tools/test_build_extension.py")
#: two pytest workers, each taking whole files (module fixtures stay in one process): most tests wait on one core
#: (kernel builds, Python), so the 2-core machines finish in about half the time
PARALLEL = ("-n", "2", "--dist", "loadfile")
RELEASES = {
    "5.3": Release("3.13", "5.3.0", (), ALL_BLENDER_TESTS),
    "4.2": Release("3.11", "4.2.23", ("numpy<2",),
                   ("tests/blender/test_blender_extension.py", "tests/blender/test_blender_addon.py",
                    "tests/blender/test_blender_export.py",
                    "tests/blender/test_blender_cycles.py::test_agrees_with_cycles[mixed]")),
}


def find_python(version: str) -> str | None:
    """A CPython `version` interpreter: pythonX.Y on PATH if it runs, else one of pyenv's."""
    candidates = [shutil.which(f"python{version}")]
    pyenv = shutil.which("pyenv")
    if pyenv:
        root = subprocess.run([pyenv, "root"], capture_output=True, text=True).stdout.strip()
        candidates += sorted(glob.glob(f"{root}/versions/{version}.*/bin/python{version}"), reverse=True)
    for exe in filter(None, candidates):
        probe = subprocess.run([exe, "-c", "import sys, venv; print('%d.%d' % sys.version_info[:2])"],
                               capture_output=True, text=True)
        if probe.returncode == 0 and probe.stdout.strip() == version:
            return exe
    return None


def run(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    print("+", " ".join(cmd), flush=True)
    return subprocess.run(cmd, **kw)


def ensure_venv(name: str, release: Release, venv_root: Path, python: str) -> Path:
    """The release's virtual environment, (re)made when its requirements differ from the ones it was made with."""
    venv = venv_root / name
    exe = venv / "bin" / "python"
    requirements = [f"bpy=={release.bpy}", "pytest>=8", "pytest-xdist>=3", *release.extra]
    stamp = venv / "restircl-requirements.txt"
    wanted = "\n".join(requirements) + "\n"
    if exe.exists() and stamp.exists() and stamp.read_text() == wanted:
        return exe
    if venv.exists():
        shutil.rmtree(venv)
    run([python, "-m", "venv", str(venv)], check=True)
    run([str(exe), "-m", "pip", "install", "-q", "-e", f"{ROOT}[pocl]", *requirements], check=True)
    stamp.write_text(wanted)
    return exe


def build_zip(out: Path) -> Path:
    run([sys.executable, str(ROOT / "tools" / "build_extension.py"), "--output-dir", str(out), "--build-dir",
         str(out / "build"), "--platform", "linux-x64"], check=True)
    return next(out.glob("restircl-*-linux_x64.zip"))


def current_bpy() -> str | None:
    try:
        return importlib.metadata.version("bpy")
    except importlib.metadata.PackageNotFoundError:
        return None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--releases", default=",".join(RELEASES), help=f"comma-separated, of {', '.join(RELEASES)}")
    ap.add_argument("--venv-root", type=Path, default=ROOT / ".venv-blender")
    ap.add_argument("--skip-missing-python", action="store_true",
                    help="a release whose CPython is not installed is a warning, not a failure")
    args = ap.parse_args(argv)
    names = [n for n in args.releases.split(",") if n]
    unknown = [n for n in names if n not in RELEASES]
    if unknown:
        ap.error(f"unknown release(s) {', '.join(unknown)}; known: {', '.join(RELEASES)}")
    names = [n for n in names if RELEASES[n].bpy != current_bpy()]
    results: dict[str, str] = {}
    extension_zip = build_zip(args.venv_root / "dist") if names else None
    for name in names:
        release = RELEASES[name]
        python = find_python(release.python)
        if python is None:
            results[name] = f"no CPython {release.python} found (e.g. pyenv install {release.python})"
            if not args.skip_missing_python:
                results[name] = "FAILED: " + results[name]
            continue
        t0 = time.perf_counter()
        exe = ensure_venv(name, release, args.venv_root, python)
        setup_s = time.perf_counter() - t0
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        env["RESTIRCL_EXTENSION_ZIP"] = str(extension_zip)
        t0 = time.perf_counter()
        rc = run([str(exe), "-m", "pytest", "-q", "-p", "no:cacheprovider", *PARALLEL, *release.tests], cwd=ROOT,
                 env=env).returncode
        verdict = "ok" if rc == 0 else f"FAILED (pytest exit {rc})"
        results[name] = f"{verdict}: bpy {release.bpy}, set-up {setup_s:.0f} s, tests {time.perf_counter() - t0:.0f} s"
    for name, line in results.items():
        print(f"Blender {name}: {line}")
    return 1 if any(line.startswith("FAILED") for line in results.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
