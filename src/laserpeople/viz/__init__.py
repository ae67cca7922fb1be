"""Pictures, animations and exports of recordings with their tracks and ground truth.

Everything goes through a :class:`Scene` (scans of one topic, tracks and truth aligned by
scan index, in the display frame) and :func:`render`, which picks the output by extension:
``.png`` (one scan, or the trajectory overview), ``.gif``/``.mp4`` (one frame per scan),
``.mcap`` (Foxglove) or ``.rrd`` (rerun). matplotlib, pillow and rerun are imported only
when an output needs them.

Shortcuts for other commands (``laserpeople track --plot/--animate``)::

    from laserpeople.viz import plot_tracks, animate_tracks
    plot_tracks("run.bag", "tracks.csv", "tracks.png", topic="/scan", tracks_frame="world")
    animate_tracks("run.bag", "tracks.csv", "tracks.gif", topic="/scan", every=2)
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from laserpeople.io import RecordingSource
from laserpeople.scan import CoordinateFrame, Scan
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame
from laserpeople.viz.colors import PALETTE, track_color
from laserpeople.viz.figure import FrameRenderer
from laserpeople.viz.mcap_export import export_mcap
from laserpeople.viz.raster import (
    RenderResult,
    animate,
    iter_images,
    plot_overview,
    plot_scan,
    write_gif,
)
from laserpeople.viz.render import OUTPUT_KINDS, ProgressFn, render
from laserpeople.viz.rerun_export import export_rerun
from laserpeople.viz.scene import FrameChoice, Scene, SceneFrame

__all__ = [
    "OUTPUT_KINDS",
    "PALETTE",
    "FrameRenderer",
    "RenderResult",
    "Scene",
    "SceneFrame",
    "animate",
    "animate_tracks",
    "export_mcap",
    "export_rerun",
    "iter_images",
    "plot_overview",
    "plot_scan",
    "plot_tracks",
    "render",
    "track_color",
    "write_gif",
]

RecordingLike = str | Path | RecordingSource | Iterable[Scan]
TracksLike = str | Path | Iterable[Tracks] | None
TruthLike = str | Path | Iterable[TruthFrame] | None


def plot_tracks(
    recording: RecordingLike,
    tracks: TracksLike,
    out: str | Path,
    *,
    truth: TruthLike = "auto",
    topic: str | None = None,
    frame: FrameChoice = "auto",
    tracks_frame: CoordinateFrame | None = None,
    truth_frame: CoordinateFrame | None = None,
    scan: int | None = None,
) -> RenderResult:
    """PNG of a recording's tracks: the trajectory overview, or one scan when ``scan`` is
    given. ``tracks`` is a tracks CSV or a sequence of :class:`Tracks`; ``truth`` a truth
    CSV, a sequence of truth frames, ``"auto"`` (the recording's own, if any) or None;
    ``truth_frame`` the frame of a given truth's positions (None: the tracks' frame)."""
    scene = Scene(
        recording,
        tracks,
        truth,
        topic=topic,
        frame=frame,
        tracks_frame=tracks_frame,
        truth_frame=truth_frame,
    )
    return render(scene, out, scan=scan)


def animate_tracks(
    recording: RecordingLike,
    tracks: TracksLike,
    out: str | Path,
    *,
    truth: TruthLike = "auto",
    topic: str | None = None,
    frame: FrameChoice = "auto",
    tracks_frame: CoordinateFrame | None = None,
    truth_frame: CoordinateFrame | None = None,
    every: int = 1,
    fps: float | None = None,
    progress: ProgressFn | None = None,
) -> RenderResult:
    """GIF/MP4 (by extension) of a recording's tracks, one frame per ``every``-th scan;
    ``progress`` is e.g. ``lambda it, n: cli.common.progress(it, n, "drawing")``."""
    scene = Scene(
        recording,
        tracks,
        truth,
        topic=topic,
        frame=frame,
        tracks_frame=tracks_frame,
        truth_frame=truth_frame,
        every=every,
    )
    return render(scene, out, fps=fps, progress=progress)
