"""The data model of a 2D laser scan: :class:`Scan`, :class:`PointSet`, :class:`Segment`.

Units are SI throughout: metres, seconds, radians. Angles are wrapped to
(-pi, pi]. A scan's beam angles are computed from ``angle_min`` and
``angle_increment`` exactly as ROS does (``angle_min + i * angle_increment``),
so a negative increment (a scanner mounted upside down, as on the MiR robot)
works without special cases.

A beam is *valid* only when its range is finite, non-zero and inside
``[range_min, range_max]``. Invalid beams are never treated as obstacles: they
come out of :meth:`Scan.points` as NaN and are left out of
:meth:`Scan.valid_points`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache
from types import ModuleType
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import ScanFormatError

if TYPE_CHECKING:
    from laserpeople.truth import BeamLabels

CoordinateFrame = Literal["sensor", "world"]

POSE_LIMIT = 1.0e7
"""Largest |x|, |y| [m] of a sensor pose (10,000 km: room for UTM coordinates). A scan
whose pose lies beyond it is damaged (a corrupt transform or odometry record): its points
would overflow the grids built from them."""

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

_UNSET = object()
_extension: object = _UNSET
"""Leg detection's C extension (a scan's validity and points in one call), or None;
looked up at the first scan's arrays (:func:`_points_extension`)."""


def _points_extension() -> ModuleType | None:
    """Leg detection's C extension, or None (its Python references run), imported when a
    scan first needs it: reading recordings does not import the detector."""
    global _extension
    if _extension is _UNSET:
        from laserpeople.detection import compiled

        _extension = compiled.EXTENSION
    assert _extension is None or isinstance(_extension, ModuleType)
    return _extension


Layout = tuple[float, float, int]
"""A laser's beam layout: ``(angle_min [rad], angle_increment [rad], beam count)``."""


def same_layout(a: Layout, b: Layout) -> bool:
    """Whether two beam layouts are the same: equal beam counts, angles within 1e-9 rad."""
    return a[2] == b[2] and all(
        math.isclose(x, y, rel_tol=0.0, abs_tol=1e-9) for x, y in zip(a[:2], b[:2], strict=True)
    )


@lru_cache(maxsize=32)
def _beam_directions(
    angle_min: float, angle_increment: float, n_beams: int
) -> tuple[FloatArray, FloatArray]:
    """Cosine and sine (N,) of the beam angles of a scan geometry (read-only; the same
    floats as ``np.cos(scan.angles)`` and ``np.sin(scan.angles)``), computed once per
    geometry: every scan of a laser shares them."""
    raw = angle_min + np.arange(n_beams, dtype=np.float64) * angle_increment
    a = wrap_angle(raw)
    cos, sin = np.cos(a), np.sin(a)
    cos.setflags(write=False)
    sin.setflags(write=False)
    return cos, sin


def wrap_angle(angle: NDArray[np.floating] | float) -> NDArray[np.float64]:
    """Wrap angles [rad] to (-pi, pi]; works element-wise on arrays."""
    a = np.asarray(angle, dtype=np.float64)
    wrapped = np.mod(a + np.pi, 2.0 * np.pi) - np.pi
    return np.where(wrapped <= -np.pi, wrapped + 2.0 * np.pi, wrapped)


_MANY_POINTS = 32
"""Beyond this many points :meth:`Pose2D.transform_points` adds the translation column by
column (fewer are cheaper broadcast). Measured on 1081 points: 34 against 47-53 us; on 10
points 19 against 17 us."""


