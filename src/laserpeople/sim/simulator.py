"""Run a scene: plan everyone's motion, ray cast every scan of every sensor, record truth.

:func:`simulate` takes a :class:`Scene` (world, people, sensors, optional robot) and
returns a :class:`SimResult` with the scans of all sensors interleaved in time order,
one :class:`~laserpeople.truth.TruthFrame` per scan of the first sensor, and JSON
metadata (sensors, static map, people, robot odometry).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import LaserPeopleError, RecordingError
from laserpeople.io.paths import why_unwritable
from laserpeople.scan import Pose2D, Scan, wrap_angle
from laserpeople.sim.accessories import ACCESSORIES, accessory_geometry
from laserpeople.sim.people import LEG_Z_MAX, TORSO_Z, PersonSpec, PlannedPerson, plan_person
from laserpeople.sim.raycast import Primitives, cast
from laserpeople.sim.robot import RobotSpec, integrate_odometry
from laserpeople.sim.sensors import SensorSpec, add_range_noise
from laserpeople.sim.world import World
from laserpeople.truth import BeamLabels, TruthFrame

FloatArray = NDArray[np.float64]
ProgressWrapper = Callable[[Iterable[Any], int, str], Iterable[Any]]


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything a simulation needs.

    Attributes:
        world: Static objects.
        people: The people.
        sensors: The scanners; the first one sets the ground-truth frames.
        robot: The robot carrying the ``on_robot`` sensors, if any.
        notes: Extra JSON-ready facts for the metadata (e.g. the permutation of a crossing).
        poses_from_odometry: Give the scans the robot's drifting odometry poses instead of
            the true ones, as a real robot without localisation has them; the ground truth
            is then expressed in that odometry frame too (each frame moved by the
            odometry error at its instant), so tracks and truth stay comparable while
            static objects appear to drift as they do on a real robot.
        truth_seen_within: When set [s], a person is in a truth frame only if a beam of the
            first sensor hit them within this many seconds before or after the frame (people
            out of view for long are not counted as missed; short occlusions still are).
            None keeps everyone present in the scene.
        truth_in_view: When true, a person is in a truth frame only while the first sensor
            can see them in that very scan (:func:`in_view_truth`: inside its field of
            view, within its range, not fully occluded), as annotators label a recording;
            excludes ``truth_seen_within``.
    """

    world: World
    people: list[PersonSpec]
    sensors: list[SensorSpec]
    robot: RobotSpec | None = None
    notes: dict[str, Any] = field(default_factory=dict)
    poses_from_odometry: bool = False
    truth_seen_within: float | None = None
    truth_in_view: bool = False

    def __post_init__(self) -> None:
        if self.truth_in_view and self.truth_seen_within is not None:
            raise ValueError("a scene's truth is either in view or seen within a window, not both")


@dataclass(frozen=True, eq=False)
class SimResult:
    """The output of a simulation.

    Attributes:
        scans: Scans of all sensors in time order, each with ``pose`` (sensor pose in the
            world), ``labels`` (per-beam truth), ``sensor`` and ``index`` (per sensor).
        truth: One frame per scan of the first sensor (``scan_index`` = that scan's index).
        meta: JSON-ready metadata: scenario, seed, rate, sensors, static_map, people, robot.
    """

    scans: list[Scan]
    truth: list[TruthFrame]
    meta: dict[str, Any]

    def write(self, path: str | Path) -> Path:
        """Write the recording; ``.npz`` keeps the ground truth, ``.mcap``/``.bag`` only scans."""
        p = check_recording_suffix(path)
        suffix = p.suffix.lower()
        if suffix == ".npz":
            from laserpeople.io import write_recording

            try:
                return write_recording(p, self.scans, self.truth, self.meta)
            except OSError as exc:  # the npz writer lets file-system errors through
                raise RecordingError(
                    f"cannot write the recording: {why_unwritable(exc, p)}",
                    path=p,
                    hint="choose a writable directory for -o",
                ) from exc
        return _write_rosbag(p, self.scans)


