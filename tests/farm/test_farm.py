"""An animation rendered in chunks on a local Dask cluster of 2 worker processes (farm/cluster.py): the frames agree
with a single-process render, the first frame of a chunk is as good as with full history thanks to its warm-up (and
measurably worse without it), a killed worker's chunk is re-done, and a finished job re-run renders nothing."""

from __future__ import annotations

import logging
import math
import os
import signal
import tempfile
import threading
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

from restircl import Renderer, Settings, read_exr, scenes  # noqa: E402
from restircl.farm.chunks import Chunk, FrameRange, plan_chunks  # noqa: E402
from restircl.farm.cluster import JobProgress, run_farm  # noqa: E402
from restircl.farm.worker import Job, SceneSource, render_chunk  # noqa: E402
from restircl.io.frame_files import frame_paths, written_frames  # noqa: E402

W, H, FRAMES, CHUNK, WARMUP = 32, 18, 64, 8, 16


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=logging.ERROR) as c, distributed.Client(c) as client:
        yield c, client


@pytest.fixture(scope="module")
def scene_bytes():
    scene = scenes.many_lights(width=W, height=H, frames=FRAMES)
    with tempfile.TemporaryDirectory() as tmp:
        scene.save(Path(tmp) / "s.npz")
        return scene, (Path(tmp) / "s.npz").read_bytes()


def job(out: Path, data: bytes, **settings) -> Job:
    return Job("anim", str(out), SceneSource.of_bytes(data), asdict(Settings(**settings)))


def colour(out: Path, frame: int) -> np.ndarray:
    ch = read_exr(frame_paths(out, "anim", frame)[0])
    return np.stack([ch[c] for c in "RGB"], axis=-1).astype(np.float64)


def tonemapped_mse(img: np.ndarray, ref: np.ndarray) -> float:
    # tone-mapped: the lamps seen directly (radiance ~100) would otherwise decide the error by their edges alone
    return float(np.mean((img / (1 + img) - ref / (1 + ref)) ** 2))


def test_frame_keys_do_not_depend_on_the_chunking(tmp_path, scene_bytes):
    """Without reuse and TAA a frame depends on its camera and its random stream only: chunks of 4 without warm-up
    give the single-process frames bit for bit (with the stream keyed by the place in the chunk they would not)."""
    _, data = scene_bytes
    one, cut = job(tmp_path / "one", data, method="ris", taa=False), job(tmp_path / "cut", data, method="ris",
                                                                          taa=False)
    render_chunk(one, Chunk(0, 0, 0, 11), data)
    for c in plan_chunks(FrameRange(0, 11), 4, 0):
        render_chunk(cut, c, data)
    for f in range(12):
        assert np.array_equal(colour(tmp_path / "one", f), colour(tmp_path / "cut", f)), f


