"""Reader and writer of CARMEN log files (the classic Freiburg format), plain or gzipped.

One message per line, fields separated by white space, the keyword first. The scan lines
read here (``n`` readings, angles in radians, ranges in metres, times in seconds)::

    FLASER n r_1..r_n x y theta odom_x odom_y odom_theta timestamp host logger_timestamp
    RLASER (same as FLASER, the rear laser)
    RAWLASER1..4 laser_type start_angle fov angular_res max_range accuracy remission_mode
                 n r_1..r_n m e_1..e_m timestamp host logger_timestamp
    ROBOTLASER1..2 (RAWLASER's fields up to the remissions, then)
                 laser_x laser_y laser_theta robot_x robot_y robot_theta
                 tv rv forward_safety_dist side_safety_dist turn_axis
                 timestamp host logger_timestamp
    ODOM x y theta tv rv accel timestamp host logger_timestamp

Every other keyword (``PARAM``, ``SYNC``, ``TRUTH``, ...) and ``#`` comments are not
scans and are counted in :attr:`CarmenRecording.other_lines`.

Conventions:

* ``Scan.sensor`` is the keyword (``RAWLASER1``, ``FLASER``, ...); ``Scan.index`` counts the
  lines of that keyword from 0; ``Scan.stamp`` is the ``timestamp`` field (the sensor's
  time; the logger's own time is not used).
* FLASER/RLASER carry no angles: they cover 180 degrees from -90 degrees, at
  ``pi / (n - 1)`` for an odd ``n`` (181, 361) and ``pi / n`` for an even ``n`` (180, 360).
* CARMEN marks "no return" with the maximum range: readings ``>= max_range`` become
  ``inf`` (invalid). FLASER/RLASER have no maximum range field;
  :attr:`CarmenParams.flaser_max_range` is used.
* Sensor poses: the laser pose of ROBOTLASER lines and the first pose (``x y theta``) of
  FLASER/RLASER lines; RAWLASER scans get the ODOM pose interpolated at the scan time,
  composed with the sensor's entry in ``laser_offsets`` (default: the laser sits at the
  robot's origin, as the CARMEN-to-ROS conversion of the corridor bags assumes).
"""

from __future__ import annotations

import gzip
import heapq
import math
import os
import tempfile
import zlib
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import numpy as np

from laserpeople.config import param
from laserpeople.errors import (
    RecordingError,
    ScanFormatError,
    UnsortedStampsError,
)
from laserpeople.io.damage import BACKWARD_HINT, DamagedRecords, OnError, stamp_back
from laserpeople.io.npz import TopicInfo
from laserpeople.io.paths import not_found
from laserpeople.io.poses import PoseParams, PoseTrack
from laserpeople.io.topics import match_topics
from laserpeople.scan import Pose2D, Scan, wrap_angle
from laserpeople.truth import TruthFrame

FLASER_KEYWORDS = ("FLASER", "RLASER")
RAWLASER_KEYWORDS = ("RAWLASER1", "RAWLASER2", "RAWLASER3", "RAWLASER4")
ROBOTLASER_KEYWORDS = ("ROBOTLASER1", "ROBOTLASER2")
SCAN_KEYWORDS = FLASER_KEYWORDS + RAWLASER_KEYWORDS + ROBOTLASER_KEYWORDS
MSGTYPE = "carmen/{}"


@dataclass(frozen=True)
class CarmenParams:
    """Reading choices for CARMEN logs."""

    flaser_max_range: float = param(
        81.9, "SICK LMS 2xx data sheet (CARMEN's max-range reading)", "range limit of FLASER", "m"
    )


class _BadLineError(Exception):
    """A malformed line (converted to a RecordingError naming file and line)."""


@dataclass(frozen=True)
class _Parsed:
    keyword: str
    stamp: float
    angle_min: float
    angle_max: float
    angle_increment: float
    ranges: np.ndarray
    max_range: float
    intensities: np.ndarray | None
    laser_pose: Pose2D | None


def _pose(values: np.ndarray) -> Pose2D | None:
    """The pose ``x y theta`` of a line; None when a value is not finite."""
    if not np.all(np.isfinite(values[:3])):
        return None
    theta = float(values[2])
    if not -math.pi < theta <= math.pi:
        theta = float(wrap_angle(theta))
    return Pose2D(float(values[0]), float(values[1]), theta)


