"""Sinks: where a pipeline's frames and tracks go (CSV files, a bag of ROS messages).

Each sink opens its file on the first frame, so that the tracks' frame and the topic are
known, writes one frame at a time (flushed, so that a crash leaves a valid file) and
closes in :meth:`close`.
"""

from __future__ import annotations

from contextlib import AbstractContextManager, suppress
from pathlib import Path
from typing import Any

from laserpeople.frame import Frame
from laserpeople.io.detections_csv import DetectionsCsvWriter
from laserpeople.io.tracks_csv import TracksCsvWriter
from laserpeople.scan import CoordinateFrame
from laserpeople.tracks import Tracks


class TracksCsvSink:
    """Tracks CSV with a ``topic`` column (the laser, or ``fused``).

    Args:
        path: The CSV to write.
        frame: Frame of the written positions (default: the tracks' own frame).
        contours: Add the ``contour`` column (group outlines).
    """

    def __init__(
        self, path: str | Path, frame: CoordinateFrame | None = None, contours: bool = False
    ) -> None:
        self.path = Path(path)
        self.frame = frame
        self.contours = contours
        self._writer: TracksCsvWriter | None = None
        self.rows = 0
        self.left: str | None = None
        """After :meth:`abandon`: what was left as it was (None: scans were written)."""

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Append the frame's tracks."""
        if tracks is None:
            return
        if self._writer is None:
            self._writer = TracksCsvWriter(
                self.path,
                frame=self.frame or tracks.frame,
                topic=frame.topic,
                contours=self.contours,
            )
        self._writer.write(tracks)
        self.rows = self._writer.rows

    @property
    def written_frame(self) -> CoordinateFrame | None:
        """The frame of the written positions (None before the first frame)."""
        return None if self._writer is None else self._writer.frame

    def close(self) -> None:
        """Close the file; with no frame at all, leave a valid file with a header only."""
        if self._writer is None:
            self._writer = TracksCsvWriter(
                self.path, frame=self.frame or "sensor", topic="", contours=self.contours
            )
        self._writer.close()

    def abandon(self) -> str | None:
        """Close the file after a failed run: one that no scan came to is left as it was.

        Returns:
            What was left as it was, for the error message (None: scans were written).
        """
        if self._writer is None:
            self.left = left_as_it_was("tracks CSV", self.path, self.path.exists())
        else:
            existed = not self._writer.created
            if self._writer.abandon():
                self.left = left_as_it_was("tracks CSV", self.path, existed)
        return self.left


def left_as_it_was(what: str, path: Path, existed: bool) -> str:
    """What a failed run that wrote no scan says about its output ``path``."""
    if existed:
        return f"the {what} {path} was left as it was (no scan was written)"
    return f"no {what} was written (no scan was)"


class DetectionsCsvSink:
    """Detections CSV with a ``topic`` column.

    Args:
        path: The CSV to write.
        per_laser: Write every laser's detections in its own sensor frame with its topic
            (needs the :class:`~laserpeople.pipeline.observe.DetectLegs` stage as
            ``stage``); otherwise the frame's legs in the frame's coordinate frame with the
            frame's topic (``fused`` for several lasers).
        stage: The leg detection stage (for ``per_laser``).
    """

    def __init__(self, path: str | Path, *, per_laser: bool = False, stage: Any = None) -> None:
        self.path = Path(path)
        self.per_laser = per_laser
        self.stage = stage
        self._writer = DetectionsCsvWriter(self.path, topic="")
        self.scans = 0
        """Scans whose detections were written."""
        self.left: str | None = None
        """After :meth:`abandon`: what was left as it was (None: scans were written)."""

    @property
    def rows(self) -> int:
        """Rows written."""
        return self._writer.rows

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Append the frame's detections."""
        self.scans += len(frame.scans)
        if self.per_laser:
            for scan, dets in zip(frame.scans, self.stage.per_scan, strict=True):
                self._writer.write(dets, topic=scan.sensor)
        elif frame.legs is not None:
            self._writer.write(frame.legs, topic=frame.topic)

    def close(self) -> None:
        """Close the file."""
        self._writer.close()

    def abandon(self) -> str | None:
        """Close the file after a failed run: one that no scan came to is left as it was.

        Returns:
            What was left as it was, for the error message (None: scans were written).
        """
        existed = not self._writer.created
        if self._writer.abandon():
            self.left = left_as_it_was("detections CSV", self.path, existed)
        return self.left


class TracksBagSink:
    """A ROS bag (``.bag``) or MCAP/db3 (ROS 2) with the frames' scans and the tracks as
    ``people_msgs/People`` and ``visualization_msgs/MarkerArray`` (see
    :mod:`laserpeople.io.tracks_bag`)."""

    def __init__(self, path: str | Path, *, scans: bool = True) -> None:
        from laserpeople.io.rosbag_writer import open_bag
        from laserpeople.io.tracks_bag import TracksBagWriter

        self.path = Path(path)
        self._context: AbstractContextManager[Any] = open_bag(self.path)
        self._writer = TracksBagWriter(self._context.__enter__(), scans=scans)
        self._closed = False

    @property
    def frames(self) -> int:
        """Frames written."""
        return self._writer.frames

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Append the frame's scans and tracks."""
        if tracks is not None:
            self._writer.write(frame.scans, tracks)

    def close(self) -> None:
        """Close the bag and move it into place."""
        if not self._closed:
            self._closed = True
            self._context.__exit__(None, None, None)

    def abandon(self) -> str | None:
        """Close the bag after a failed run: one that no frame came to is discarded (an
        older bag at its path is left as it was); one that frames came to is moved into
        place with them, as after :meth:`close`.

        Returns:
            What was left as it was, for the error message (None: frames were written).
        """
        if self._closed:
            return None
        if self._writer.frames:
            self.close()
            return None
        self._closed = True
        discard = RuntimeError("run failed before its first frame")
        with suppress(Exception):  # (the run's own error is the one to report)
            self._context.__exit__(RuntimeError, discard, None)
        return left_as_it_was("tracks bag", self.path, self.path.exists())


__all__ = ["DetectionsCsvSink", "TracksBagSink", "TracksCsvSink", "left_as_it_was"]