SIM_SUFFIXES = (".npz", ".mcap", ".bag", ".db3")
"""Extensions of the recordings :meth:`SimResult.write` writes."""


def check_recording_suffix(path: str | Path) -> Path:
    """``path`` if :meth:`SimResult.write` can write a recording there (``.npz``,
    ``.mcap``, ``.db3``, ``.bag``), else a :class:`LaserPeopleError` naming it: for a
    caller to check before it simulates."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in SIM_SUFFIXES:
        from laserpeople.spelling import did_you_mean

        raise LaserPeopleError(
            f"cannot write simulated recordings as {suffix or '(no extension)'!r}"
            + did_you_mean(suffix, SIM_SUFFIXES, lead="; "),
            path=p,
            hint="use .npz (scans and ground truth), or .mcap/.db3/.bag (scans only)",
        )
    return p


def _write_rosbag(path: Path, scans: list[Scan]) -> Path:
    """Scans (and sensor poses on /tf, parent frame "world") as a ROS bag; no ground truth."""
    try:
        from laserpeople.io.rosbag_writer import write_laserscan_bag
    except ImportError as exc:  # the writer arrives with the io issue
        raise LaserPeopleError(
            f"writing {path.suffix} needs laserpeople.io.rosbag_writer, which this "
            "installation does not have",
            path=path,
            hint="write .npz instead",
        ) from exc
    write_laserscan_bag(path, scans, world_frame="world")
    return path


@dataclass(frozen=True, eq=False)
class _DynamicShapes:
    """Moving shapes seen by one sensor at each of its T scan times."""

    circles: FloatArray  # (T, C, 3)
    circle_labels: NDArray[np.int32]  # (T, C, 4)
    circle_present: NDArray[np.bool_]  # (T, C)
    ellipses: FloatArray  # (T, E, 5)
    ellipse_labels: NDArray[np.int32]
    ellipse_present: NDArray[np.bool_]
    segments: FloatArray  # (T, S, 4)
    segment_labels: NDArray[np.int32]
    segment_present: NDArray[np.bool_]

    def at(self, k: int) -> Primitives:
        c = self.circle_present[k]
        e = self.ellipse_present[k]
        s = self.segment_present[k]
        circ = self.circles[k, c]
        ell = self.ellipses[k, e]
        seg = self.segments[k, s]
        return Primitives(
            circ[:, :2],
            circ[:, 2],
            self.circle_labels[k, c],
            ell[:, :2],
            ell[:, 2:4],
            ell[:, 4],
            self.ellipse_labels[k, e],
            seg[:, :2],
            seg[:, 2:],
            self.segment_labels[k, s],
        )


def _label_rows(
    pid: int, leg: int, group: NDArray[np.int64], obj: int, n: int
) -> NDArray[np.int32]:
    """(T, n, 4) label rows for n shapes of one person over T instants."""
    t = group.size
    rows = np.empty((t, n, 4), dtype=np.int32)
    rows[..., 0] = pid
    rows[..., 1] = leg
    rows[..., 2] = group[:, None]
    rows[..., 3] = obj
    return rows


def _dynamic_shapes(
    people: list[PlannedPerson], times: FloatArray, height: float, first_accessory_id: int
) -> _DynamicShapes:
    t = times.size
    circ: list[FloatArray] = []
    ell: list[FloatArray] = []
    seg: list[FloatArray] = []
    clab: list[NDArray[np.int32]] = []
    elab: list[NDArray[np.int32]] = []
    slab: list[NDArray[np.int32]] = []
    cpres: list[NDArray[np.bool_]] = []
    epres: list[NDArray[np.bool_]] = []
    spres: list[NDArray[np.bool_]] = []
    acc_id = first_accessory_id
    for person in people:
        spec = person.spec
        st = person.state(times)
        pid = spec.person_id
        if height <= LEG_Z_MAX:
            for leg in (0, 1):
                c = np.concatenate([st.legs[:, leg], np.full((t, 1), spec.leg_radius)], axis=1)
                circ.append(c[:, None, :])
                clab.append(_label_rows(pid, leg, st.group, -1, 1))
                cpres.append(st.present[:, None])
        if TORSO_Z[0] <= height <= TORSO_Z[1]:
            a, b = spec.torso_axes
            e = np.column_stack([st.xy, np.full(t, a), np.full(t, b), st.heading])
            ell.append(e[:, None, :])
            elab.append(_label_rows(pid, -1, st.group, -1, 1))
            epres.append(st.present[:, None])
        if spec.accessory is not None:
            shape = ACCESSORIES[spec.accessory]
            oid = acc_id
            acc_id += 1
            if shape.z_min <= height <= shape.z_max:
                g = accessory_geometry(spec.accessory, st.xy, st.heading, st.legs, spec.leg_radius)
                for arr, store, labs, pres in (
                    (g.circles, circ, clab, cpres),
                    (g.ellipses, ell, elab, epres),
                    (g.segments, seg, slab, spres),
                ):
                    if arr.shape[1]:
                        store.append(arr)
                        labs.append(_label_rows(pid, -1, st.group, oid, arr.shape[1]))
                        pres.append(np.repeat(st.present[:, None], arr.shape[1], axis=1))

    def stack(
        parts: list[Any], labs: list[Any], pres: list[Any], width: int
    ) -> tuple[FloatArray, NDArray[np.int32], NDArray[np.bool_]]:
        if not parts:
            return (
                np.empty((t, 0, width)),
                np.empty((t, 0, 4), dtype=np.int32),
                np.empty((t, 0), dtype=bool),
            )
        return (
            np.concatenate(parts, axis=1),
            np.concatenate(labs, axis=1),
            np.concatenate(pres, axis=1),
        )

    return _DynamicShapes(
        *stack(circ, clab, cpres, 3), *stack(ell, elab, epres, 5), *stack(seg, slab, spres, 4)
    )


def scan_times(duration: float, rate: float, phase: float) -> FloatArray:
    """Stamps [s] of a sensor scanning at ``rate`` [Hz] from ``phase`` until ``duration``."""
    n = math.floor((duration - phase) * rate + 1e-9) + 1
    return phase + np.arange(max(n, 0)) / rate


def _sensor_poses(spec: SensorSpec, robot: RobotSpec | None, times: FloatArray) -> FloatArray:
    """Sensor poses (T, 3) in the world frame."""
    m = spec.mount
    if not spec.on_robot:
        return np.tile([m.x, m.y, m.theta], (times.size, 1))
    if robot is None:
        raise ValueError(f"sensor {spec.name} rides on a robot but the scene has none")
    xy, th, _ = robot.track.at(times)
    c, s = np.cos(th), np.sin(th)
    x = xy[:, 0] + c * m.x - s * m.y
    y = xy[:, 1] + s * m.x + c * m.y
    return np.column_stack([x, y, wrap_angle(th + m.theta)])


def simulate(
    scene: Scene,
    duration: float,
    *,
    seed: int = 0,
    rate: float | None = None,
    name: str = "custom",
    description: str = "",
    progress: ProgressWrapper | None = None,
) -> SimResult:
    """Simulate ``scene`` for ``duration`` [s]; ``rate`` [Hz] overrides every sensor's rate.

    ``progress(items, total, description)`` may wrap the loop over scans (e.g. the CLI's
    progress bar).
    """
    if not scene.sensors:
        raise ValueError("a scene needs at least one sensor")
    seeds = np.random.SeedSequence(seed).spawn(len(scene.sensors) + 1)
    planned = [plan_person(p, duration) for p in scene.people]
    first_acc = scene.world.n_objects
    per_sensor = []
    events: list[tuple[float, int, int]] = []
    for i, spec in enumerate(scene.sensors):
        times = scan_times(duration, spec.rate(rate), spec.phase)
        shapes = _dynamic_shapes(planned, times, spec.height, first_acc)
        poses = _sensor_poses(spec, scene.robot, times)
        per_sensor.append((times, shapes, poses, np.random.default_rng(seeds[i])))
        events.extend((float(t), i, k) for k, t in enumerate(times))
    events.sort()
    scans: list[Scan] = []
    in_view: list[NDArray[np.int64]] = []  # per scan of the first sensor
    loop: Iterable[tuple[float, int, int]] = events
    if progress is not None:
        loop = progress(events, len(events), f"simulating {name}")
    for _stamp, i, k in loop:
        spec = scene.sensors[i]
        times, shapes, poses, rng = per_sensor[i]
        scan, visible = render_scan(
            spec, scene.world, shapes.at(k), poses[k], float(times[k]), k, rng
        )
        scans.append(scan)
        if i == 0:
            in_view.append(visible)
    truth = _truth_frames(planned, per_sensor[0][0])
    if scene.truth_in_view:
        truth = in_view_truth(truth, in_view)
    elif scene.truth_seen_within is not None:
        first = scene.sensors[0].name
        truth = seen_truth(
            [sc for sc in scans if sc.sensor == first], truth, scene.truth_seen_within
        )
    meta = _meta(scene, planned, duration, seed, rate, name, description, per_sensor, seeds[-1])
    if scene.poses_from_odometry and scene.robot is not None:
        scans, truth = _odometry_frame(scene.robot, scans, truth, seeds[-1])
        meta["frame"] = "odometry"
    return SimResult(scans, truth, meta)


def seen_truth(scans: list[Scan], truth: list[TruthFrame], window: float) -> list[TruthFrame]:
    """``truth`` (one frame per scan of ``scans``) keeping in each frame only the people hit
    by a beam of some scan within ``window`` [s] of it (beam labels say who was hit)."""

    stamps = np.array([s.stamp for s in scans])
    hit: dict[int, list[float]] = {}
    for scan in scans:
        if scan.labels is None:
            continue
        for pid in np.unique(scan.labels.person[scan.labels.person >= 0]).tolist():
            hit.setdefault(int(pid), []).append(scan.stamp)
    seen_times = {pid: np.asarray(ts) for pid, ts in hit.items()}

    def seen_near(pid: int, t: float) -> bool:
        times = seen_times.get(pid)
        if times is None:
            return False
        k = int(np.searchsorted(times, t - window))  # first hit at or after t - window
        return k < times.size and times[k] <= t + window

    out = []
    for k, frame in enumerate(truth):
        t = float(stamps[k])
        keep = np.array([seen_near(pid, t) for pid in frame.person_ids.tolist()], dtype=bool)
        out.append(_keep_people(frame, keep))
    return out


def in_view_truth(truth: list[TruthFrame], visible: list[NDArray[np.int64]]) -> list[TruthFrame]:
    """``truth`` keeping in each frame only the people of ``visible`` (the same length as
    ``truth``: per frame, the ids of the people its scan can see, as :func:`render_scan` gives)."""
    if len(visible) != len(truth):
        raise ValueError(f"{len(visible)} visibility sets for {len(truth)} truth frames")
    return [
        _keep_people(frame, np.isin(frame.person_ids, ids))
        for frame, ids in zip(truth, visible, strict=True)
    ]


def _keep_people(frame: TruthFrame, keep: NDArray[np.bool_]) -> TruthFrame:
    """``frame`` with only the people where ``keep`` (P,) is true."""
    from dataclasses import replace

    if keep.all():
        return frame
    return replace(
        frame,
        person_ids=frame.person_ids[keep],
        positions=frame.positions[keep],
        velocities=frame.velocities[keep],
        group_ids=frame.group_ids[keep],
        leg_positions=frame.leg_positions[keep],
        hues=frame.hues[keep],
    )


def _odometry_correction(
    robot: RobotSpec, odo_seed: np.random.SeedSequence, times: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Rotation angle (T,) and translation (T, 2) of the rigid map C(t) from the true world
    frame to the odometry frame: C(t) = T_odo(t) T_true(t)^-1 (robot base poses)."""
    track = robot.track
    odo = integrate_odometry(track, robot.odometry, np.random.default_rng(odo_seed))
    xy, th, _ = track.at(times)
    ox = np.interp(times, track.times, odo[:, 0])
    oy = np.interp(times, track.times, odo[:, 1])
    oth = np.interp(times, track.times, np.unwrap(odo[:, 2]))
    dth = oth - np.unwrap(th)
    c, s = np.cos(dth), np.sin(dth)
    tx = ox - (c * xy[:, 0] - s * xy[:, 1])
    ty = oy - (s * xy[:, 0] + c * xy[:, 1])
    return dth, np.column_stack([tx, ty])


