#!/usr/bin/env python3
"""Build the restircl Blender extension: one zip per platform, each with the Python wheels of that platform only.

    python tools/build_extension.py [--platform linux-x64 ...] [--python-version 3.11 ...] [--output-dir dist]
                                    [--wheel-dir DIR] [--restircl-wheel WHL] [--no-denoiser]

Steps:
  1. stage addon/restircl_blender/ in build/extension/restircl_blender/;
  2. put the wheels in its wheels/ folder: restircl itself (built here with `pip wheel --no-deps`, or
     --restircl-wheel), and for every platform (linux-x64, windows-x64, macos-arm64, macos-x64; default all) and
     every CPython the supported Blender releases embed (3.11: 4.2 LTS to 5.0; 3.13: 5.1 and newer) the wheels of
     pyopencl and its dependencies (pytools, platformdirs, typing_extensions, siphash24), OpenEXR and Pillow
     (restircl's image I/O), pyoidn with cffi and pycparser (the denoiser; --no-denoiser leaves it out), and on
     Linux pocl-binary-distribution (PoCL, the CPU OpenCL driver: its wheels exist for Linux only), downloaded
     unmodified from PyPI (`pip download --only-binary=:all:`) into a cache (build/wheel-cache, kept between
     runs) or taken from --wheel-dir without downloading; versions are pinned to the ones installed in the
     running Python when it has them, so the zips hold the combination that was tested;
  3. list them all in the staged blender_manifest.toml with `platforms = [...]`, and set `blender_version_min` /
     `blender_version_max` to the releases those Pythons cover (RELEASES below);
  4. build one zip per platform with Blender's own split-platform build (`blender --command extension build
     --split-platforms`, or the same script, bl_pkg/cli/blender_ext.py, found in an installed bpy module): each
     zip holds the wheels of its platform (and the pure-Python ones), and its manifest names that platform;
  5. check each zip here (only its platform's wheels, every distribution for every Python) and validate it with
     Blender's `extension validate`.

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
# Blender's platform names and the wheel platform tags pip may take for each, best first. macOS: Blender 4.2-5.x
# runs on macOS 11.2 and newer; the tags stop at 12.0, so a wheel that needs a newer macOS is not taken unseen
# (pyoidn's arm64 wheel needs 12.0: on macOS 11 Denoise then warns and leaves the image as it is).
PLATFORMS: dict[str, tuple[str, ...]] = {
    "linux-x64": ("manylinux_2_28_x86_64", "manylinux_2_27_x86_64", "manylinux_2_17_x86_64", "manylinux2014_x86_64",
                  "manylinux_2_5_x86_64", "manylinux1_x86_64", "linux_x86_64"),
    "windows-x64": ("win_amd64",),
    "macos-arm64": ("macosx_12_0_arm64", "macosx_11_0_arm64", "macosx_12_0_universal2", "macosx_11_0_universal2",
                    "macosx_10_9_universal2"),
    "macos-x64": ("macosx_12_0_x86_64", "macosx_11_0_x86_64", *(f"macosx_10_{m}_x86_64" for m in range(15, 8, -1)),
                  "macosx_10_9_universal2"),
}
# The Blender releases whose embedded CPython is each version: [min, max) as the manifest's blender_version_min and
# blender_version_max read them (max is the first release that is not supported; None: no upper bound known).
RELEASES = {"3.11": ("4.2.0", "5.1.0"), "3.13": ("5.1.0", None)}
DEFAULT_PYTHONS = tuple(RELEASES)
# With wheels for two Pythons in one zip, Blender must choose per Python: 4.2.0 chooses by platform only (its
# bl_pkg keeps one wheel per distribution, the highest file name, so it would take the cp313 ones); 4.2.13, the
# oldest later 4.2 on PyPI, and every release since filter by Python version first.
PER_PYTHON_WHEELS_MIN = "4.2.13"
# Distribution names of the runtime dependencies (numpy is Blender's), the denoiser's, and those published for
# some platforms only.
DEPENDENCIES = ("pyopencl", "pytools", "platformdirs", "typing_extensions", "siphash24", "OpenEXR", "pillow")
DENOISER = ("pyoidn", "cffi", "pycparser")
ONLY_ON = {"pocl-binary-distribution": ("linux-x64",)}
WHEEL_CACHE = ROOT / "build" / "wheel-cache"


def run(cmd: list[str]) -> None:
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)


def pinned(name: str) -> str:
    version = _installed(name)
    return name if version is None else f"{name}=={version}"


def normalise(name: str) -> str:
    """A distribution name as wheel file names spell it (PEP 427: runs of -_. become _), lower case."""
    return re.sub(r"[-_.]+", "_", name).lower()


def distributions(platform: str, denoiser: bool, include_numpy: bool = False) -> list[str]:
    """The distributions whose wheels the zip for `platform` carries (restircl's own wheel apart)."""
    names = list(DEPENDENCIES) + (list(DENOISER) if denoiser else []) + (["numpy"] if include_numpy else [])
    return names + [name for name, where in ONLY_ON.items() if platform in where]


def stage(build: Path) -> Path:
    dst = build / "restircl_blender"
    if dst.exists():
        shutil.rmtree(dst)
    shutil.copytree(ADDON, dst, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "wheels"))
    (dst / "wheels").mkdir()
    return dst


