"""The GPU half of the performance work in one short run: the same kernels on a GPU (and on a CPU device for
comparison), images compared within the noise, ms per frame at 640x360 and 1920x1080, and traversal Mrays/s.

    python tools/device_check.py                       # first GPU against the first CPU device, if both exist
    python tools/device_check.py --devices 0:0,1:0     # any devices ('P:D' or a part of the name)
    python tools/device_check.py --sizes 640x360 --frames 32 --no-traversal

Images: many_lights, still camera, no jitter; every device renders the same frames with the same seeds (the same
estimator, so the images agree to the noise unless a device computes something else). Per pixel, the mean over the
frames and its standard error (from the frame-to-frame spread); the check reports the image means' difference in
standard errors and the share of pixels whose means differ by more than 4 standard errors, against what a normal
distribution allows (6.3e-5), and the share of pixels equal bit for bit in frame 0 (rounding and FMA contraction
differ between devices, so a few differing pixels are expected). Methods: RIS (8 candidates) and ReSTIR unbiased
(its frames are correlated by temporal reuse, so its standard errors are too small: read its z figures as a trend).

Timing: `bench.time_frames` for the methods of `restircl bench frame`, animated camera, TAA on, at each size.
Traversal: `bench_traversal.run` (1M triangles, camera and shadow rays), no Embree.

With $OUT set, everything printed also goes to $OUT/device_check.json. On a machine without pip access (the device
machine of this project's sessions), carry wheels of pyopencl, pytools, platformdirs, siphash24 and
typing_extensions and install them with `pip install --no-index --no-deps --target`, then run with
PYTHONPATH=<that target>:python (docs/measurements/benchmarks.md, "GPU").
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np
from restircl import Device, Renderer, Settings, list_devices, scenes
from restircl.eval.bench.main import FRAME_METHODS
from restircl.eval.bench.timing import time_frames

Z_LIMIT = 4.0
NORMAL_TAIL = 6.3e-5  # P(|z| > 4) for a standard normal


def pick_devices(spec: str | None) -> list[Device]:
    if spec:
        return [Device(s) for s in spec.split(",") if s.strip()]
    found = list_devices()
    out = []
    for kind in ("GPU", "CPU"):
        first = next((info for info, _ in found if info.device_type == kind), None)
        if first is not None:
            out.append(Device(f"{first.platform_index}:{first.device_index}"))
    return out


def still_frames(device: Device, settings: Settings, width: int, height: int, frames: int) -> np.ndarray:
    """(frames, H, W, 3) per-frame samples of a still many_lights camera."""
    scene = scenes.many_lights(width=width, height=height, frames=1)
    r = Renderer(scene, settings, device)
    return np.stack([r.render_frame(0, still=True, aovs=False).noisy for _ in range(frames)]).astype(np.float64)


def compare(a: np.ndarray, b: np.ndarray) -> dict:
    """Agreement of two (frames, H, W, 3) sample stacks of the same estimator."""
    lum = np.array([0.2126, 0.7152, 0.0722])
    la, lb = a @ lum, b @ lum
    n = la.shape[0]
    ma, mb = la.mean(0), lb.mean(0)
    se = np.sqrt(la.var(0, ddof=1) / n + lb.var(0, ddof=1) / n)
    live = se > 0
    z = np.abs(ma - mb)[live] / se[live]
    exact = ~live
    img_a, img_b = la.mean((1, 2)), lb.mean((1, 2))
    se_img = np.sqrt(img_a.var(ddof=1) / n + img_b.var(ddof=1) / n)
    return {
        "image_mean": [float(img_a.mean()), float(img_b.mean())],
        "image_mean_z": float(abs(img_a.mean() - img_b.mean()) / se_img) if se_img > 0 else 0.0,
        "pixels_z_over_4": float((z > Z_LIMIT).mean()) if z.size else 0.0,
        "pixels_without_spread_equal": float(np.mean(ma[exact] == mb[exact])) if exact.any() else 1.0,
        "frame0_bit_identical": float(np.mean(np.all(a[0] == b[0], axis=-1))),
        "finite": bool(np.isfinite(a).all() and np.isfinite(b).all()),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--devices", default=None, help="comma-separated 'P:D' or name parts (default: first GPU, "
                                                    "first CPU)")
    ap.add_argument("--sizes", default="640x360,1920x1080", help="frame-time sizes (%(default)s)")
    ap.add_argument("--image-size", default="320x180", help="size of the compared images (%(default)s)")
    ap.add_argument("--frames", type=int, default=64, help="frames per compared image stack (%(default)s)")
    ap.add_argument("--methods", default=None, help="frame-time methods, comma-separated names of `restircl "
                                                    "bench frame` (default: all)")
    ap.add_argument("--no-traversal", action="store_true")
    ap.add_argument("--triangles", type=int, default=1_000_000)
    a = ap.parse_args(argv)
    out: dict = {"devices": [], "images": {}, "frame_ms": {}, "traversal": {}}

    def say(line: str) -> None:
        print(line, flush=True)

    for info, _ in list_devices():
        say(f"found {info.label}")
    devices = pick_devices(a.devices)
    if not devices:
        say("no device to check")
        return 1
    out["devices"] = [d.label for d in devices]
    for di, d in enumerate(devices):
        say(f"device {di}: {d.label}")
    iw, ih = (int(v) for v in a.image_size.split("x"))

    # images: the same estimator on every device
    for name, kw in (("ris (8)", dict(method="ris", candidates=8)), ("restir unbiased (4)",
                                                                     dict(method="restir", candidates=4))):
        s = Settings(seed=21, jitter=False, taa=False, **kw)
        stacks = [still_frames(d, s, iw, ih, a.frames) for d in devices]
        for k in range(1, len(stacks)):
            c = compare(stacks[0], stacks[k])
            out["images"][f"{name}: device 0 vs device {k}"] = c
            say(f"images {name} {iw}x{ih}, {a.frames} frames, device 0 vs device {k}: image means "
                f"{c['image_mean'][0]:.5g} / {c['image_mean'][1]:.5g} ({c['image_mean_z']:.2f} standard errors), "
                f"pixels beyond 4 standard errors {c['pixels_z_over_4']:.2e} (normal: {NORMAL_TAIL:.1e}), frame 0 "
                f"bit-identical {c['frame0_bit_identical'] * 100:.1f} %, finite {c['finite']}")

    # frame times
    methods = FRAME_METHODS if not a.methods else {m: FRAME_METHODS[m] for m in a.methods.split(",")}
    for di, d in enumerate(devices):
        for size in a.sizes.split(","):
            w, h = (int(v) for v in size.split("x"))
            scene = scenes.many_lights(width=w, height=h, frames=16)
            for name, kw in methods.items():
                ms, st = time_frames(scene, Settings(**kw), device=d)
                out["frame_ms"][f"device {di} {size} {name}"] = {"ms": ms, "stages": st}
                stages = ", ".join(f"{k} {v:.1f}" for k, v in st.items() if k not in ("upload", "cpu"))
                say(f"frame device {di} ({d.label}) {size} {name:<36} {ms:8.2f} ms  [{stages}]")

    # traversal
    if not a.no_traversal:
        from restircl.eval.bench import traversal as bench_traversal

        for di, d in enumerate(devices):
            t0 = time.perf_counter()
            res = bench_traversal.run(a.triangles, embree=False, print_fn=lambda s: None, device=d)
            out["traversal"][f"device {di}"] = res
            say(f"traversal device {di} ({d.label}): {res['triangles']} triangles, primary "
                f"{res['primary_mrays']:.2f} Mrays/s, shadow {res['shadow_mrays']:.2f} Mrays/s "
                f"({time.perf_counter() - t0:.0f} s with the BVH build)")

    if os.environ.get("OUT"):
        path = Path(os.environ["OUT"]) / "device_check.json"
        path.write_text(json.dumps(out, indent=1, default=float))
        say(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