def _odometry_frame(
    robot: RobotSpec,
    scans: list[Scan],
    truth: list[TruthFrame],
    odo_seed: np.random.SeedSequence,
) -> tuple[list[Scan], list[TruthFrame]]:
    """Scans with odometry poses and truth in the odometry frame (see :class:`Scene`)."""
    from dataclasses import replace

    stamps = np.array([s.stamp for s in scans])
    dth, t = _odometry_correction(robot, odo_seed, stamps)
    out_scans = []
    for k, scan in enumerate(scans):
        pose = scan.pose
        assert pose is not None  # simulated scans always carry their pose
        c, s = math.cos(dth[k]), math.sin(dth[k])
        x = c * pose.x - s * pose.y + t[k, 0]
        y = s * pose.x + c * pose.y + t[k, 1]
        out_scans.append(replace(scan, pose=Pose2D(x, y, float(wrap_angle(pose.theta + dth[k])))))
    tstamps = np.array([f.stamp for f in truth])
    fdth, ft = _odometry_correction(robot, odo_seed, tstamps)
    out_truth = []
    for k, f in enumerate(truth):
        c, s = math.cos(fdth[k]), math.sin(fdth[k])
        rot = np.array([[c, -s], [s, c]])
        out_truth.append(
            replace(
                f,
                positions=f.positions @ rot.T + ft[k],
                velocities=f.velocities @ rot.T,
                leg_positions=f.leg_positions @ rot.T + ft[k],
            )
        )
    return out_scans, out_truth


