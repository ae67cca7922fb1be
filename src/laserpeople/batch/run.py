"""Run many recordings on a Dask cluster: plan, skip what is done, submit, gather, summarise.

:func:`run_batch` is the whole of ``laserpeople batch`` as a function::

    from laserpeople.batch import ClusterSpec, TrackOptions, run_batch

    result = run_batch(["a.bag", "b.npz"], "out", TrackOptions(tracker="leg-mht"),
                       ClusterSpec(workers=2))
    print(result.failed, [r.people for r in result.rows])

One task per recording (:func:`~laserpeople.batch.task.track_recording`, every laser topic
on its own or fused). Without ``scheduler`` a ``LocalCluster`` of one single-threaded
worker process per core is started (tracking holds the GIL, so processes, not threads, use
the cores); with ``scheduler`` (``tcp://HOST:PORT``) the tasks go to an existing cluster,
whose workers must see the recordings and the output folder under the same paths. A
worker that dies (killed, out of memory) has its tasks started again on another, up to
``retries`` times (Dask's ``allowed-failures`` for a local cluster); the summary's
``attempts`` column says how often each was started.
"""

from __future__ import annotations

import hashlib
import logging
import os
import signal
import threading
import time
import uuid
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from laserpeople.batch.hashing import content_hash
from laserpeople.batch.manifest import Manifest
from laserpeople.batch.options import ResolvedTrack, TrackOptions, resolve
from laserpeople.batch.summary import write_summary
from laserpeople.batch.task import (
    FAILED,
    SKIPPED,
    RecordingTask,
    TopicRow,
    clear_attempts,
    count_attempts,
    track_recording,
)
from laserpeople.batch.unused import unused_warnings
from laserpeople.errors import ConfigError
from laserpeople.io.paths import lock_for_one_writer, make_folder


@dataclass(frozen=True)
class ClusterSpec:
    """Where the tasks run.

    Attributes:
        scheduler: Address of an existing Dask scheduler (``tcp://HOST:PORT``); None starts
            a ``LocalCluster``.
        workers: Local workers (None: one per core this process may use).
        threads: Threads per local worker.
        processes: Local workers as processes (True) or threads of this process (False).
        retries: Times a task is started again after its worker died (or it raised).
        memory_limit: Memory limit per local worker (Dask's syntax, ``"auto"``: the
            machine's memory shared equally).
        connect_timeout: Seconds to wait for ``scheduler`` to answer before the run stops.
    """

    scheduler: str | None = None
    workers: int | None = None
    threads: int = 1
    processes: bool = True
    retries: int = 2
    memory_limit: str = "auto"
    connect_timeout: float = 20.0

    def __post_init__(self) -> None:
        if self.workers is not None and self.workers < 1:
            raise ConfigError(f"--workers must be at least 1, not {self.workers}")
        if self.threads < 1:
            raise ConfigError(f"--threads must be at least 1, not {self.threads}")
        if self.retries < 0:
            raise ConfigError(f"--retries must be 0 or more, not {self.retries}")


def machine_workers() -> int:
    """Cores this process may use (the default number of local workers)."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:  # not on Linux
        return max(os.cpu_count() or 1, 1)


@contextmanager
def open_client(spec: ClusterSpec) -> Iterator[Any]:
    """A ``dask.distributed.Client`` on ``spec``'s cluster (a local one is shut down after)."""
    try:
        import dask
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise ConfigError("batch runs need Dask", hint="pip install 'laserpeople[batch]'") from None
    if spec.scheduler is not None:
        try:
            client = Client(spec.scheduler, timeout=f"{spec.connect_timeout}s")
        except (OSError, ValueError, TypeError) as exc:  # unreachable, or no address
            raise ConfigError(
                f"cannot reach the Dask scheduler {spec.scheduler!r}: {exc}",
                hint="give the address it prints at its start (tcp://HOST:PORT; "
                "`dask scheduler` starts one, `dask worker ADDRESS` its workers), or "
                "drop --scheduler to run on this machine's cores",
            ) from None
        with client:
            yield client
        return
    config = {
        "distributed.scheduler.allowed-failures": spec.retries,
    }
    with dask.config.set(config), workers_deaf_to_ctrl_c():
        cluster = LocalCluster(
            n_workers=spec.workers or machine_workers(),
            threads_per_worker=spec.threads,
            processes=spec.processes,
            memory_limit=spec.memory_limit,
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        )
    with dask.config.set(config), cluster, Client(cluster) as client:
        yield client


