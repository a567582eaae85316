"""The built extension zip, installed by Blender's own installer into an empty user folder, enables, adds the
engine, and renders with the wheels it carries: F12 of a small scene agrees with Cycles (bound as
tests/blender/test_blender_cycles.py). Runs on whichever Blender the bpy module is (tools/blender_tests.py runs it on
the other supported releases too).

The zip is built with tools/build_extension.py (its wheels come from PyPI), or taken from $RESTIRCL_EXTENSION_ZIP.
"""

from __future__ import annotations

import importlib.metadata
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from .test_blender_support import read_exr_passes, relmse  # noqa: E402

pytestmark = pytest.mark.blender

ROOT = Path(__file__).resolve().parents[2]
BOUND = 0.01  # relMSE, as tests/blender/test_blender_cycles.py


@pytest.fixture(scope="module")
def extension_zip(tmp_path_factory) -> Path:
    given = os.environ.get("RESTIRCL_EXTENSION_ZIP")
    if given:
        assert Path(given).is_file(), f"RESTIRCL_EXTENSION_ZIP={given}: no such file"
        return Path(given)
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, str(ROOT / "tools" / "build_extension.py"), "--output-dir", str(out),
                    "--build-dir", str(out / "build"), "--platform", "linux-x64"], check=True, timeout=900)
    return next(out.glob("restircl-*-linux_x64.zip"))


def _requirements(dist: importlib.metadata.Distribution) -> list[str]:
    reqs = []
    for req in dist.requires or []:
        if "extra ==" in req:
            continue
        reqs.append(re.match(r"[A-Za-z0-9_.-]+", req).group(0))
    return reqs


def bpy_only_site(dest: Path) -> Path:
    """A folder of links to bpy and the distributions it requires (and theirs), nothing else."""
    dest.mkdir()
    todo, seen = ["bpy"], set()
    while todo:
        name = todo.pop()
        key = re.sub(r"[-_.]+", "-", name).lower()
        if key in seen:
            continue
        seen.add(key)
        try:
            dist = importlib.metadata.distribution(name)
        except importlib.metadata.PackageNotFoundError:  # a requirement for other Pythons (its marker is false)
            continue
        todo += _requirements(dist)
        for top in {Path(str(f)).parts[0] for f in dist.files or []}:
            src = Path(dist.locate_file(top))
            if top != ".." and not top.endswith(".dist-info") and src.exists() and not (dest / top).exists():
                (dest / top).symlink_to(src)
    return dest


def test_installed_zip_enables_and_renders_like_cycles(extension_zip, tmp_path):
    user = tmp_path / "user"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH" and not k.startswith("BLENDER_USER_")}
    for kind in ("RESOURCES", "CONFIG", "SCRIPTS", "EXTENSIONS", "DATAFILES"):
        env[f"BLENDER_USER_{kind}"] = str(user / kind.lower())
    site = bpy_only_site(tmp_path / "site")
    out = subprocess.run([sys.executable, "-S", str(ROOT / "tests" / "blender/extension_install_script.py"),
                          str(extension_zip), str(tmp_path), str(site)],
                         capture_output=True, text=True, env=env, timeout=900)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    report = json.loads(out.stdout.strip().splitlines()[-1])
    print(report)
    assert report["installed_before"] == [], "the user folder was not empty"
    assert report["install"] == ["FINISHED"] and report["enabled"] and report["engine"], report
    ext = Path(report["extensions_dir"])
    for name, path in report["modules"].items():  # from the zip's wheels, not from this Python's site-packages
        assert Path(path).is_relative_to(ext), f"{name} imported from {path}"
    cyc = read_exr_passes(tmp_path / "cycles.exr")["Combined"]
    ours = read_exr_passes(tmp_path / "ours.exr")["Combined"]
    assert ours.shape == cyc.shape == (36, 48, 4)
    assert np.all(np.isfinite(ours)) and cyc[..., :3].mean() > 0.01
    err = relmse(ours, cyc)
    print(f"Blender {report['blender']} (Python {report['python']}): install {report['install_s']:.1f} s, "
          f"F12 {report['f12_s']:.1f} s, relMSE against Cycles {100 * err:.3f} %")
    assert err < BOUND
    # Denoise with the zip's pyoidn (imported above from the extension's wheels): the image before it is kept as
    # the Noisy Image pass, and the denoiser changed the image
    denoised = read_exr_passes(tmp_path / "denoised.exr")
    assert "pyoidn" in report["modules"] and "Noisy Image" in denoised, sorted(denoised)
    assert np.all(np.isfinite(denoised["Combined"]))
    assert np.abs(denoised["Combined"][..., :3] - denoised["Noisy Image"][..., :3]).max() > 1e-4