def render_scan(
    spec: SensorSpec,
    world: World,
    dynamic: Primitives,
    pose: NDArray[np.floating],
    stamp: float,
    index: int,
    rng: np.random.Generator,
) -> tuple[Scan, NDArray[np.int64]]:
    """One scan of sensor ``spec`` at world pose ``pose`` (x, y, theta) with beam labels,
    and the ids of the people the scan can see: those some beam hits first within
    ``[range_min, range_max]`` of the true range. That is the geometry alone (inside the
    field of view, within range, not fully occluded): range noise and dropout, which make a
    beam miss what it points at, do not hide a person."""
    x, y, th = (float(v) for v in pose)
    c, s = math.cos(th), math.sin(th)
    rot_t = np.array([[c, s], [-s, c]])  # world -> sensor rotation
    shapes = Primitives.concat([world.primitives(spec.height), dynamic]).transformed(
        rot_t, -(rot_t @ np.array([x, y]))
    )
    laser = spec.laser
    hit = cast(laser.fan(), shapes)
    ranges, echo = add_range_noise(hit.ranges, spec, rng)
    lab = np.where(echo[:, None], hit.labels, -1).astype(np.int32)
    in_range = np.isfinite(hit.ranges) & (hit.ranges >= laser.range_min)
    in_range &= hit.ranges <= laser.range_max
    person = hit.labels[:, 0][in_range]
    visible = np.unique(person[person >= 0]).astype(np.int64)
    fan = laser.fan()
    scan = Scan(
        stamp=stamp,
        angle_min=fan.angle_min,
        angle_increment=fan.increment,
        ranges=ranges,
        range_min=laser.range_min,
        range_max=laser.range_max,
        sensor=spec.name,
        pose=Pose2D(x, y, th),
        index=index,
        labels=BeamLabels(lab[:, 0], lab[:, 1], lab[:, 2], lab[:, 3]),
    )
    return scan, visible