def _floats(tokens: list[str], start: int, count: int) -> np.ndarray:
    if count < 0 or start + count > len(tokens):
        raise _BadLineError(f"expected {count} numbers from field {start}, line has {len(tokens)}")
    try:
        return np.array(tokens[start : start + count], dtype=np.float64)
    except ValueError as exc:
        raise _BadLineError(
            f"not a number among fields {start}..{start + count - 1}: {exc}"
        ) from None


def _int(tokens: list[str], i: int) -> int:
    if i >= len(tokens):
        raise _BadLineError(f"line ends at field {len(tokens)}, expected a count at field {i}")
    try:
        value = int(float(tokens[i]))
    except ValueError:
        raise _BadLineError(f"field {i} should be a count, got {tokens[i]!r}") from None
    if value < 0:
        raise _BadLineError(f"field {i} is a negative count {value}")
    return value


def _stamp_at(tokens: list[str], i: int) -> float:
    if i >= len(tokens):
        raise _BadLineError(f"line ends at field {len(tokens)} before its timestamp")
    try:
        stamp = float(tokens[i])
    except ValueError:
        raise _BadLineError(f"timestamp field {i} is {tokens[i]!r}") from None
    if not math.isfinite(stamp):
        raise _BadLineError(f"timestamp field {i} is {tokens[i]!r}")
    return stamp


def _no_return(ranges: np.ndarray, max_range: float) -> np.ndarray:
    out = ranges.copy()
    with np.errstate(invalid="ignore"):
        out[out >= max_range] = np.inf
    return out


def parse_scan_line(tokens: list[str], params: CarmenParams) -> _Parsed:
    """Parse the tokens of one FLASER/RLASER/RAWLASERn/ROBOTLASERn line."""
    keyword = tokens[0]
    if keyword in FLASER_KEYWORDS:
        n = _int(tokens, 1)
        ranges = _floats(tokens, 2, n)
        poses = _floats(tokens, 2 + n, 6)
        stamp = _stamp_at(tokens, 8 + n)
        increment = math.pi / (n - 1) if n % 2 == 1 and n > 1 else math.pi / max(n, 1)
        max_range = params.flaser_max_range
        return _Parsed(
            keyword,
            stamp,
            -0.5 * math.pi,
            -0.5 * math.pi + (n - 1) * increment,
            increment,
            _no_return(ranges, max_range),
            max_range,
            None,
            _pose(poses[:3]),
        )
    head = _floats(tokens, 1, 6)  # laser_type start fov res max_range accuracy
    start, fov, res, max_range = (float(v) for v in head[1:5])
    n = _int(tokens, 8)
    ranges = _floats(tokens, 9, n)
    m = _int(tokens, 9 + n)
    remissions = _floats(tokens, 10 + n, m)
    i = 10 + n + m
    pose = None
    if keyword in ROBOTLASER_KEYWORDS:
        poses = _floats(tokens, i, 11)
        pose = _pose(poses[:3])
        i += 11
    stamp = _stamp_at(tokens, i)
    if not (math.isfinite(max_range) and max_range > 0.0):
        raise _BadLineError(f"maximum range {max_range!r} is not a positive number")
    return _Parsed(
        keyword,
        stamp,
        start,
        start + fov,
        res,
        _no_return(ranges, max_range),
        max_range,
        remissions if m == n and n > 0 else None,
        pose,
    )


def _open_text(path: Path) -> IO[str]:
    with open(path, "rb") as fh:
        magic = fh.read(2)
    if magic == b"\x1f\x8b":
        return gzip.open(path, "rt", encoding="latin-1")
    return open(path, encoding="latin-1")


_READ_ERRORS = (OSError, EOFError, zlib.error, UnicodeDecodeError)