@dataclass(frozen=True, slots=True)
class Pose2D:
    """A planar pose: position (x, y) [m] and heading theta [rad] in a parent frame."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0

    def as_array(self) -> FloatArray:
        """The pose as ``array([x, y, theta])``."""
        return np.array([self.x, self.y, self.theta], dtype=np.float64)

    def rotation(self) -> FloatArray:
        """The 2x2 rotation matrix of ``theta``."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return np.array([[c, -s], [s, c]], dtype=np.float64)

    def transform_points(self, points: NDArray[np.floating]) -> FloatArray:
        """Map points (N, 2) from this pose's child frame into its parent frame."""
        pts = np.asarray(points, dtype=np.float64)
        out = pts @ self.rotation().T
        if out.ndim == 2 and out.shape[0] > _MANY_POINTS:
            # (the same sums: adding a (2,) row broadcast runs numpy's inner loop once per
            # point, two columns twice in all; a third of the cost on a scan's ~1000 points)
            out[:, 0] += self.x
            out[:, 1] += self.y
            return out
        return out + np.array([self.x, self.y])

    def inverse_transform_points(self, points: NDArray[np.floating]) -> FloatArray:
        """Map points (N, 2) from the parent frame into this pose's child frame."""
        pts = np.asarray(points, dtype=np.float64) - np.array([self.x, self.y])
        return pts @ self.rotation()

    def compose(self, other: Pose2D) -> Pose2D:
        """``self ∘ other``: the pose ``other`` (given in this pose's frame) in the parent frame."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2D(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            float(wrap_angle(self.theta + other.theta)),
        )

    def inverse(self) -> Pose2D:
        """The inverse transform: the parent frame's pose seen from this pose."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2D(
            -(c * self.x + s * self.y),
            -(-s * self.x + c * self.y),
            float(wrap_angle(-self.theta)),
        )

    @classmethod
    def from_array(cls, values: NDArray[np.floating] | tuple[float, float, float]) -> Pose2D:
        """A pose from ``(x, y, theta)``."""
        x, y, theta = (float(v) for v in values)
        return cls(x, y, theta)


_FLOAT64 = np.dtype(np.float64)

_SCALAR_FIELDS = ("stamp", "angle_min", "angle_increment", "range_min", "range_max")
"""The fields of a :class:`Scan` that hold one number."""


def _float_array(value: object, name: str) -> FloatArray:
    """``value`` (a :class:`Scan`'s ``ranges`` or ``intensities``: an array or sequence of
    real numbers) as a float64 array.

    Raises:
        TypeError: ``value`` is None, a string, or holds what is no real number (text,
            complex numbers, None); names the field and what it takes.
    """
    expects = f"Scan: {name} must be an array of real numbers, one per beam"
    if value is None or isinstance(value, str | bytes):
        raise TypeError(f"{expects}, got {type(value).__name__} {value!r:.40}")
    try:
        array = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged sequences
        raise TypeError(f"{expects}: {exc}") from None
    if array.dtype.kind not in "fiu":
        if array.dtype.kind == "O":
            try:
                return np.asarray(array, dtype=np.float64)
            except (TypeError, ValueError):
                pass
        raise TypeError(f"{expects}, got an array of {array.dtype} values")
    return np.asarray(array, dtype=np.float64)


def _check_field_types(scan: Scan) -> None:
    """Name the field of ``scan`` that holds a value of the wrong type.

    Raises:
        TypeError: a number field holds no real number (text, None, an array), or ``pose``
            is no :class:`Pose2D`; names the field, what it takes and what it got.
    """
    for name in _SCALAR_FIELDS:
        value = getattr(scan, name)
        if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
            raise TypeError(
                f"Scan: {name} must be a real number, got {type(value).__name__} {value!r:.40}"
            )
    if scan.pose is not None and not isinstance(scan.pose, Pose2D):
        raise TypeError(
            f"Scan: pose must be a Pose2D or None, got {type(scan.pose).__name__} "
            f"{scan.pose!r:.40} (Pose2D.from_array makes one of (x, y, theta))"
        )


def _check_index(scan: Scan) -> None:
    """Take an ``index`` of another integer type (``numpy.int64``) as an int; refuse one
    that is no integer.

    Raises:
        TypeError: ``index`` is a float (even ``3.0``: it would be written ``3.0`` where
            readers expect a scan number), a bool, text or None; names the field, what
            it takes, what it got and the file, if any.
    """
    index = scan.index
    if isinstance(index, int | np.integer) and not isinstance(index, bool | np.bool_):
        object.__setattr__(scan, "index", int(index))
        return
    whose = f" (a scan of {scan.source})" if scan.source else ""
    todo = (
        f": give int({index!r})"
        if isinstance(index, float | np.floating) and float(index).is_integer()
        else ""
    )
    raise TypeError(
        f"Scan: index must be an integer, the scan's 0-based place among its laser's scans; "
        f"got {type(index).__name__} {index!r:.40}{whose}{todo}"
    )