def download(cache: Path, platform: str, python: str, names: list[str]) -> None:
    """pip download the wheels of `names` for one platform and CPython into cache/<platform>/ (kept; pip skips a
    file that is already there)."""
    dest = cache / platform
    cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:", "--dest", str(dest),
           "--python-version", python, "--implementation", "cp"]
    for tag in PLATFORMS[platform]:
        cmd += ["--platform", tag]
    run(cmd + [pinned(n) for n in names])


def wheel_tags(name: str) -> tuple[str, str, str, str]:
    """(distribution, python tags, abi tag, platform tags) of a wheel file name."""
    parts = name[:-4].split("-")
    if not name.endswith(".whl") or len(parts) < 5:
        raise SystemExit(f"{name}: not a standard wheel file name")
    return parts[0].lower(), parts[-3], parts[-2], parts[-1]


def wheel_platforms(name: str) -> set[str]:
    """The Blender platforms the wheel file `name` installs on ("any": all of them)."""
    found = set()
    for tag in wheel_tags(name)[3].split("."):
        if tag == "any":
            return set(PLATFORMS)
        if tag.startswith(("manylinux", "musllinux", "linux")) and tag.endswith("_x86_64"):
            found.add("linux-x64")
        elif tag == "win_amd64":
            found.add("windows-x64")
        elif tag.startswith("macosx_") and tag.endswith(("_arm64", "_universal2")):
            found.add("macos-arm64")
        if tag.startswith("macosx_") and tag.endswith(("_x86_64", "_universal2")):
            found.add("macos-x64")
    return found


def wheel_pythons(name: str, python_versions: list[str]) -> set[str]:
    """Which of `python_versions` (e.g. "3.11") the wheel file `name` installs on, whatever the platform."""
    _, py, abi, _ = wheel_tags(name)
    ok = set()
    for version in python_versions:
        cp = "cp" + version.replace(".", "")
        if any(t in ("py3", cp) or (t.startswith("cp3") and abi == "abi3" and int(t[3:]) <= int(cp[3:]))
               for t in py.split(".")):
            ok.add(version)
    return ok


def select_wheels(folder: Path, platform: str, python_versions: list[str], names: list[str]) -> list[Path]:
    """From `folder`, the wheels of `names` for `platform`: for each distribution and Python, the version installed
    in this Python where the folder has it, else the highest that installs there; a distribution missing for one
    of them is an error."""
    if (folder / platform).is_dir():  # a cache: one folder per platform
        folder = folder / platform
    chosen: list[Path] = []
    for name in names:
        key = normalise(name)
        for version in python_versions:
            fits = [p for p in folder.glob("*.whl") if normalise(wheel_tags(p.name)[0]) == key
                    and platform in wheel_platforms(p.name) and version in wheel_pythons(p.name, [version])]
            if not fits:
                raise SystemExit(f"no wheel of {name} for {platform}, CPython {version} in {folder}")
            installed = [p for p in fits if p.name.split("-")[1] == _installed(name)]  # the tested one, if cached
            best = max(installed or fits, key=lambda p: _release_key(p.name.split("-")[1]))
            if best not in chosen:
                chosen.append(best)
    return chosen


def _installed(name: str) -> str | None:
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return None


def _release_key(version: str) -> tuple:
    return tuple((0, int(x)) if x.isdigit() else (1, x) for x in re.split(r"[.+-]", version))


def collect_wheels(wheels: Path, platforms: list[str], python_versions: list[str], denoiser: bool,
                   include_numpy: bool, wheel_dir: Path | None, restircl_wheel: Path | None,
                   cache: Path = WHEEL_CACHE) -> None:
    """restircl's wheel, then every platform's dependencies (from --wheel-dir when given, else via the cache)."""
    if restircl_wheel is not None:
        shutil.copy2(restircl_wheel, wheels / restircl_wheel.name)
    else:
        run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", str(wheels), str(ROOT)])
    for platform in platforms:
        names = distributions(platform, denoiser, include_numpy)
        folder = wheel_dir
        if folder is None:
            for version in python_versions:
                download(cache, platform, version, names)
            folder = cache
        for path in select_wheels(folder, platform, python_versions, names):
            shutil.copy2(path, wheels / path.name)


