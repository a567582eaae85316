"""`restircl render SCENE --frames A-B [--workers N | --scheduler ADDRESS]`: an animation cut into chunks with
warm-up frames (farm/chunks.py), rendered in this process or on a Dask cluster (farm/cluster.py), every frame written
once and atomically; a re-run renders only the frames that are missing."""

from __future__ import annotations

import argparse
import sys
import tempfile
from dataclasses import asdict
from pathlib import Path

from ..farm.chunks import FrameRange, default_chunk_size, plan_chunks
from ..farm.worker import Job, SceneSource, render_chunk
from ..io.frame_files import written_frames
from ..settings.table import Settings
from .arguments import COUNT, load_scene
from .progress import Progress


def add_farm_arguments(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("many processes or machines (Dask distributed; docs/farm.md)")
    g.add_argument("--workers", type=COUNT, default=None,
                   help="render the frames on a local cluster of this many worker processes")
    g.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="render on the workers of a running Dask scheduler (e.g. tcp://host:8786); the output "
                        "folder (and a .blend) must be reachable by every worker under the same path")
    g.add_argument("--chunk-size", type=COUNT, default=None,
                   help="frames per chunk (default: one chunk per worker); every chunk first renders "
                        "--warmup-frames frames and discards them")


def wants_farm(a: argparse.Namespace) -> bool:
    """Whether `render` goes through the chunked path: workers, a frame range or a .blend."""
    return bool(a.workers or a.scheduler or isinstance(a.frames, FrameRange) or a.scene.endswith(".blend"))


def render_job(a: argparse.Namespace) -> int:
    settings: Settings = a.settings
    if a.mode == "still":
        raise ValueError("--workers, --scheduler and frame ranges render animations, not stills (--mode still)")
    job, frames, earliest, data = _job(a, settings)
    workers = a.workers or 1
    size = a.chunk_size or default_chunk_size(frames, workers)
    chunks = plan_chunks(frames, size, settings.warmup_frames, earliest)
    out = Path(job.out)
    already = len(written_frames(out, job.name, frames.frames()))
    print(f"{job.name}: frames {frames.first}-{frames.last} in {len(chunks)} chunks of up to {size}, "
          f"{settings.warmup_frames} warm-up frames each; {already} already written in {out}/")
    if settings.warmup_frames == 0 and len(chunks) > 1:
        print("warning: --warmup-frames 0: every chunk after the first starts without ReSTIR/TAA history (its first "
              "frames are noisier than the rest)")
    bar = Progress(frames.count, "frames")
    from ..farm.cluster import JobProgress

    progress = JobProgress(frames.count, done=already)
    bar.update(already)

    def update() -> None:
        bar.update(progress.done, progress.rates())

    if a.workers or a.scheduler:
        from ..farm.cluster import FarmError, run_farm

        try:
            result = run_farm(job, chunks, workers=a.workers, scheduler=a.scheduler, scene_data=data,
                              progress=progress, on_update=update)
        except FarmError as exc:
            print(f"restircl: error: {exc}", file=sys.stderr)
            return 2
        reports, wall, count = result.reports, result.wall_s, result.workers
    else:
        reports = []
        for c in chunks:
            reports.append(render_chunk(job, c, data, lambda *_: (progress.frame("this process"), update())))
        wall, count = sum(r.total_s for r in reports), 1
    written = sum(r.written for r in reports)
    print(f"wrote {written} frames ({sum(r.rendered for r in reports)} rendered with warm-up) in {wall:.1f} s on "
          f"{count} worker(s); {frames.count - written} were already there")
    for r in reports:
        if r.rendered:
            print(f"  chunk {r.index} on {r.worker}: {r.rendered} frames in {r.total_s:.1f} s (scene and kernels "
                  f"{r.setup_s:.1f} s, warm-up {r.warmup_s:.1f} s)")
    return 0


def _job(a: argparse.Namespace, settings: Settings) -> tuple[Job, FrameRange, int, bytes | None]:
    """The job, its frames, the earliest frame a warm-up may reach, and the scene's bytes (None: a path)."""
    common = {"out": a.out, "settings": asdict(settings), "device": a.device}
    if a.scene.endswith(".blend"):
        if not isinstance(a.frames, FrameRange):
            raise ValueError(f"{a.scene}: give the Blender frames to render as --frames A-B")
        path = Path(a.scene)
        if not path.is_file():
            raise ValueError(f"{a.scene}: no such .blend file")
        frames = a.frames
        earliest = frames.first - settings.warmup_frames  # Blender has the frames before the first one too
        source = SceneSource.of_path(path, a.width, a.height)
        return Job(path.stem, source=source, index_offset=earliest, export_last=frames.last, **common), frames, \
            earliest, None
    frames = a.frames if isinstance(a.frames, FrameRange) else FrameRange(0, a.frames - 1)
    scene = load_scene(a.scene, a.width, a.height, frames.last + 1).validate()
    if scene.frames == 1:
        raise ValueError(f"scene {scene.name} has one frame: nothing to split (render it as a still)")
    if frames.last >= scene.frames:
        raise ValueError(f"scene {scene.name} has frames 0-{scene.frames - 1}; asked for {frames.last}")
    with tempfile.TemporaryDirectory() as tmp:
        scene.save(Path(tmp) / "scene.npz")
        data = (Path(tmp) / "scene.npz").read_bytes()
    return Job(scene.name, source=SceneSource.of_bytes(data), **common), frames, 0, data