@dataclass(frozen=True, eq=False)
class Scan:
    """One sweep of a 2D laser scanner, in the layout of ROS ``sensor_msgs/LaserScan``.

    Attributes:
        stamp: Acquisition time of the first beam [s].
        angle_min: Angle of beam 0 in the sensor frame [rad].
        angle_increment: Angle between consecutive beams [rad]; may be negative.
        ranges: Measured ranges (N,) [m]; NaN, inf, 0 and out-of-limit values mean "no return".
        range_min: Smallest valid range [m].
        range_max: Largest valid range [m]; must be > 0 and >= ``range_min`` (limits
            that leave no usable beam make the scan damaged: ``ScanFormatError``).
        intensities: Optional return intensities (N,), sensor-specific units.
        sensor: Name of the sensor (topic or CARMEN laser id) this scan came from.
        pose: Sensor pose in the world frame at ``stamp``, if known; |x|, |y| at most
            :data:`POSE_LIMIT`.
        index: 0-based index of this scan among the scans of its sensor/topic.
        source: The file the scan was read from (for error messages); "" if none.
        labels: Per-beam ground truth, if the recording carries it.
    """

    stamp: float
    angle_min: float
    angle_increment: float
    ranges: FloatArray
    range_min: float = 0.0
    range_max: float = math.inf
    intensities: FloatArray | None = None
    sensor: str = "laser"
    pose: Pose2D | None = None
    index: int = 0
    source: str = ""
    labels: BeamLabels | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        ranges = self.ranges
        if type(ranges) is not np.ndarray or ranges.dtype is not _FLOAT64:
            ranges = _float_array(ranges, "ranges")
        if ranges.ndim != 1:
            self._fail(f"ranges must be one-dimensional, got shape {ranges.shape}")
        object.__setattr__(self, "ranges", ranges)
        try:
            self._check_header()
        except (TypeError, ValueError, AttributeError) as exc:
            # (a field of the wrong type: said naming it; the checks cost nothing when
            # every field is right, which is why they are not made first)
            _check_field_types(self)
            raise exc from None
        if type(self.index) is not int:  # (one type test: Scan is built for every scan read)
            _check_index(self)
        if self.intensities is not None:
            inten: FloatArray | None = self.intensities
            if type(inten) is not np.ndarray or inten.dtype is not _FLOAT64:
                inten = _float_array(inten, "intensities")
            assert inten is not None
            if inten.size == 0:
                inten = None
            elif inten.shape != ranges.shape:
                self._fail(
                    f"{inten.size} intensities for {ranges.size} ranges",
                    hint="intensities must be empty or have one value per beam",
                )
            object.__setattr__(self, "intensities", inten)
        if self.labels is not None and len(self.labels) != ranges.size:
            self._fail(f"{len(self.labels)} beam labels for {ranges.size} ranges")

    def _check_header(self) -> None:
        """Refuse a scan whose header (angles, stamp, range limits) or pose is damaged.

        Raises:
            ScanFormatError: names the field and the scan.
            TypeError, ValueError, AttributeError: a field of the wrong type (raw).
        """
        if not (math.isfinite(self.angle_increment) and self.angle_increment != 0.0):
            self._fail(
                f"angle_increment must be finite and non-zero, got {self.angle_increment!r}",
                hint="the scanner driver wrote a broken header",
            )
        if not math.isfinite(self.angle_min):
            self._fail(f"angle_min must be finite, got {self.angle_min!r}")
        if not math.isfinite(self.stamp):
            self._fail(f"stamp must be finite, got {self.stamp!r}")
        if not (self.range_max > 0.0 and self.range_min <= self.range_max):  # NaN fails too
            self._fail(
                f"range limits range_min={self.range_min:.6g} m, range_max={self.range_max:.6g} m "
                "leave no usable beam",
                hint="the scanner driver wrote broken range limits",
            )
        pose = self.pose
        if pose is not None and not (
            abs(pose.x) <= POSE_LIMIT and abs(pose.y) <= POSE_LIMIT and math.isfinite(pose.theta)
        ):
            self._fail(
                f"sensor pose ({pose.x:.6g}, {pose.y:.6g}, {pose.theta:.6g}) is beyond "
                f"{POSE_LIMIT:g} m or not finite",
                hint="a transform or odometry record is corrupt",
            )

    def _fail(self, message: str, hint: str | None = None) -> None:
        raise ScanFormatError(message, path=self.source or None, scan=self.index, hint=hint)

    @classmethod
    def from_angles(
        cls,
        stamp: float,
        angle_min: float,
        angle_max: float,
        angle_increment: float,
        ranges: NDArray[np.floating],
        *,
        tolerance_beams: float = 0.5,
        **kwargs: object,
    ) -> Scan:
        """Build a scan from a ROS-style header and check the beam count against the angles.

        ROS drivers write ``angle_max = angle_min + (N - 1) * angle_increment``; a scan whose
        beam count disagrees with that by more than ``tolerance_beams`` beams is rejected,
        because its angles would be wrong for every beam.
        """
        ranges = np.asarray(ranges, dtype=np.float64)
        scan = cls(stamp, angle_min, angle_increment, ranges, **kwargs)  # type: ignore[arg-type]
        if angle_increment != 0.0 and math.isfinite(angle_max):
            expected = (angle_max - angle_min) / angle_increment + 1.0
            if abs(expected - ranges.size) > max(tolerance_beams, 1e-6 * ranges.size) + 1.0:
                scan._fail(
                    f"{ranges.size} beams but angle_min={angle_min:.6f}, "
                    f"angle_max={angle_max:.6f}, "
                    f"angle_increment={angle_increment:.6g} imply {expected:.1f}",
                    hint="the scan header disagrees with its data; re-record or fix the driver",
                )
        return scan

    @property
    def n_beams(self) -> int:
        """Number of beams N."""
        return int(self.ranges.size)

    @property
    def angle_max(self) -> float:
        """Angle of the last beam [rad], as ROS writes it."""
        return self.angle_min + (self.n_beams - 1) * self.angle_increment

    @property
    def layout(self) -> Layout:
        """The beam layout ``(angle_min [rad], angle_increment [rad], n_beams)``."""
        return (self.angle_min, self.angle_increment, self.n_beams)

    @cached_property
    def angles(self) -> FloatArray:
        """Beam angles (N,) in the sensor frame [rad], wrapped to (-pi, pi]."""
        raw = self.angle_min + np.arange(self.n_beams, dtype=np.float64) * self.angle_increment
        return wrap_angle(raw)

    @cached_property
    def valid(self) -> BoolArray:
        """Validity mask (N,): finite, non-zero and inside [range_min, range_max]."""
        if _points_extension() is not None:
            return self._compiled_points()[0]
        r = self.ranges
        # (no np.errstate: numpy 2's comparisons raise no floating-point warning on NaN,
        # and entering and leaving it costs more than the four comparisons on a scan)
        return np.isfinite(r) & (r > 0.0) & (r >= self.range_min) & (r <= self.range_max)

    @property
    def n_invalid(self) -> int:
        """Number of beams without a valid return."""
        return int(self.n_beams - np.count_nonzero(self.valid))

    def _compiled_points(self) -> tuple[BoolArray, FloatArray, IntArray, FloatArray]:
        """:attr:`valid`, :attr:`_sensor_points`, :attr:`valid_beams` and
        :attr:`_valid_sensor_points` at once by leg detection's C extension (the same
        arrays, in one pass over the beams instead of some ten numpy calls), stored as
        those cached properties."""
        extension = _points_extension()
        assert extension is not None
        cos, sin = self._directions()
        ranges = np.ascontiguousarray(self.ranges, dtype=np.float64)
        parts = extension.scan_points(ranges, self.range_min, self.range_max, cos, sin)
        valid = np.frombuffer(parts[0], dtype=np.bool_)  # (writable, as numpy's mask)
        points = np.frombuffer(parts[1], dtype=np.float64).reshape(-1, 2)
        beams = np.frombuffer(parts[2], dtype=np.int64)
        kept = np.frombuffer(parts[3], dtype=np.float64).reshape(-1, 2)
        cached = self.__dict__
        cached["valid"], cached["_sensor_points"] = valid, points
        cached["valid_beams"], cached["_valid_sensor_points"] = beams, kept
        return valid, points, beams, kept

    def _directions(self) -> tuple[FloatArray, FloatArray]:
        """Cosine and sine (N,) of the beam angles (shared by the scans of a geometry)."""
        return _beam_directions(float(self.angle_min), float(self.angle_increment), self.n_beams)

    @cached_property
    def _sensor_points(self) -> FloatArray:
        if _points_extension() is not None:
            return self._compiled_points()[1]
        r = np.where(self.valid, self.ranges, np.nan)
        cos, sin = self._directions()
        pts = np.empty((self.n_beams, 2), dtype=np.float64)
        np.multiply(r, cos, out=pts[:, 0])
        np.multiply(r, sin, out=pts[:, 1])
        pts.setflags(write=False)
        return pts

    def points(self, frame: CoordinateFrame = "sensor") -> FloatArray:
        """Cartesian beam end points (N, 2) [m]; rows of invalid beams are NaN.

        ``frame="world"`` applies :attr:`pose` and raises if the pose is unknown.
        """
        if frame == "sensor":
            return self._sensor_points
        return self.sensor_to_world(self._sensor_points)

    @cached_property
    def valid_beams(self) -> IntArray:
        """Indices (K,) of the valid beams, increasing (read-only)."""
        if _points_extension() is not None:
            return self._compiled_points()[2]
        idx = np.flatnonzero(self.valid).astype(np.int64)
        idx.setflags(write=False)
        return idx

    @cached_property
    def _valid_sensor_points(self) -> FloatArray:
        if _points_extension() is not None:
            return self._compiled_points()[3]
        # (take along rows: the rows of ``[idx]`` at a tenth of its cost on ~700 beams)
        pts = self._sensor_points.take(self.valid_beams, axis=0)
        pts.setflags(write=False)
        return pts

    def valid_points(self, frame: CoordinateFrame = "sensor") -> tuple[FloatArray, IntArray]:
        """Points (K, 2) of the valid beams only, and their beam indices (K,) (both
        read-only: the sensor frame's are computed once per scan and shared)."""
        if frame == "sensor":
            return self._valid_sensor_points, self.valid_beams
        idx = self.valid_beams
        return self.points(frame).take(idx, axis=0), idx

    def sensor_to_world(self, points: NDArray[np.floating]) -> FloatArray:
        """Map sensor-frame points (N, 2) into the world frame using :attr:`pose`."""
        if self.pose is None:
            from laserpeople.errors import PoseUnavailableError

            raise PoseUnavailableError(
                f"no sensor pose for sensor {self.sensor!r}",
                path=self.source or None,
                scan=self.index,
                hint="use --output-frame sensor, or give a recording with /tf or odometry",
            )
        return self.pose.transform_points(points)

    def with_pose(self, pose: Pose2D | None) -> Scan:
        """A copy of this scan with another sensor pose."""
        return replace(self, pose=pose)