def check_wheels(wheels: Path | list[str], python_versions: list[str], platforms: list[str],
                 names: dict[str, list[str]] | None = None) -> list[str]:
    """Every wheel installs on one of the platforms and Pythons, every distribution has a wheel for each platform
    and Python (`names`: the distributions each platform must have, else those found); the manifest's paths."""
    files = sorted(p.name for p in wheels.glob("*.whl")) if isinstance(wheels, Path) else sorted(wheels)
    covered: dict[tuple[str, str], set[str]] = {}
    for name in files:
        pythons = wheel_pythons(name, python_versions)
        where = wheel_platforms(name) & set(platforms)
        if not pythons or not where:
            raise SystemExit(f"{name}: installs on none of CPython {', '.join(python_versions)} on "
                             f"{', '.join(platforms)}")
        if isinstance(wheels, Path):
            with zipfile.ZipFile(wheels / name) as z:
                if not any(n.endswith(".dist-info/WHEEL") for n in z.namelist()):
                    raise SystemExit(f"{name}: no .dist-info/WHEEL inside")
        for platform in where:
            covered.setdefault((normalise(wheel_tags(name)[0]), platform), set()).update(pythons)
    for platform in platforms:
        wanted = ["restircl"] + (names[platform] if names else [d for d, p in covered if p == platform])
        for dist in sorted({normalise(n) for n in wanted}):
            missing = [v for v in python_versions if v not in covered.get((dist, platform), set())]
            if missing:
                raise SystemExit(f"{dist}: no wheel for {platform}, CPython {', '.join(missing)}")
    return [f"./wheels/{name}" for name in files]


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


def write_manifest(staged: Path, wheel_paths: list[str], python_versions: list[str],
                   platforms: list[str] | None = None) -> None:
    manifest = staged / "blender_manifest.toml"
    text = manifest.read_text()
    listing = "wheels = [\n" + "".join(f'  "{p}",\n' for p in wheel_paths) + "]"
    listed = ", ".join(f'"{p}"' for p in (platforms or ["linux-x64"]))
    lo, hi = blender_range(python_versions)
    versions = f'blender_version_min = "{lo}"' + (f'\nblender_version_max = "{hi}"' if hi else "")
    for key, value in (("wheels", listing), ("platforms", f"platforms = [{listed}]")):
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
    script = blender_ext_script()
    return None if script is None else [sys.executable, str(script)]