class CarmenRecording:
    """A CARMEN log as a :class:`~laserpeople.io.RecordingSource`.

    Args:
        path: ``.log``/``.clf``/``.carmen``/``.txt`` file, optionally gzipped (``.gz``).
        poses: Give sensor poses (``False``: every scan gets ``pose=None``, uncounted).
        skip_bad_lines: Skip malformed scan/ODOM lines and count them in
            :attr:`bad_lines` (with the first few in :attr:`bad_line_examples`) instead of
            raising :class:`~laserpeople.errors.RecordingError` at the first one.
        laser_offsets: Pose of a RAWLASER sensor on the robot (sensor name -> pose),
            composed with the interpolated ODOM pose.
        params: Range limit for FLASER.
        pose_params: Interpolation tolerances for ODOM.
        on_error: ``"skip"`` is ``skip_bad_lines=True`` and also skips scan lines whose
            header disagrees with their data; ``"stop"`` (default) raises at the first.
    """

    def __init__(
        self,
        path: str | Path,
        *,
        poses: bool = True,
        skip_bad_lines: bool = False,
        laser_offsets: Mapping[str, Pose2D] | None = None,
        params: CarmenParams | None = None,
        pose_params: PoseParams | None = None,
        on_error: OnError = "stop",
    ) -> None:
        self.path = Path(path)
        self.damaged = DamagedRecords(self.path, on_error)
        if not self.path.exists():
            raise RecordingError(not_found(self.path), path=self.path, hint="check the path")
        if self.path.is_dir():
            raise RecordingError(
                "is a directory, not a CARMEN log", path=self.path, hint="give the log file itself"
            )
        self.use_poses = poses
        self.skip_bad_lines = skip_bad_lines or on_error == "skip"
        self.laser_offsets = dict(laser_offsets or {})
        self.params = params or CarmenParams()
        self.pose_params = pose_params or PoseParams()
        self.world_frame: str | None = "odom" if poses else None
        self.counts: Counter[str] = Counter()
        self.other_lines: Counter[str] = Counter()
        self.bad_lines = 0
        self.bad_line_examples: list[str] = []
        self._odom: PoseTrack | None = None
        self._scan_pass()
        self._odom_bad_lines = self.bad_lines
        self.scans_without_pose = 0
        self.scans_read = 0
        self.pose_misses: Counter[tuple[str, str]] = Counter()

    def __enter__(self) -> CarmenRecording:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Nothing stays open between :meth:`scans` calls."""

    # -- first pass: counts and odometry -----------------------------------------------------
    def _bad(self, lineno: int, message: str) -> None:
        if not self.skip_bad_lines:
            raise RecordingError(
                f"line {lineno}: {message}",
                path=self.path,
                hint="fix or delete the line (a log cut short: delete its last line), or use "
                "--on-error skip to skip and count such lines (from Python: "
                "CarmenRecording(path, skip_bad_lines=True))",
            )
        self.bad_lines += 1
        self.damaged.count += 1
        if len(self.bad_line_examples) < 5:
            self.bad_line_examples.append(f"line {lineno}: {message}")
            self.damaged.examples.append(f"line {lineno}: {message}")

    def _scan_pass(self) -> None:
        odom_rows: list[tuple[float, float, float, float]] = []
        try:
            with _open_text(self.path) as fh:
                for lineno, line in enumerate(fh, start=1):
                    tokens = line.split()
                    if not tokens:
                        continue
                    key = tokens[0]
                    if key in SCAN_KEYWORDS:
                        self.counts[key] += 1
                    elif key == "ODOM":
                        try:
                            xyt = _floats(tokens, 1, 3)
                            stamp = _stamp_at(tokens, 7)
                        except _BadLineError as exc:
                            self._bad(lineno, f"ODOM: {exc}")
                            continue
                        if not np.all(np.isfinite(xyt)):
                            self._bad(lineno, "ODOM: pose is not finite")
                            continue
                        odom_rows.append((stamp, float(xyt[0]), float(xyt[1]), float(xyt[2])))
                    else:
                        self.other_lines["#" if key.startswith("#") else key] += 1
        except _READ_ERRORS as exc:
            raise RecordingError(
                f"cannot read CARMEN log: {exc}",
                path=self.path,
                hint="the file is corrupt or truncated; re-copy it (gunzip -t checks a .gz)",
            ) from exc
        if not self.counts:
            table = any(key.startswith("scan,stamp,") for key in self.other_lines)
            raise RecordingError(
                "no laser lines (FLASER, RLASER, RAWLASER1-4, ROBOTLASER1-2) in this file"
                + (": it is a CSV table written by laserpeople (scan,stamp,...)" if table else ""),
                path=self.path,
                hint="give the recording it was made from; the table goes to `view --tracks` "
                "or `evaluate`"
                if table
                else "is this a CARMEN log?",
            )
        if odom_rows:
            arr = np.asarray(odom_rows, dtype=np.float64)
            self._odom = PoseTrack(arr[:, 0], arr[:, 1:])

    # -- protocol ------------------------------------------------------------------------------
    @property
    def has_truth(self) -> bool:
        """CARMEN logs carry no per-person ground truth."""
        return False

    def truth(self) -> Iterator[TruthFrame]:
        """No ground truth: an empty stream."""
        return iter(())

    @property
    def odometry(self) -> PoseTrack | None:
        """The ODOM lines as a pose track, if any."""
        return self._odom

    def topics(self) -> list[TopicInfo]:
        """One entry per laser keyword present, with its line count."""
        return [
            TopicInfo(k, MSGTYPE.format(k), self.counts[k]) for k in SCAN_KEYWORDS if self.counts[k]
        ]

    def resolve_topics(self, topics: Sequence[str] | None) -> list[str]:
        """Keywords for ``topics`` (all present when None; a leading ``/`` is allowed)."""
        present = [t.name for t in self.topics()]
        if not topics:
            return present
        return match_topics(
            topics,
            present,
            key=lambda name: name.lstrip("/").upper(),
            path=self.path,
            what="laser",
            hint=f"lasers here: {', '.join(present)}",
        )

    def pose_summary(self) -> str:
        """Why scans of the last :meth:`scans` run got no pose, one line per reason."""
        if not self.use_poses:
            return "poses not requested"
        lines = []
        if self.scans_without_pose == 0:
            lines.append("every scan has a pose")
        else:
            lines.append(f"{self.scans_without_pose} of {self.scans_read} scans have no pose")
            for (topic, reason), n in sorted(self.pose_misses.items()):
                lines.append(f"  {topic}: {n} scans: {reason}")
        return "\n".join(lines)

    def scans(self, topics: Sequence[str] | None = None) -> Iterator[Scan]:
        """Scans of the given lasers in stamp order.

        Raises:
            TopicNotFoundError: A requested laser keyword is not in the log.
            RecordingError: A malformed line (unless ``skip_bad_lines``), or an unreadable file.
            UnsortedStampsError: Stamps go backwards within one laser.
            ScanFormatError: A scan's beam count disagrees with its angles.
        """
        names = self.resolve_topics(topics)
        self.bad_lines = self._odom_bad_lines  # scan lines are parsed (and counted) here
        self.scans_without_pose = 0
        self.scans_read = 0
        self.pose_misses.clear()
        streams = [self._keyword_scans(name) for name in names]
        merged = streams[0] if len(streams) == 1 else heapq.merge(*streams, key=_by_stamp)
        for scan in merged:
            self.scans_read += 1
            yield scan
        self.damaged.check_read(self.scans_read)

    def _pose_for(self, parsed: _Parsed) -> tuple[Pose2D | None, str]:
        if parsed.laser_pose is not None:
            return parsed.laser_pose, ""
        if self._odom is None:
            return None, "no ODOM lines in the log"
        p = self.pose_params
        robot = self._odom.at(parsed.stamp, p.tolerance, p.max_gap)
        if robot is None:
            return None, "stamp not covered by ODOM"
        offset = self.laser_offsets.get(parsed.keyword)
        return (robot if offset is None else robot.compose(offset)), ""

    def _keyword_scans(self, keyword: str) -> Iterator[Scan]:
        index = -1
        last = -math.inf
        source = str(self.path)
        try:
            with _open_text(self.path) as fh:
                for lineno, line in enumerate(fh, start=1):
                    if not line.startswith(keyword):
                        continue
                    tokens = line.split()
                    if not tokens or tokens[0] != keyword:
                        continue
                    try:
                        parsed = parse_scan_line(tokens, self.params)
                    except _BadLineError as exc:
                        self._bad(lineno, f"{keyword}: {exc}")
                        continue
                    index += 1
                    if parsed.stamp < last:  # (it would unsort the lasers' merge)
                        reason = f"{keyword}: {stamp_back(parsed.stamp, last)}"
                        if self.skip_bad_lines:
                            self._bad(lineno, reason)
                            continue
                        raise UnsortedStampsError(
                            f"line {lineno}: {reason}",
                            path=self.path,
                            scan=index,
                            hint=BACKWARD_HINT,
                        )
                    last = parsed.stamp
                    pose = None
                    if self.use_poses:
                        pose, reason = self._pose_for(parsed)
                        if pose is None:
                            self.scans_without_pose += 1
                            self.pose_misses[(keyword, reason)] += 1
                    try:
                        yield Scan.from_angles(
                            parsed.stamp,
                            parsed.angle_min,
                            parsed.angle_max,
                            parsed.angle_increment,
                            parsed.ranges,
                            range_min=0.0,
                            range_max=parsed.max_range,
                            intensities=parsed.intensities,
                            sensor=keyword,
                            pose=pose,
                            index=index,
                            source=source,
                        )
                    except ScanFormatError as exc:
                        if self.skip_bad_lines:
                            self._bad(lineno, f"{keyword}: {exc.detail}")
                            continue
                        raise ScanFormatError(
                            f"line {lineno}: {exc.detail}",
                            path=self.path,
                            scan=index,
                            hint=exc.hint,
                        ) from exc
        except _READ_ERRORS as exc:
            raise RecordingError(
                f"cannot read CARMEN log after {keyword} scan {index}: {exc}",
                path=self.path,
                scan=index + 1,
                hint="the file is corrupt or truncated; re-copy it",
            ) from exc


def _by_stamp(scan: Scan) -> float:
    return scan.stamp


@dataclass(frozen=True)
class CarmenWriteResult:
    """What :func:`write_carmen_log` wrote."""

    scans: int
    odom_lines: int
    poses_not_written: int


def write_carmen_log(
    path: str | Path,
    scans: Iterable[Scan],
    *,
    odom_sensor: str | None = None,
    hostname: str = "laserpeople",
) -> CarmenWriteResult:
    """Write scans as ``RAWLASERk`` lines and the poses of one sensor as ``ODOM`` lines.

    Sensors map to ``RAWLASER1..4`` in order of appearance (a sensor already named
    ``RAWLASERk`` keeps its number). Invalid beams (NaN, inf, out of limits) are written as
    the maximum range, CARMEN's "no return". The poses of ``odom_sensor`` (default: the
    first sensor) become ``ODOM`` lines at the scan stamps, so reading the log back gives
    that sensor its poses; poses of other sensors cannot be expressed with RAWLASER and
    are counted in :attr:`CarmenWriteResult.poses_not_written`. Gzipped when ``path`` ends
    in ``.gz``. Written to a temporary name and moved into place; if the scan stream fails,
    the lines written so far are kept at ``path`` and the error is raised again.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    numbers: dict[str, int] = {}
    n_scans = n_odom = n_dropped = 0
    failure: BaseException | None = None
    gzipped = target.suffix.lower() == ".gz"
    try:
        with (
            gzip.open(tmp, "wt", encoding="ascii") if gzipped else open(tmp, "w", encoding="ascii")
        ) as out:
            out.write("# CARMEN log written by laserpeople\n")
            try:
                for scan in scans:
                    if odom_sensor is None:
                        odom_sensor = scan.sensor
                    k = numbers.get(scan.sensor)
                    if k is None:
                        taken = set(numbers.values())
                        named = scan.sensor.lstrip("/").upper()
                        if named in RAWLASER_KEYWORDS and int(named[-1]) not in taken:
                            k = int(named[-1])
                        else:
                            free = [i for i in range(1, 5) if i not in taken]
                            if not free:
                                raise RecordingError(
                                    f"more than 4 sensors (at {scan.sensor!r})",
                                    path=target,
                                    scan=scan.index,
                                    hint="CARMEN has RAWLASER1..4 only; write fewer sensors",
                                )
                            k = free[0]
                        numbers[scan.sensor] = k
                    if scan.pose is not None:
                        if scan.sensor == odom_sensor:
                            p = scan.pose
                            out.write(
                                f"ODOM {p.x:.9g} {p.y:.9g} {p.theta:.9g} 0 0 0 "
                                f"{scan.stamp:.6f} {hostname} {scan.stamp:.6f}\n"
                            )
                            n_odom += 1
                        else:
                            n_dropped += 1
                    out.write(_rawlaser_line(scan, k, hostname))
                    n_scans += 1
            except BaseException as exc:  # keep what was written, then re-raise
                failure = exc
        os.replace(tmp, target)
    finally:
        if tmp.exists():
            tmp.unlink()
    if failure is not None:
        raise failure
    return CarmenWriteResult(n_scans, n_odom, n_dropped)


def _rawlaser_line(scan: Scan, k: int, hostname: str) -> str:
    n = scan.n_beams
    max_range = scan.range_max if math.isfinite(scan.range_max) else 81.9
    ranges = np.where(scan.valid, scan.ranges, max_range)
    fov = (n - 1) * scan.angle_increment
    parts = [
        f"RAWLASER{k} 0 {scan.angle_min:.9g} {fov:.9g} {scan.angle_increment:.9g} "
        f"{max_range:.9g} 0 0 {n}",
        " ".join(np.char.mod("%.9g", ranges)),
    ]
    if scan.intensities is not None:
        parts.append(f"{n} " + " ".join(np.char.mod("%.9g", scan.intensities)))
    else:
        parts.append("0")
    parts.append(f"{scan.stamp:.6f} {hostname} {scan.stamp:.6f}")
    return " ".join(p for p in parts if p) + "\n"