@dataclass(frozen=True, eq=False)
class PointSet:
    """Points from one or several scanners at one time, in a common frame.

    Attributes:
        stamp: Time of the set [s].
        points: Positions (N, 2) [m] in ``frame``.
        sensor_ids: Index (N,) into ``sensors`` of the scanner each point came from.
        beams: Beam index (N,) of each point within its scan.
        sensors: Sensor names.
        frame: The frame of ``points``.
        index: 0-based index of the set in its sequence.
    """

    stamp: float
    points: FloatArray
    sensor_ids: IntArray
    beams: IntArray
    sensors: tuple[str, ...] = ("laser",)
    frame: CoordinateFrame = "world"
    index: int = 0

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=np.float64).reshape(-1, 2)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "sensor_ids", np.asarray(self.sensor_ids, dtype=np.int64))
        object.__setattr__(self, "beams", np.asarray(self.beams, dtype=np.int64))
        if not (len(self.sensor_ids) == len(self.beams) == len(pts)):
            raise ScanFormatError(
                f"point set has {len(pts)} points, {len(self.sensor_ids)} sensor ids and "
                f"{len(self.beams)} beam indices",
                scan=self.index,
            )

    def __len__(self) -> int:
        return int(self.points.shape[0])

    @classmethod
    def from_scans(
        cls,
        scans: list[Scan],
        frame: CoordinateFrame = "world",
        *,
        stamp: float | None = None,
        index: int | None = None,
    ) -> PointSet:
        """Merge the valid points of several scans into one set (world frame needs poses);
        ``stamp`` [s] and ``index`` of the set default to the latest scan's stamp and the
        first scan's index."""
        if not scans:
            raise ScanFormatError("cannot build a point set from no scans")
        when = max(s.stamp for s in scans) if stamp is None else stamp
        where = scans[0].index if index is None else index
        if len(scans) == 1:  # (one laser: its arrays as they are, no concatenation)
            pts, idx = scans[0].valid_points(frame)
            one = object.__new__(cls)
            for name, value in (
                ("stamp", when),
                ("points", pts),
                ("sensor_ids", np.zeros(idx.size, dtype=np.int64)),
                ("beams", idx),
                ("sensors", (scans[0].sensor,)),
                ("frame", frame),
                ("index", where),
            ):
                object.__setattr__(one, name, value)
            return one
        parts, ids, beams = [], [], []
        for i, scan in enumerate(scans):
            pts, idx = scan.valid_points(frame)
            parts.append(pts)
            ids.append(np.full(idx.size, i, dtype=np.int64))
            beams.append(idx)
        return cls(
            stamp=when,
            points=np.concatenate(parts),
            sensor_ids=np.concatenate(ids),
            beams=np.concatenate(beams),
            sensors=tuple(s.sensor for s in scans),
            frame=frame,
            index=where,
        )


