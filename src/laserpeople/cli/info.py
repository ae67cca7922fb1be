"""`laserpeople info`: summarise a recording, one row per laser topic."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from laserpeople.cli.common import (
    MountOption,
    OnErrorOption,
    WorldFrameOption,
    console,
    plain,
    progress,
    report_damage,
)

if TYPE_CHECKING:
    from laserpeople.io import RecordingSource
    from laserpeople.scan import Scan

_BAG_SUFFIXES = {".bag", ".db3", ".mcap"}
_CARMEN_SUFFIXES = {".log", ".clf", ".carmen", ".txt", ".gz"}


@dataclass
class TopicSummary:
    """Running statistics of the scans of one topic."""

    name: str
    msgtype: str
    count: int = 0
    stamps: list[float] = field(default_factory=list)
    beams: set[int] = field(default_factory=set)
    increments: set[float] = field(default_factory=set)
    fovs: set[float] = field(default_factory=set)
    range_min: float = math.inf
    range_max: float = -math.inf
    total_beams: int = 0
    invalid_beams: int = 0
    with_pose: int = 0

    def add(self, scan: Scan) -> None:
        """Account for one scan."""
        self.count += 1
        self.stamps.append(scan.stamp)
        self.beams.add(scan.n_beams)
        self.increments.add(round(scan.angle_increment, 9))
        self.fovs.add(round(abs(scan.angle_max - scan.angle_min), 9))
        self.range_min = min(self.range_min, scan.range_min)
        self.range_max = max(self.range_max, scan.range_max)
        self.total_beams += scan.n_beams
        self.invalid_beams += scan.n_invalid
        if scan.pose is not None:
            self.with_pose += 1

    def rate(self) -> float | None:
        """Median scan rate [Hz] from the stamp differences (None with < 2 scans)."""
        if len(self.stamps) < 2:
            return None
        import numpy as np

        diffs = np.diff(np.asarray(self.stamps))
        diffs = diffs[diffs > 0]
        return float(1.0 / np.median(diffs)) if diffs.size else None

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready summary (angles in degrees, ranges in metres, rate in Hz)."""
        return {
            "topic": self.name,
            "msgtype": self.msgtype,
            "scans": self.count,
            "rate_hz": self.rate(),
            "fov_deg": sorted(math.degrees(f) for f in self.fovs),
            "beams": sorted(self.beams),
            "angular_resolution_deg": sorted(math.degrees(i) for i in self.increments),
            "range_min_m": self.range_min if self.count else None,
            "range_max_m": self.range_max if self.count else None,
            "invalid_share": self.invalid_beams / self.total_beams if self.total_beams else None,
            "scans_with_pose": self.with_pose,
            "scans_without_pose": self.count - self.with_pose,
        }


def _fmt(values: list[float], digits: int) -> str:
    return ", ".join(f"{v:.{digits}f}" for v in values) if values else "-"


def _open(
    path: Path, world_frame: str | None, mounts: list[str], poses: bool, on_error: str = "stop"
) -> RecordingSource:
    from laserpeople.io.damage import check_on_error

    policy = check_on_error(on_error)
    is_bag = path.suffix.lower() in _BAG_SUFFIXES or (
        path.is_dir() and (path / "metadata.yaml").exists()
    )
    if is_bag and (world_frame or mounts or not poses) and path.exists():
        from laserpeople.io.poses import parse_mounts
        from laserpeople.io.rosbag import RosbagRecording

        return RosbagRecording(
            path,
            poses=poses,
            world_frame=world_frame,
            mounts=parse_mounts(mounts),
            on_error=policy,
        )
    if (world_frame or mounts) and not is_bag:  # refused as by every other command
        from laserpeople.pipeline.recording import open_source

        return open_source(path, world_frame, mounts, on_error)
    if path.suffix.lower() in _CARMEN_SUFFIXES and not poses and path.exists():
        from laserpeople.io.carmen import CarmenRecording

        return CarmenRecording(path, poses=False, on_error=policy)
    from laserpeople.io import open_recording

    return open_recording(path, on_error=policy)


