"""An animation rendered by many processes or machines through Dask `distributed` (docs/farm.md says why Dask):
one task per chunk of contiguous frames (farm/chunks.py), run by farm_render.render_chunk on a worker, which writes
the frames itself into the shared output folder. A local cluster of N single-threaded worker processes, or the
workers of a running scheduler. A worker that dies has its chunk re-run elsewhere (the scheduler does it, up to
`distributed.scheduler.allowed-failures` times); the re-run starts at the chunk's first missing frame, with a
warm-up of its own. Workers report every written frame as a Dask event, which drives the progress line."""

from __future__ import annotations

import logging
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field

from .chunks import Chunk
from .worker import ChunkReport, Job, render_chunk

TOPIC = "restircl-farm"  # the Dask event topic of written frames


class FarmError(RuntimeError):
    """A chunk failed on the farm (its error names the chunk and the frames)."""


@dataclass
class JobProgress:
    """Frames written over the whole job, and per worker, for the progress line (thread-safe: Dask calls
    `frame` from its event loop)."""

    total: int
    done: int = 0
    per_worker: dict[str, int] = field(default_factory=dict)
    t0: float = field(default_factory=time.perf_counter)
    lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    def frame(self, worker: str) -> None:
        with self.lock:
            self.done += 1
            self.per_worker[worker] = self.per_worker.get(worker, 0) + 1

    def rates(self) -> str:
        """'host:pid 1.2 fr/s, ...': frames per second of each worker since the job began."""
        dt = max(time.perf_counter() - self.t0, 1e-9)
        with self.lock:
            items = sorted(self.per_worker.items())
        return ", ".join(f"{w} {n / dt:.2f} fr/s" for w, n in items)


@dataclass
class FarmResult:
    reports: list[ChunkReport]
    wall_s: float
    workers: int

    @property
    def written(self) -> int:
        return sum(r.written for r in self.reports)

    @property
    def rendered(self) -> int:
        return sum(r.rendered for r in self.reports)


def _chunk_task(job: Job, chunk: Chunk, scene_data: bytes | None) -> ChunkReport:
    """The Dask task: render one chunk, reporting every written frame as an event."""
    from distributed import get_worker

    worker = get_worker()
    name = f"{worker.name}"

    def on_frame(number: int, ms: float) -> None:
        worker.log_event(TOPIC, {"frame": number, "worker": name, "ms": ms})

    return render_chunk(job, chunk, scene_data, on_frame)


def run_farm(job: Job, chunks: list[Chunk], *, workers: int | None = None, scheduler: str | None = None,
             scene_data: bytes | None = None, progress: JobProgress | None = None,
             on_update: Callable[[], None] | None = None, retries: int = 1) -> FarmResult:
    """Render `chunks` of `job` on a local cluster of `workers` processes or on the cluster at `scheduler`.
    `on_update` is called (from Dask's event thread) after each written frame, once `progress` counted it."""
    from distributed import Client, LocalCluster, as_completed

    t0 = time.perf_counter()
    if scheduler:
        cluster, client = None, Client(scheduler)
    else:
        cluster = LocalCluster(n_workers=max(int(workers or 1), 1), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
    try:
        count = len(client.scheduler_info()["workers"])

        def handle(event) -> None:
            _, msg = event
            if progress is not None:
                progress.frame(str(msg.get("worker", "?")))
            if on_update is not None:
                on_update()

        client.subscribe_topic(TOPIC, handle)
        data = client.scatter(scene_data, broadcast=True) if scene_data is not None else None
        token = uuid.uuid4().hex[:8]  # a fresh key per run: a re-run is new work, never a cached result
        futures = {client.submit(_chunk_task, job, c, data, key=f"restircl-{job.name}-{token}-chunk{c.index}",
                                 retries=retries, pure=False): c for c in chunks}
        reports = []
        for fut in as_completed(futures):
            c = futures[fut]
            try:
                reports.append(fut.result())
            except Exception as exc:
                raise FarmError(f"chunk {c.index} (frames {c.first}-{c.last}) failed: {type(exc).__name__}: "
                                f"{exc}") from exc
        client.unsubscribe_topic(TOPIC)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    reports.sort(key=lambda r: r.index)
    return FarmResult(reports, time.perf_counter() - t0, count)