@contextmanager
def workers_deaf_to_ctrl_c() -> Iterator[None]:
    """Start worker processes with SIGINT ignored (they inherit it): a terminal's Ctrl-C
    goes to every process of the command, and workers that took it printed a traceback each
    while this process, which took it too, shuts them down. Off the main thread (where
    Python cannot set handlers) nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    handler = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, handler)


@dataclass
class BatchResult:
    """What a batch run did.

    Attributes:
        rows: Summary rows in input order (one per recording and topic).
        seconds: Wall time [s].
        submitted: Tasks submitted (recordings not skipped).
        workers: Workers of the cluster at the start.
        summary: The summary files written (parquet, csv).
        unused: Options of the run that had no effect on some recordings, one line each,
            naming them (:func:`~laserpeople.batch.unused.unused_warnings`).
    """

    rows: list[TopicRow] = field(default_factory=list)
    seconds: float = 0.0
    submitted: int = 0
    workers: int = 0
    summary: tuple[Path, ...] = ()
    unused: list[str] = field(default_factory=list)

    @property
    def failed(self) -> int:
        """Rows that failed."""
        return sum(r.status == FAILED for r in self.rows)

    @property
    def skipped(self) -> int:
        """Rows done by an earlier run."""
        return sum(r.status == SKIPPED for r in self.rows)

    @property
    def retried(self) -> list[TopicRow]:
        """Rows whose task was started more than once (a worker died under it)."""
        return [r for r in self.rows if r.attempts > 1]

    @property
    def scans(self) -> int:
        """Scans tracked in this run (skipped rows not counted)."""
        return sum(r.scans for r in self.rows if r.status != SKIPPED)


def recording_names(paths: Sequence[Path]) -> list[str]:
    """Unique output stems: the file name without its last extension, with a short hash of
    the full path added where two recordings share a name."""
    stems = [p.stem or p.name for p in paths]
    counts: dict[str, int] = {}
    for s in stems:
        counts[s] = counts.get(s, 0) + 1
    return [
        s if counts[s] == 1 else f"{s}-{hashlib.sha256(str(p.resolve()).encode()).hexdigest()[:8]}"
        for s, p in zip(stems, paths, strict=True)
    ]


OnDone = Callable[[list[TopicRow]], None]


def run_batch(
    recordings: Sequence[str | Path],
    out: str | Path,
    options: TrackOptions | ResolvedTrack,
    cluster: ClusterSpec | None = None,
    *,
    force: bool = False,
    on_done: OnDone | None = None,
    client: Any = None,
    task_function: Callable[[RecordingTask], list[TopicRow]] = track_recording,
) -> BatchResult:
    """Track ``recordings`` on a Dask cluster into ``out`` (see the module docstring).

    Args:
        recordings: Recording paths (bags, .npz, CARMEN logs; ROS 2 bag folders).
        out: Output folder: ``tracks/``, ``manifest.jsonl``, ``summary.parquet``,
            ``summary.csv``.
        options: The options (or already resolved ones).
        cluster: Where to run (None: a local cluster sized to the machine).
        force: Track every recording, done or not.
        on_done: Called with each task's rows as it finishes (progress).
        client: An open ``dask.distributed.Client`` to use instead of ``cluster``.
        task_function: What a worker runs per recording (the tracking; a test may wrap it).

    Returns:
        The rows (failed recordings included; nothing raised for them) and timings.

    Raises:
        ConfigError: Bad options, or an output folder that is a recording.
    """
    start = time.perf_counter()
    resolved = options if isinstance(options, ResolvedTrack) else resolve(options)
    folder = Path(out)
    from laserpeople.pipeline.recording import refuse_one_for_many

    refuse_one_for_many("recordings", recordings)
    paths = [Path(r) for r in recordings]
    for p in paths:
        if folder.resolve() == p.resolve():
            raise ConfigError("--out is one of the recordings", path=p)
    make_folder(folder, "--out")
    with one_run_in(folder):
        manifest = Manifest(folder)
        slots: list[list[TopicRow] | None] = [None] * len(paths)
        tasks: list[tuple[int, RecordingTask]] = []
        for k, (path, name) in enumerate(zip(paths, recording_names(paths), strict=True)):
            try:
                digest = content_hash(path)
            except Exception as exc:
                slots[k] = [_row_failed(path, name, exc, resolved)]
                if on_done is not None:
                    on_done(slots[k] or [])
                continue
            done = None if force else manifest.done_rows(name, digest, resolved.digest)
            if done is not None:
                slots[k] = done
                if on_done is not None:
                    on_done(done)
                continue
            tasks.append(
                (k, RecordingTask(path.absolute(), name, folder.absolute(), resolved, digest))
            )
        result = BatchResult()
        if tasks:
            if client is not None:
                _gather(
                    client, tasks, slots, manifest, cluster or ClusterSpec(), on_done, task_function
                )
                result.workers = len(client.scheduler_info().get("workers", {}))
            else:
                spec = cluster or ClusterSpec()
                with open_client(spec) as own:
                    result.workers = len(own.scheduler_info().get("workers", {}))
                    _gather(own, tasks, slots, manifest, spec, on_done, task_function)
        manifest.compact()
        result.rows = [row for rows in slots for row in (rows or [])]
        result.submitted = len(tasks)
        result.summary = write_summary(result.rows, folder)
        result.unused = unused_warnings(result.rows, resolved.options)
        result.seconds = time.perf_counter() - start
        return result


@contextmanager
def one_run_in(folder: Path) -> Iterator[None]:
    """Hold ``folder`` (a batch output folder) for this run alone: two runs into one folder
    at once took each other's task starts for workers that died, and wrote one summary over
    the other.

    Raises:
        ConfigError: another run holds it; names the folder.
    """
    marker = folder / ".batch" / "run.lock"
    marker.parent.mkdir(parents=True, exist_ok=True)
    with open(marker, "a") as fh:
        if not lock_for_one_writer(fh.fileno()):
            raise ConfigError(
                "another batch run is writing into this folder now",
                path=folder,
                hint="wait until it has finished, or give --out another folder",
            )
        yield


def _gather(
    client: Any,
    tasks: list[tuple[int, RecordingTask]],
    slots: list[list[TopicRow] | None],
    manifest: Manifest,
    spec: ClusterSpec,
    on_done: OnDone | None,
    task_function: Callable[[RecordingTask], list[TopicRow]],
) -> None:
    from dask.distributed import as_completed

    run = uuid.uuid4().hex[:8]
    futures = {}
    for k, task in tasks:
        clear_attempts(task.out, task.key)
        future = client.submit(
            task_function, task, key=f"{task.key}-{run}", retries=spec.retries, pure=False
        )
        futures[future] = (k, task)
    for future in as_completed(futures):
        k, task = futures[future]
        try:
            rows = list(future.result())
        except Exception as exc:  # the worker died more often than allowed, or was lost
            rows = [_row_failed(task.recording, task.name, exc, task.resolved, task.input_hash)]
        attempts = max(count_attempts(task.out, task.key), 1)
        rows = [replace(r, attempts=attempts) for r in rows]
        slots[k] = rows
        manifest.record(task.name, task.input_hash, task.resolved.digest, rows)
        if on_done is not None:
            on_done(rows)
        future.release()


def _row_failed(
    path: Path, name: str, exc: BaseException, resolved: ResolvedTrack, input_hash: str = ""
) -> TopicRow:
    from laserpeople.errors import LaserPeopleError

    text = str(exc) if isinstance(exc, LaserPeopleError) else f"{type(exc).__name__}: {exc}"
    return TopicRow(
        recording=str(path),
        name=name,
        topic="",
        status=FAILED,
        error=text,
        input_hash=input_hash,
        config_hash=resolved.digest,
    )


__all__ = [
    "BatchResult",
    "ClusterSpec",
    "machine_workers",
    "open_client",
    "recording_names",
    "run_batch",
]
