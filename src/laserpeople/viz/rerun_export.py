"""Export a scene to a rerun ``.rrd`` file (needs the optional ``rerun-sdk`` >= 0.23, for
``RecordingStream(application_id)`` and ``set_time``; the tests write and read back files
with 0.41).

Entities under ``world/``: ``scan`` (points), ``sensor``, ``legs``, ``people``,
``groups`` (closed contours, or the covariance ellipse when the contour is unknown, with
labels), ``covariance`` (95 % ellipses) and ``truth``; each is logged once per drawn scan,
empty when there is nothing to show, so that old tracks disappear. Two timelines: ``scan``
(the 0-based scan index, a sequence) and ``time`` (the scan stamp [s], a duration).
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from laserpeople.errors import LaserPeopleError
from laserpeople.viz.colors import SCAN_POINTS, SENSOR, TRUTH, track_color
from laserpeople.viz.geometry import covariance_ellipses, group_outline
from laserpeople.viz.scene import ProgressFn, Scene, SceneFrame, track_positions

APPLICATION_ID = "laserpeople"
MIN_RERUN_VERSION = "0.23"  # RecordingStream(application_id) and set_time(...)


class RerunMissingError(LaserPeopleError):
    """The rerun SDK is not installed, or is older than :data:`MIN_RERUN_VERSION`."""


def import_rerun() -> ModuleType:
    """The rerun SDK, or a clear error naming the extra to install."""
    try:
        import rerun
    except ImportError as exc:
        raise RerunMissingError(
            "writing .rrd needs the rerun SDK, which is not installed",
            hint="pip install 'laserpeople[rerun]'",
        ) from exc
    if not hasattr(rerun.RecordingStream, "set_time"):  # before 0.23
        raise RerunMissingError(
            f"writing .rrd needs rerun-sdk {MIN_RERUN_VERSION} or newer, this is "
            f"{getattr(rerun, '__version__', 'an older one')}",
            hint=f"pip install -U 'rerun-sdk>={MIN_RERUN_VERSION}'",
        )
    return rerun


def _set_time(rec: Any, scan_index: int, stamp: float) -> None:
    """Set both timelines (the ``set_time`` API of rerun >= 0.23)."""
    rec.set_time("scan", sequence=scan_index)
    rec.set_time("time", duration=stamp)


def export_rerun(
    scene: Scene,
    out: str | Path,
    *,
    progress: ProgressFn | None = None,
    total: int | None = None,
) -> int:
    """Write ``scene`` to the rerun file ``out``; returns the number of scans written."""
    rr = import_rerun()
    p = Path(out)
    p.parent.mkdir(parents=True, exist_ok=True)
    rec = rr.RecordingStream(APPLICATION_ID)
    rec.save(str(p))
    frames: Iterable[SceneFrame] = scene.frames()
    if progress is not None:
        frames = progress(frames, total)
    n = 0
    for f in frames:
        _set_time(rec, f.scan.index, f.scan.stamp)
        rec.log("world/scan", rr.Points2D(f.points, radii=0.02, colors=[SCAN_POINTS]))
        rec.log(
            "world/sensor",
            rr.Points2D([[f.sensor_pose.x, f.sensor_pose.y]], radii=0.1, colors=[SENSOR]),
        )
        for kind, entity, radius in (("leg", "legs", 0.08), ("person", "people", 0.2)):
            tracks = f.tracks.of_kind(kind)  # type: ignore[arg-type]
            rec.log(
                f"world/{entity}",
                rr.Points2D(
                    track_positions(tracks),
                    radii=radius,
                    colors=[track_color(t.track_id, t.kind) for t in tracks],
                    labels=[f"{kind[0].upper()}{t.track_id}" for t in tracks],
                ),
            )
        all_tracks = f.tracks.tracks
        ellipses = covariance_ellipses(
            track_positions(all_tracks),
            np.array([t.covariance for t in all_tracks]).reshape(-1, 2, 2),
        )
        finite = [bool(np.all(np.isfinite(e))) for e in ellipses]
        # a group's outline: the padded hull of its contour, else (e.g. read from an old
        # tracks CSV without contours) its covariance ellipse, as in the MCAP export
        outlines = [
            (t, group_outline(t.contour) if t.contour.shape[0] else ellipses[i])
            for i, t in enumerate(all_tracks)
            if t.kind == "group" and (t.contour.shape[0] or finite[i])
        ]
        rec.log(
            "world/groups",
            rr.LineStrips2D(
                [outline for _, outline in outlines],
                colors=[track_color(g.track_id, "group") for g, _ in outlines],
                labels=[f"G{g.track_id} x{g.size}" for g, _ in outlines],
            ),
        )
        keep = [i for i in range(len(all_tracks)) if finite[i]]
        rec.log(
            "world/covariance",
            rr.LineStrips2D(
                [ellipses[i] for i in keep],
                colors=[track_color(all_tracks[i].track_id, all_tracks[i].kind) for i in keep],
            ),
        )
        truth = f.truth
        rec.log(
            "world/truth",
            rr.Points2D(
                truth.positions if truth is not None else np.empty((0, 2)),
                radii=0.25,
                colors=[TRUTH],
                labels=[f"truth {i}" for i in truth.person_ids] if truth is not None else [],
            ),
        )
        n += 1
    _close(rec, p)
    if n == 0:
        p.unlink(missing_ok=True)
        raise scene.empty_window_error()
    return n


def _close(rec: Any, path: Path) -> None:
    """Flush and close the file sink, so the ``.rrd`` is complete (with its footer, on
    rerun versions that write one) when this returns rather than when ``rec`` is collected.

    Raises:
        LaserPeopleError: rerun's file writer stopped (a full disk, a file system that
            refused the write: rerun logs the cause and raises a RuntimeError that does not
            name it); names ``path``.
    """
    try:
        rec.flush()
    except RuntimeError as exc:
        raise LaserPeopleError(
            f"cannot write the output: rerun's file writer stopped ({exc}; its log line "
            "above says why, e.g. no space left on device)",
            path=path,
            hint="free disk space, or give -o a path in a writable directory",
        ) from exc
    finally:
        rec.disconnect()