def _truth_frames(planned: list[PlannedPerson], times: FloatArray) -> list[TruthFrame]:
    states = [p.state(times) for p in planned]
    frames = []
    for k, t in enumerate(times):
        here = [j for j, st in enumerate(states) if st.present[k]]
        frames.append(
            TruthFrame(
                stamp=float(t),
                scan_index=k,
                person_ids=np.array([planned[j].spec.person_id for j in here], dtype=np.int64),
                positions=np.array([states[j].xy[k] for j in here]).reshape(-1, 2),
                velocities=np.array([states[j].velocity[k] for j in here]).reshape(-1, 2),
                group_ids=np.array([states[j].group[k] for j in here], dtype=np.int64),
                leg_positions=np.array([states[j].legs[k] for j in here]).reshape(-1, 2, 2),
                hues=np.array([planned[j].spec.hue for j in here]),
                frame="world",
            )
        )
    return frames


def _meta(
    scene: Scene,
    planned: list[PlannedPerson],
    duration: float,
    seed: int,
    rate: float | None,
    name: str,
    description: str,
    per_sensor: list[Any],
    odo_seed: np.random.SeedSequence,
) -> dict[str, Any]:
    accessory_ids: dict[int, int] = {}
    for p in planned:  # numbered after the static objects, in person order (as rendered)
        if p.spec.accessory is not None:
            accessory_ids[p.spec.person_id] = scene.world.n_objects + len(accessory_ids)
    meta: dict[str, Any] = {
        "generator": "laserpeople.sim",
        "scenario": name,
        "description": description,
        "seed": seed,
        "rate_hz": rate,
        "duration_s": duration,
        "frame": "world",
        "sensors": [
            {**s.meta(), "rate_hz": s.rate(rate), "scans": int(per_sensor[i][0].size)}
            for i, s in enumerate(scene.sensors)
        ],
        "truth_sensor": scene.sensors[0].name,
        "static_map": scene.world.static_map(),
        "people": [
            {
                "id": p.spec.person_id,
                "hue_deg": p.spec.hue,
                "leg_radius_m": p.spec.leg_radius,
                "hip_half_width_m": p.spec.hip_half_width,
                "torso_axes_m": list(p.spec.torso_axes),
                "accessory": p.spec.accessory,
                "accessory_obj_id": accessory_ids.get(p.spec.person_id),
                "enter_s": p.enter,
                "leave_s": None if math.isinf(p.leave) else p.leave,
            }
            for p in planned
        ],
        "notes": scene.notes,
    }
    if scene.robot is not None:
        times = per_sensor[0][0]
        track = scene.robot.track
        odo_all = integrate_odometry(track, scene.robot.odometry, np.random.default_rng(odo_seed))
        xy, th, _ = track.at(times)
        ox = np.interp(times, track.times, odo_all[:, 0])
        oy = np.interp(times, track.times, odo_all[:, 1])
        oth = wrap_angle(np.interp(times, track.times, np.unwrap(odo_all[:, 2])))
        meta["robot"] = {
            "stamps": times.tolist(),
            "true_poses": np.column_stack([xy, th]).round(6).tolist(),
            "odometry_poses": np.column_stack([ox, oy, oth]).round(6).tolist(),
            "note": "robot base poses at the first sensor's scan stamps; odometry drifts "
            "(see laserpeople.sim.robot.OdometryParams)",
        }
    return meta