def blender_ext_script(package_dirs: list[str] | None = None) -> Path | None:
    """bl_pkg/cli/blender_ext.py of an installed bpy module (the script `blender --command extension` runs)."""
    if package_dirs is None:
        spec = importlib.util.find_spec("bpy")
        package_dirs = list(spec.submodule_search_locations or []) if spec is not None else []
    for root in package_dirs:
        hits = glob.glob(str(Path(root) / "*" / "scripts" / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"))
        if hits:
            return Path(hits[0])
    return None


def zip_platform(path: Path) -> str:
    """The platform a split zip was built for, from its name (restircl-0.1.0-linux_x64.zip)."""
    for platform in PLATFORMS:
        if path.stem.endswith("-" + platform.replace("-", "_")) or f"-{platform.replace('-', '_')}-" in path.stem:
            return platform
    raise SystemExit(f"{path.name}: no platform in its name")


def zip_manifest(path: Path) -> dict:
    """The manifest of a built zip, with the platform and wheels its split build wrote ([build.generated])."""
    import tomllib

    with zipfile.ZipFile(path) as z:
        meta = tomllib.loads(z.read("blender_manifest.toml").decode())
    generated = meta.get("build", {}).get("generated", {})
    return {**meta, **{k: generated[k] for k in ("platforms", "wheels") if k in generated}}


def check_zip(path: Path, python_versions: list[str], names: list[str] | None = None) -> list[str]:
    """A split zip's wheels are those its manifest lists, all for its own platform, every distribution (`names`,
    else those present) for every Python; returns the wheel file names."""
    platform = zip_platform(path)
    meta = zip_manifest(path)
    if meta.get("platforms") != [platform]:
        raise SystemExit(f"{path.name}: manifest platforms {meta.get('platforms')}, expected [{platform!r}]")
    with zipfile.ZipFile(path) as z:
        present = sorted(n for n in z.namelist() if n.startswith("wheels/") and n.endswith(".whl"))
    listed = sorted(w.removeprefix("./") for w in meta.get("wheels", []))
    if present != listed:
        raise SystemExit(f"{path.name}: wheels in the zip {present} differ from the manifest's {listed}")
    files = [n.removeprefix("wheels/") for n in present]
    check_wheels(files, python_versions, [platform], {platform: names} if names is not None else None)
    return files


def build_zips(staged: Path, output: Path, suffix: str = "") -> list[Path]:
    """Blender's split-platform build of the staged extension: one zip per platform of its manifest, each
    validated by Blender's `extension validate`. Without Blender's builder, one zip of everything (not split)."""
    import tomllib

    meta = tomllib.loads((staged / "blender_manifest.toml").read_text())
    builder = find_builder()
    if builder is None:
        print("Blender's extension builder not found (no `blender` on PATH, no bpy module): zipping here, "
              "unvalidated", flush=True)
        return [_zip_platform(staged, output / f"{meta['id']}-{meta['version']}-{p.replace('-', '_')}{suffix}.zip", p)
                for p in meta["platforms"]]
    split = output / f".split-{meta['id']}"
    if split.exists():
        shutil.rmtree(split)
    split.mkdir(parents=True)
    run(builder + ["build", "--source-dir", str(staged), "--output-dir", str(split), "--split-platforms"])
    zips = []
    for platform in meta["platforms"]:
        made = split / f"{meta['id']}-{meta['version']}-{platform.replace('-', '_')}.zip"
        out = output / (made.stem + suffix + ".zip")
        made.replace(out)
        run(builder + ["validate", str(out)])
        zips.append(out)
    shutil.rmtree(split)
    return zips


def _zip_platform(staged: Path, out: Path, platform: str) -> Path:
    """One platform's zip without Blender's builder: the add-on, the wheels that install there, and the manifest
    naming that platform and those wheels."""
    text = (staged / "blender_manifest.toml").read_text()
    keep = [p for p in sorted((staged / "wheels").glob("*.whl")) if platform in wheel_platforms(p.name)]
    listing = "wheels = [\n" + "".join(f'  "./wheels/{p.name}",\n' for p in keep) + "]"
    text = re.sub(r"^wheels\s*=\s*\[[^\]]*\]", listing, text, flags=re.M)
    text = re.sub(r"^platforms\s*=\s*\[[^\]]*\]", f'platforms = ["{platform}"]', text, flags=re.M)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("blender_manifest.toml", text)
        for path in sorted(staged.rglob("*")):
            rel = path.relative_to(staged).as_posix()
            if path.is_file() and rel != "blender_manifest.toml" and (path.suffix != ".whl" or path in keep):
                z.write(path, rel)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--output-dir", type=Path, default=ROOT / "dist")
    ap.add_argument("--build-dir", type=Path, default=ROOT / "build" / "extension")
    ap.add_argument("--platform", action="append", choices=list(PLATFORMS), default=None,
                    help="a platform to build a zip for, repeatable (default: all four)")
    ap.add_argument("--python-version", action="append", choices=list(RELEASES), default=None,
                    help="CPython of the target Blender, repeatable (3.11: 4.2 LTS-5.0; 3.13: 5.1+; default both)")
    ap.add_argument("--wheel-dir", type=Path, default=None,
                    help="take the dependency wheels from this folder (or its <platform>/ subfolders, as in the "
                         "cache) instead of downloading them")
    ap.add_argument("--wheel-cache", type=Path, default=WHEEL_CACHE,
                    help="where downloaded wheels are kept between runs, one folder per platform")
    ap.add_argument("--restircl-wheel", type=Path, default=None,
                    help="bundle this restircl wheel instead of building one from the checkout")
    ap.add_argument("--no-denoiser", dest="denoiser", action="store_false",
                    help="leave out pyoidn (Intel Open Image Denoise, 50-90 MB a platform) and its cffi")
    ap.add_argument("--include-numpy", action="store_true", help="bundle a numpy wheel too")
    args = ap.parse_args(argv)
    pythons = sorted(set(args.python_version or DEFAULT_PYTHONS), key=_version_key)
    platforms = [p for p in PLATFORMS if p in (args.platform or PLATFORMS)]
    args.build_dir.mkdir(parents=True, exist_ok=True)
    args.output_dir.mkdir(parents=True, exist_ok=True)
    staged = stage(args.build_dir)
    collect_wheels(staged / "wheels", platforms, pythons, args.denoiser, args.include_numpy, args.wheel_dir,
                   args.restircl_wheel, args.wheel_cache)
    names = {p: distributions(p, args.denoiser, args.include_numpy) for p in platforms}
    paths = check_wheels(staged / "wheels", pythons, platforms, names)
    write_manifest(staged, paths, pythons, platforms)
    suffix = "" if pythons == list(DEFAULT_PYTHONS) else "-" + "-".join("cp" + v.replace(".", "") for v in pythons)
    lo, hi = blender_range(pythons)
    for out in build_zips(staged, args.output_dir, suffix):
        count = len(check_zip(out, pythons, names[zip_platform(out)]))
        print(f"built {out} ({out.stat().st_size / 2**20:.1f} MiB, {count} wheels, CPython {', '.join(pythons)}: "
              f"Blender {lo} to {'any newer' if hi is None else 'before ' + hi})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