def test_chunked_render_agrees_and_warmup_gives_chunk_starts_their_history(tmp_path, cluster, scene_bytes):
    """ReSTIR + TAA, moving camera, 64 frames in chunks of 8. A chunk's first frame is compared with the same frame
    of the single-process render (full history), against a reference, paired per chunk start (the frames' own
    content differs more from one frame to the next than warm-up matters, so neighbours are reported, not tested):
    with 16 warm-up frames its excess error is zero within 3 standard errors of the chunk starts; with none it is
    positive beyond 3 of them."""
    scene, data = scene_bytes
    address = cluster[0].scheduler_address
    single = job(tmp_path / "single", data)
    render_chunk(single, Chunk(0, 0, 0, FRAMES - 1), data)
    runs = {}
    for warmup in (WARMUP, 0):
        j = job(tmp_path / f"w{warmup}", data)
        chunks = plan_chunks(FrameRange(0, FRAMES - 1), CHUNK, warmup)
        res = run_farm(j, chunks, scheduler=address, scene_data=data, progress=JobProgress(FRAMES))
        assert res.written == FRAMES and res.workers == 2
        assert sum(r.rendered for r in res.reports) == FRAMES + sum(c.first - c.start for c in chunks)
        assert len({r.worker for r in res.reports}) == 2  # both workers took chunks
        runs[warmup] = tmp_path / f"w{warmup}"
    # chunks whose warm-up reaches frame 0 start like the single-process render: the same frames, bit for bit,
    # rendered in other processes
    for f in range(2 * CHUNK):
        assert np.array_equal(colour(runs[WARMUP], f), colour(tmp_path / "single", f)), f
    starts = [s for s in range(CHUNK, FRAMES, CHUNK) if s - WARMUP > 0]
    ref = Renderer(scene, Settings(method="ris"))
    excess: dict[int, list[float]] = {WARMUP: [], 0: []}
    for s in starts:
        r = ref.render_still(s, 64).color[..., :3].astype(np.float64)
        e_single = tonemapped_mse(colour(tmp_path / "single", s), r)
        for warmup, out in runs.items():
            excess[warmup].append(tonemapped_mse(colour(out, s), r) - e_single)
        print(f"frame {s}: single {e_single:.4f}, warm-up {WARMUP} {e_single + excess[WARMUP][-1]:.4f}, "
              f"none {e_single + excess[0][-1]:.4f}")
    for warmup, d in excess.items():
        d = np.asarray(d)
        mean, se = d.mean(), d.std(ddof=1) / math.sqrt(len(d))
        print(f"warm-up {warmup}: excess error of a chunk's first frame {mean:.2e} +- {se:.2e}")
        if warmup:
            assert mean <= 3 * se, (warmup, d)
        else:
            assert mean > 3 * se, (warmup, d)  # the test can fail: without warm-up the chunk starts are worse


def _pid_running(client, key_part: str) -> int | None:
    for addr, keys in client.processing().items():
        if any(key_part in str(k) for k in keys):
            return client.run(os.getpid, workers=[addr])[addr]
    return None


def test_killed_worker_chunk_is_redone_and_rerun_renders_nothing(tmp_path, cluster, scene_bytes):
    """SIGKILL the worker process rendering chunk 1 once it wrote a few frames: the nanny restarts it, the scheduler
    re-runs the chunk, which resumes at its first missing frame (with its warm-up). Every frame ends up written
    and readable. Then the same job again: nothing rendered, no file touched."""
    _, data = scene_bytes
    _, client = cluster
    out = tmp_path / "kill"
    j = job(out, data)
    chunks = plan_chunks(FrameRange(0, FRAMES - 1), FRAMES // 2, 4)
    done: dict = {}
    t = threading.Thread(target=lambda: done.update(res=run_farm(j, chunks, scheduler=cluster[0].scheduler_address,
                                                                 scene_data=data)))
    t.start()
    killed, before = None, set()
    deadline = time.monotonic() + 120
    while killed is None and time.monotonic() < deadline and t.is_alive():
        before = written_frames(out, "anim", chunks[1].kept)
        if len(before) >= 2:
            killed = _pid_running(client, "chunk1")
            if killed is not None:
                os.kill(killed, signal.SIGKILL)
        time.sleep(0.005)
    t.join(300)
    assert killed is not None, "chunk 1 finished before it could be killed: nothing was tested"
    assert len(before) < len(chunks[1].kept), "chunk 1 was done when killed"
    res = done["res"]
    report = res.reports[1]
    assert report.worker.split(":")[1] != str(killed)
    assert report.skipped >= len(before) >= 2 and report.written == len(chunks[1].kept) - report.skipped
    assert written_frames(out, "anim", range(FRAMES)) == set(range(FRAMES))
    for f in range(FRAMES):
        assert np.all(np.isfinite(colour(out, f)))
    mtimes = {p: p.stat().st_mtime_ns for p in out.glob("anim_*")}
    again = run_farm(j, chunks, scheduler=cluster[0].scheduler_address, scene_data=data)
    assert again.rendered == 0 and again.written == 0
    assert {p: p.stat().st_mtime_ns for p in out.glob("anim_*")} == mtimes
