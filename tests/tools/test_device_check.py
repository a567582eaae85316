"""tools/device_check.py (the GPU half's check, run by hand on a machine with a GPU): its image comparison flags a
different estimator and passes the same one, and the whole script runs on the CPU device at a tiny size."""

import importlib.util
import json
from pathlib import Path

import numpy as np
from restircl import Settings

TOOL = Path(__file__).resolve().parents[2] / "tools" / "device_check.py"


def load_tool():
    spec = importlib.util.spec_from_file_location("device_check", TOOL)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_compare_flags_another_estimator_and_passes_the_same(device):
    dc = load_tool()
    s = dict(method="ris", candidates=4, jitter=False, taa=False)
    a = dc.still_frames(device, Settings(seed=1, **s), 24, 16, 64)
    b = dc.still_frames(device, Settings(seed=2, **s), 24, 16, 64)
    same = dc.compare(a, a)
    assert same["image_mean_z"] == 0 and same["frame0_bit_identical"] == 1.0 and same["pixels_z_over_4"] == 0
    other_seed = dc.compare(a, b)  # the same estimator, other random numbers: agreement within the noise
    assert other_seed["finite"] and other_seed["image_mean_z"] < 4 and other_seed["frame0_bit_identical"] < 1
    assert other_seed["pixels_z_over_4"] <= 0.01
    brighter = dc.compare(a, 1.25 * b)  # an estimator 25 % off (10 % gave z = 3.7 at this size and frame count)
    assert brighter["image_mean_z"] > 4


def test_script_runs_on_the_cpu(device, tmp_path, monkeypatch):
    dc = load_tool()
    monkeypatch.setenv("OUT", str(tmp_path))
    spec = f"{device.info.platform_index}:{device.info.device_index}"
    assert dc.main(["--devices", f"{spec},{spec}", "--sizes", "48x27", "--image-size", "24x16", "--frames", "8",
                    "--methods", "ris (8)", "--triangles", "3000"]) == 0
    out = json.loads((tmp_path / "device_check.json").read_text())
    assert len(out["devices"]) == 2 and len(out["images"]) == 2 and len(out["frame_ms"]) == 2
    for c in out["images"].values():  # one device against itself: identical
        assert c["frame0_bit_identical"] == 1.0 and c["image_mean_z"] == 0
    assert all(np.isfinite(v["ms"]) for v in out["frame_ms"].values())
    assert len(out["traversal"]) == 2
    assert all(v["primary_mrays"] > 0 and v["shadow_mrays"] > 0 for v in out["traversal"].values())