def _finite(value: Any) -> Any:
    """``value`` with non-finite floats (also inside lists and dicts) replaced by None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, list):
        return [_finite(v) for v in value]
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    return value


def summarise(rec: RecordingSource, topics: list[str] | None) -> dict[str, Any]:
    """Read every scan of ``topics`` (all when None) once and summarise them per topic."""
    listed = {t.name: t for t in rec.topics()}
    summaries: dict[str, TopicSummary] = {}
    total = sum(t.count for t in listed.values()) if not topics else None
    for scan in progress(rec.scans(topics or None), total=total, description="reading"):
        s = summaries.get(scan.sensor)
        if s is None:
            info = listed.get(scan.sensor)
            s = summaries[scan.sensor] = TopicSummary(
                scan.sensor, info.msgtype if info else "sensor_msgs/msg/LaserScan"
            )
        s.add(scan)
    if not topics:  # a laser topic recorded without a scan is a row of 0 scans, not left out
        for name, info in listed.items():
            if not info.count and name not in summaries:
                summaries[name] = TopicSummary(name, info.msgtype)
    # in the recording's order, whose first laser `track` takes by default (the scans of
    # another laser may come first, as on the corridor bags)
    order = {name: k for k, name in enumerate(listed)}
    ordered = sorted(summaries.values(), key=lambda s: order.get(s.name, len(order)))
    out: dict[str, Any] = {
        "path": str(rec.path),
        "topics": [s.as_dict() for s in ordered],
        "ground_truth": bool(rec.has_truth),
        "world_frame": getattr(rec, "world_frame", None),
    }
    pose_summary = getattr(rec, "pose_summary", None)
    if callable(pose_summary) and any(s.count for s in summaries.values()):
        out["pose_summary"] = pose_summary()
    mount_notes = getattr(rec, "mount_notes", [])  # given mounts left out, and why
    if mount_notes:
        out["mount_notes"] = list(mount_notes)
    for attr in ("bad_lines", "scans_with_log_time"):
        if getattr(rec, attr, 0):
            out[attr] = getattr(rec, attr)
    changes = getattr(rec, "frame_changes", None)
    if changes:
        out["frame_changes"] = [change.describe(topic) for topic, change in sorted(changes.items())]
    other_types = getattr(rec, "other_types", None)
    if other_types:  # a laser topic carrying other messages too: {topic: {type: count}}
        out["other_types"] = {topic: dict(types) for topic, types in sorted(other_types.items())}
    other_lines = getattr(rec, "other_lines", None)
    if other_lines:
        out["other_lines"] = dict(other_lines)
    all_topics = getattr(rec, "all_topics", None)
    if callable(all_topics):
        from laserpeople.io.tracks_bag import TRACK_TOPICS
        from laserpeople.io.truth_bag import TRUTH_TYPES

        out["other_topics"] = [
            {"topic": t.name, "msgtype": t.msgtype, "messages": t.count}
            for t in all_topics()
            if t.name not in listed
        ]
        ours = set(TRACK_TOPICS.values())  # the tracks of `track --bag`: not ground truth
        out["truth_topics"] = [
            t["topic"]
            for t in out["other_topics"]
            if t["msgtype"] in TRUTH_TYPES and t["topic"] not in ours
        ]
        from laserpeople.io.tracks_bag import PEOPLE_TYPE

        out["track_topics"] = [
            t["topic"]
            for t in out["other_topics"]
            if t["topic"] in ours and t["msgtype"] == PEOPLE_TYPE
        ]
        out["drawn_topics"] = [  # a Foxglove export of `view`: drawings, not tracks
            t["topic"]
            for t in out["other_topics"]
            if t["topic"] in ours and t["msgtype"] != PEOPLE_TYPE
        ]
        out["ground_truth"] = out["ground_truth"] or bool(out["truth_topics"])
    return out


def _print_table(report: dict[str, Any]) -> None:
    from rich import box
    from rich.table import Table

    table = Table(title=plain(report["path"]), title_justify="left", box=box.SIMPLE_HEAD)
    for col, justify in (
        ("topic", "left"),
        ("scans", "right"),
        ("Hz", "right"),
        ("FOV°", "right"),
        ("beams", "right"),
        ("res°", "right"),
        ("range m", "right"),
        ("invalid", "right"),
        ("poses", "right"),
    ):
        table.add_column(col, justify=justify, no_wrap=True)  # type: ignore[arg-type]
    for t in report["topics"]:
        rate = t["rate_hz"]
        invalid = t["invalid_share"]
        table.add_row(
            plain(t["topic"]),
            str(t["scans"]),
            "-" if rate is None else f"{rate:.2f}",
            _fmt(t["fov_deg"], 1),
            ", ".join(str(b) for b in t["beams"]) or "-",
            _fmt(t["angular_resolution_deg"], 3),
            "-" if t["range_min_m"] is None else f"{t['range_min_m']:.2f}–{t['range_max_m']:.1f}",
            "-" if invalid is None else f"{100 * invalid:.1f}%",
            f"{t['scans_with_pose']}/{t['scans']}",
        )
    out = console  # in a pipe: wide and never folded (cli.common.make_console)
    out.print(table)

    def line(text: str) -> None:  # topics, frames and file names as written
        out.print(plain(text))

    truth = "yes" if report["ground_truth"] else "no"
    if report.get("truth_topics"):
        first = report["truth_topics"][0]
        truth += f", topic {', '.join(report['truth_topics'])} (use --truth BAG:{first})"
    line(f"ground truth: {truth}")
    if report.get("track_topics"):
        line(
            f"tracks of laserpeople track --bag: {', '.join(report['track_topics'])} "
            "(score them with laserpeople evaluate RECORDING --truth ...)"
        )
    if report.get("drawn_topics"):
        line(
            f"tracks drawn for Foxglove (laserpeople view): {', '.join(report['drawn_topics'])} "
            "(drawings: evaluate and view read the tracks CSV they were drawn from)"
        )
    if report.get("pose_summary"):
        line(f"poses: {report['pose_summary']}")
    for note in report.get("mount_notes", []):
        line(note)
    if report.get("bad_lines"):
        line(f"malformed lines skipped: {report['bad_lines']}")
    if report.get("scans_with_log_time"):
        line(f"scans with a zero header stamp (bag time used): {report['scans_with_log_time']}")
    for note in report.get("frame_changes", []):
        line(note)
    for topic, types in report.get("other_types", {}).items():
        shown = ", ".join(f"{n} {msgtype}" for msgtype, n in sorted(types.items()))
        line(f"{topic} also carries other messages, left out: {shown}")
    if report.get("other_lines"):
        lines = ", ".join(f"{k} ({n})" for k, n in report["other_lines"].items())
        line(f"other lines: {lines}")
    others = report.get("other_topics")
    if others:
        line(
            "other topics: "
            + ", ".join(f"{o['topic']} ({o['msgtype']}, {o['messages']})" for o in others)
        )


def register(app: typer.Typer) -> None:
    """Add the `info` command to ``app``."""

    @app.command("info")
    def info(
        recording: Annotated[
            Path,
            typer.Argument(
                help="A .bag, .mcap, .db3, ROS 2 bag folder, CARMEN log or .npz recording."
            ),
        ],
        topic: Annotated[
            list[str] | None,
            typer.Option(
                "--topic", "-t", help="Laser topic to summarise (repeatable; default: all)."
            ),
        ] = None,
        as_json: Annotated[
            bool, typer.Option("--json", help="Print one JSON object instead.")
        ] = False,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        poses: Annotated[
            bool, typer.Option("--poses/--no-poses", help="Look up sensor poses.")
        ] = True,
        on_error: OnErrorOption = "stop",
    ) -> None:
        """Summarise a recording: per laser topic the scan count, rate, field of view, beams,
        angular resolution, range limits, share of invalid beams and how many scans have a
        sensor pose; and whether it carries ground truth."""
        rec = _open(recording, world_frame, mount or [], poses, on_error)
        try:
            report = summarise(rec, topic or None)
        finally:
            report_damage(rec)
            rec.close()
        if as_json:
            import json  # (at use: not for every start-up)

            print(json.dumps(_finite(report), allow_nan=False))
        else:
            _print_table(report)
