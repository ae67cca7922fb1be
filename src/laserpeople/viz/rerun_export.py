"""Export a scene to a rerun ``.rrd`` file (needs the optional ``rerun-sdk``).

Entities under ``world/``: ``scan`` (points), ``sensor``, ``legs``, ``people``,
``groups`` (contours with labels), ``covariance`` (95 % ellipses), ``truth``. Two
timelines: ``scan`` (the 0-based scan index) and ``time`` (the scan stamp [s]).
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from laserpeople.errors import LaserPeopleError
from laserpeople.viz.colors import SCAN_POINTS, SENSOR, TRUTH, track_color
from laserpeople.viz.geometry import covariance_ellipses
from laserpeople.viz.scene import ProgressFn, Scene, SceneFrame, track_positions


class RerunMissingError(LaserPeopleError):
    """The rerun SDK is not installed."""


def import_rerun() -> ModuleType:
    """The rerun SDK, or a clear error naming the extra to install."""
    try:
        import rerun
    except ImportError as exc:
        raise RerunMissingError(
            "writing .rrd needs the rerun SDK, which is not installed",
            hint="pip install 'laserpeople[rerun]'",
        ) from exc
    return rerun


def _set_time(rec: Any, scan_index: int, stamp: float) -> None:
    """Set both timelines, on rerun versions before and after the ``set_time`` API."""
    if hasattr(rec, "set_time"):
        rec.set_time("scan", sequence=scan_index)
        rec.set_time("time", duration=stamp)
    else:
        rec.set_time_sequence("scan", scan_index)
        rec.set_time_seconds("time", stamp)


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
    rec = rr.RecordingStream("laserpeople")
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
        groups = [g for g in f.tracks.of_kind("group") if g.contour.shape[0] >= 3]
        rec.log(
            "world/groups",
            rr.LineStrips2D(
                [np.vstack([g.contour, g.contour[:1]]) for g in groups],
                colors=[track_color(g.track_id, "group") for g in groups],
                labels=[f"G{g.track_id} x{g.size}" for g in groups],
            ),
        )
        all_tracks = f.tracks.tracks
        ellipses = covariance_ellipses(
            track_positions(all_tracks),
            np.array([t.covariance for t in all_tracks]).reshape(-1, 2, 2),
        )
        keep = [i for i in range(len(all_tracks)) if np.all(np.isfinite(ellipses[i]))]
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
    rec.flush()
    if n == 0:
        raise scene.empty_window_error()
    return n
