"""What a farm worker does with one chunk: load the scene once per process, render the chunk's warm-up and kept
frames with one Renderer, and write every kept frame that is not written yet (io/frame_files.py). Free of the
distributed engine: farm/cluster.py calls it inside a Dask task, and a render without workers calls it directly."""

from __future__ import annotations

import hashlib
import os
import socket
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..io.frame_files import write_frame, written_frames
from ..render.pipeline import Renderer
from ..scene.scene import Scene
from ..settings.table import Settings
from .chunks import Chunk
from .region import FrameRegion


@dataclass(frozen=True)
class SceneSource:
    """Where a worker gets the scene: the bytes of a scene file (shipped once to every worker), a scene file path
    or a .blend path (in a folder every worker can read), with the resolution overridden if given."""

    kind: str  # "bytes", "file" or "blend"
    path: str | None = None
    key: str = ""  # identifies the scene in a worker's cache: a digest of the bytes, or the path and its mtime
    width: int | None = None
    height: int | None = None

    @staticmethod
    def of_bytes(data: bytes, width: int | None = None, height: int | None = None) -> SceneSource:
        return SceneSource("bytes", key=hashlib.sha256(data).hexdigest(), width=width, height=height)

    @staticmethod
    def of_path(path: str | Path, width: int | None = None, height: int | None = None) -> SceneSource:
        p = Path(path).resolve()
        kind = "blend" if p.suffix == ".blend" else "file"
        return SceneSource(kind, str(p), key=f"{p}:{p.stat().st_mtime_ns}", width=width, height=height)


@dataclass(frozen=True)
class Job:
    """An animation render: frame numbers are the scene's frame indices plus `index_offset` (a .blend: Blender's
    frame numbers, the export starting at frame `index_offset`)."""

    name: str  # the output files' stem
    out: str  # the output folder, shared by the workers
    source: SceneSource
    settings: dict = field(default_factory=dict)  # Settings fields
    device: str | None = None
    index_offset: int = 0
    export_last: int = 0  # a .blend: the last Blender frame to export


@dataclass
class ChunkReport:
    """What a chunk took: frames rendered (warm-up included), written and skipped (already there); seconds spent
    loading the scene and building the renderer (0 when the worker had it), in warm-up frames and in all."""

    index: int
    worker: str
    rendered: int = 0
    written: int = 0
    skipped: int = 0
    setup_s: float = 0.0
    warmup_s: float = 0.0
    total_s: float = 0.0


# one renderer per worker process (its scene, kernels and buffers), with the render region of its frames
_CACHE: dict[tuple, tuple[Renderer, FrameRegion | None]] = {}


def render_chunk(job: Job, chunk: Chunk, scene_data: bytes | None = None,
                 on_frame: Callable[[int, float], None] | None = None) -> ChunkReport:
    """Render `chunk` of `job`; `on_frame(frame, ms)` is called after each frame written."""
    t0 = time.perf_counter()
    out = Path(job.out)
    report = ChunkReport(chunk.index, f"{socket.gethostname()}:{os.getpid()}")
    done = written_frames(out, job.name, chunk.kept)
    todo = chunk.resumed(done)
    report.skipped = len(done)
    if todo is None:
        report.total_s = time.perf_counter() - t0
        return report
    renderer, region = _renderer(job, scene_data)
    report.setup_s = time.perf_counter() - t0
    renderer.reset()  # a chunk's frames depend on the chunk only, not on what this worker rendered before
    for number in todo.rendered:
        keep = number >= todo.first and number not in done
        frame = renderer.render_frame(number - job.index_offset, sample=number, aovs=keep)
        report.rendered += 1
        if number < todo.first:
            report.warmup_s += frame.ms / 1e3
        if keep:
            write_frame(out, job.name, number, frame if region is None else region.place(frame))
            report.written += 1
            if on_frame is not None:
                on_frame(number, frame.ms)
    report.skipped = len(chunk.kept) - report.written
    report.total_s = time.perf_counter() - t0
    return report


def _renderer(job: Job, scene_data: bytes | None) -> tuple[Renderer, FrameRegion | None]:
    key = (job.source, tuple(sorted(job.settings.items())), job.device, job.index_offset, job.export_last)
    cached = _CACHE.get(key)
    if cached is None:
        _CACHE.clear()  # one job at a time per worker: let the last one's buffers go
        scene, region = load_source_region(job, scene_data)
        cached = Renderer(scene, Settings(**job.settings), job.device), region
        _CACHE[key] = cached
    return cached


def load_source_region(job: Job, scene_data: bytes | None) -> tuple[Scene, FrameRegion | None]:
    """The job's scene, and the render region of a .blend (its camera then sees the region alone)."""
    src = job.source
    if src.kind != "blend":
        return load_source(job, scene_data), None
    from ..io.blend import export_blend_region

    assert src.path is not None
    scene, region = export_blend_region(src.path, job.index_offset, job.export_last, src.width, src.height)
    return (scene if region is None else region.apply(scene)), region


def load_source(job: Job, scene_data: bytes | None) -> Scene:
    """The job's scene (a .blend's of the full frame, whatever its render region)."""
    src = job.source
    if src.kind == "blend":
        from ..io.blend import export_blend

        assert src.path is not None
        return export_blend(src.path, job.index_offset, job.export_last, src.width, src.height)
    if src.kind == "bytes":
        if scene_data is None:
            raise ValueError(f"job {job.name}: the scene's bytes did not reach the worker")
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "scene.npz"
            path.write_bytes(scene_data)
            scene = Scene.load(path)
    else:
        assert src.path is not None
        scene = Scene.load(src.path)
    if scene.camera is not None:
        scene.camera.width = src.width or scene.camera.width
        scene.camera.height = src.height or scene.camera.height
    return scene
