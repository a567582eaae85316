"""Issue 23: the regression cases (tests/render/test_regression_images.py) rendered with leaf packets and with the
one-by-one leaf test (bvh_packets.ENABLED on / off, each with its own leaf size), and the buffers compared bit for
bit on this device. The recorded hashes hold only on the recording device; this check holds on any.

    PYTHONPATH=python python tools/experiments/bvh_layout_images.py
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tests package

from restircl import get_device  # noqa: E402
from restircl.bvh import packets as bvh_packets  # noqa: E402

from tests import test_regression_images as regression  # noqa: E402


def render_all(packets: bool, device) -> dict[str, str]:
    saved = bvh_packets.ENABLED
    bvh_packets.ENABLED = packets
    try:
        return {f"{s}/{c}/{k}": hashlib.sha256(np.ascontiguousarray(v).tobytes()).hexdigest()
                for s, c in regression.CASES for k, v in regression._render(s, c, device).items()}
    finally:
        bvh_packets.ENABLED = saved


def main() -> int:
    device = get_device()
    off, on = render_all(False, device), render_all(True, device)
    diff = sorted(k for k in off if off[k] != on[k])
    print(f"{device.label}: {len(diff)} of {len(off)} buffers differ between leaf packets on and off", diff[:20])
    return 1 if diff else 0


if __name__ == "__main__":
    raise SystemExit(main())
