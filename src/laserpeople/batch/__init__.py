"""Batch runs: track thousands of recordings on a Dask cluster (``laserpeople batch``).

One task per recording (:mod:`.task`), every option of ``track`` (:mod:`.options`), a
manifest keyed by content and configuration so that a rerun does only what is not done
(:mod:`.manifest`), tracks as CSV or Parquet (:mod:`.parquet`), one summary table
(:mod:`.summary`), the run on a local or remote cluster (:mod:`.run`) and parameter
sweeps over labelled recordings (:mod:`.sweep`). Dask and pyarrow come with the ``batch``
extra; they are imported only when a run starts.
"""

from laserpeople.batch.options import ResolvedTrack, TrackOptions, parse_topics, resolve
from laserpeople.batch.run import BatchResult, ClusterSpec, machine_workers, open_client, run_batch
from laserpeople.batch.task import RecordingTask, TopicRow, track_recording

__all__ = [
    "BatchResult",
    "ClusterSpec",
    "RecordingTask",
    "ResolvedTrack",
    "TopicRow",
    "TrackOptions",
    "machine_workers",
    "open_client",
    "parse_topics",
    "resolve",
    "run_batch",
    "track_recording",
]