@dataclass(frozen=True, eq=False)
class Segment:
    """A run of neighbouring valid beams of one scan, the unit the leg detector classifies.

    Attributes:
        start: First beam index of the segment in its scan.
        stop: One past the last beam index (the segment covers ``beams``, which lie
            in ``[start, stop)``; invalid beams inside that range are not part of it).
        beams: Beam indices (n,) of the segment's points, increasing.
        points: Point coordinates (n, 2) [m] in the sensor frame.
    """

    start: int
    stop: int
    beams: IntArray
    points: FloatArray

    def __len__(self) -> int:
        return int(self.beams.size)

    @classmethod
    def of(cls, start: int, stop: int, beams: IntArray, points: FloatArray) -> Segment:
        """``Segment(start, stop, beams, points)``, its fields written straight into its
        dict (the frozen dataclass's ``__init__`` sets each through
        ``object.__setattr__``: about half the cost of a leg's detection record)."""
        segment = object.__new__(cls)
        fields = segment.__dict__
        fields["start"] = start
        fields["stop"] = stop
        fields["beams"] = beams
        fields["points"] = points
        return segment

    @property
    def centre(self) -> FloatArray:
        """Mean of the segment's points (2,) [m]."""
        return np.asarray(self.points.mean(axis=0), dtype=np.float64)


def visible_area(scan: Scan) -> float:
    """Area [m^2] of the fan the laser saw: ``sum r_i^2 |dtheta| / 2`` over beams, a beam
    without a return counted at the range limit (the largest valid range when that is
    infinite)."""
    r = np.asarray(scan.ranges, dtype=np.float64)
    valid = scan.valid
    limit = scan.range_max
    if not math.isfinite(limit):
        limit = float(r[valid].max()) if valid.any() else 0.0
    r = np.where(valid, r, limit)
    return float(0.5 * np.sum(r**2) * abs(scan.angle_increment))
