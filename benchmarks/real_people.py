"""People on real unlabelled recordings: how many person ids, and how long people are
reported on things that never move.

For each recording (the shipped AdaBoost detector, the leg MHT through the pipeline, i.e.
as ``laserpeople track`` runs it, with the static world model ``--background``): person ids;
*walker ids*, those whose track spans at least ``--walk`` metres (the extent of its
positions); person-track-seconds (all, and of walkers); *static seconds*, the
person-track-seconds of ids whose positions stay within ``--walk`` metres for their whole
life (a person track that never moves sits on furniture, a wall or a standing person; on
these recordings people walk through); and *gaps*, the times a walker's id stops being
reported for at least 1 s and comes back.

With ``--groups`` the same counts for the group tracker's groups (``--tracker group-mht``,
000 Sec. 4) instead of people, for ``group_tracker.static_groups`` false (the default: groups
on static places that never walked are not reported) and true (000: every group); a
column counts the ids reported for at most 3 scans. Both with the default confirmation
(``group_tracker.confirm_scans``; ``benchmarks/groups_confirm.py`` compares its settings).

With ``--trackers`` the same counts for the person tracks of other registered trackers
(``csa``, ``feet-pf``, ``upper-body-pf``, ``nn``; each with its defaults and the default
static world model, as ``laserpeople track --tracker NAME`` runs it), with their person
tracks on static places reported (``static_tracks.hide`` false, the papers) and left out
(true, the default; ``pipeline/static_tracks.py``).

    PYTHONPATH=src .venv/bin/python benchmarks/real_people.py [--policies arras tracks
        tracks-noreid]
        [--backgrounds none auto] [--bags demo mir mir-all corridor] [--groups]
        [--trackers csa feet-pf upper-body-pf] [--config params.toml]
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from laserpeople.config import load_config
from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.frame import Frame
from laserpeople.pipeline import Pipeline, build
from laserpeople.pipeline.background import load_static_world
from laserpeople.pipeline.static_people import describe_people_model
from laserpeople.pipeline.static_tracks import StaticTrackFilter
from laserpeople.tracking import registry
from laserpeople.tracking.groups.params import GroupTrackerParams
from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.tracks import Tracks

ROOT = Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "../shared/data"))
MIR = ROOT / "mir/rosbags/mir_data/legs-test-split-2022-11-21-15-51-02-topic-split.bag"
BAGS: dict[str, tuple[Path, list[str] | None, list[str]]] = {
    # name: (recording, topics, mounts)
    "demo": (ROOT / "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag", None, []),
    "mir": (MIR, ["front_laser_link"], ["mir100"]),
    "mir-all": (MIR, ["all"], ["mir100"]),
    "corridor": (ROOT / "mir/rosbags/corridor/corridor.bag", None, []),
}


@dataclass(frozen=True)
class RealCount:
    """Counts of one recording, policy and static world model."""

    ids: int
    walker_ids: int
    person_seconds: float
    walker_seconds: float
    static_seconds: float
    gaps: int
    ms: float
    model: str = ""
    short_ids: int = 0


def count(tracks: list[Tracks], walk: float, gap: float = 1.0, kind: str = "person") -> RealCount:
    """Ids, walkers, track-seconds, static seconds, walker gaps (see the module docstring)
    and ids reported in at most 3 scans, of the tracks of ``kind``."""
    positions: dict[int, list[np.ndarray]] = {}
    seconds: dict[int, float] = {}
    stamps: dict[int, list[float]] = {}
    for k in range(1, len(tracks)):
        dt = tracks[k].stamp - tracks[k - 1].stamp
        for t in tracks[k].of_kind(kind):
            positions.setdefault(t.track_id, []).append(t.position)
            seconds[t.track_id] = seconds.get(t.track_id, 0.0) + dt
            stamps.setdefault(t.track_id, []).append(tracks[k].stamp)
    walkers = 0
    static = 0.0
    walker_s = 0.0
    gaps = 0
    for pid, pts in positions.items():
        arr = np.stack(pts)
        extent = float(np.max(np.linalg.norm(arr - arr.mean(axis=0), axis=1))) * 2.0
        if extent >= walk:
            walkers += 1
            walker_s += seconds[pid]
            gaps += int(np.sum(np.diff(np.asarray(stamps[pid])) >= gap))
        else:
            static += seconds[pid]
    short = sum(len(p) <= 3 for p in positions.values())
    return RealCount(
        len(positions), walkers, sum(seconds.values()), walker_s, static, gaps, 0.0, "", short
    )


def run(
    key: str, policy: str, background: str, walk: float, config: Path | None = None
) -> RealCount:
    """Track one recording through the pipeline with ``policy`` and ``background`` (the
    leg MHT's other parameters from ``config``'s ``[leg_tracker]``, the static world
    models' from their sections; None: defaults)."""
    bag, topics, mounts = BAGS[key]
    base = load_config(LegTrackerParams, config)
    params = replace(base, people_policy=policy.removesuffix("-noreid"))
    if policy.endswith("-noreid"):  # the tracks policy without re-identification
        people = params.people
        params = replace(params, people=replace(people, reid=replace(people.reid, enabled=False)))
    tracker = registry.get("leg-mht").make(params)
    pipe = build(
        bag,
        tracker=tracker,
        topics=topics,
        mounts=mounts,
        detector=AdaBoostLegDetector.default(),
        background=background if params.people_policy == "tracks" else "none",
        static_world=load_static_world(config),
    )
    out, ms = track_all(pipe)
    return replace(count(out, walk), ms=ms, model=describe_people_model(tracker, pipe.stages))


def track_all(pipe: Pipeline) -> tuple[list[Tracks], float]:
    """Every frame's tracks of ``pipe`` and the process CPU [ms] per frame."""
    out: list[Tracks] = []
    t0 = time.process_time()
    for step in pipe:
        assert step.tracks is not None
        out.append(step.tracks)
    return out, 1e3 * (time.process_time() - t0) / max(len(out), 1)


def run_groups(key: str, static_groups: bool, walk: float, config: Path | None = None) -> RealCount:
    """Track one recording's groups through the pipeline (``--tracker group-mht``) with the
    ``[group_tracker]`` section of ``config`` (the defaults when None)."""
    bag, topics, mounts = BAGS[key]
    params = replace(load_config(GroupTrackerParams, config), static_groups=static_groups)
    tracker = registry.get("group-mht").make(params)
    out, ms = track_all(build(bag, tracker=tracker, topics=topics, mounts=mounts))
    return replace(count(out, walk, kind="group"), ms=ms)


def main_groups(bags: list[str], walk: float, config: Path | None = None) -> None:
    """The group table (``--groups``): static_groups true and false."""
    print(
        "bag      static_groups  ids  walkers  short  group-s  walker-s  static-s  gaps  ms/frame"
    )
    for key in bags:
        for static_groups in (True, False):
            c = run_groups(key, static_groups, walk, config)
            print(
                f"{key:8s} {static_groups!s:13s} {c.ids:4d} {c.walker_ids:8d} "
                f"{c.short_ids:6d} "
                f"{c.person_seconds:8.1f} {c.walker_seconds:9.1f} {c.static_seconds:9.1f} "
                f"{c.gaps:5d} {c.ms:8.2f}",
                flush=True,
            )


def leg_mht_people(key: str) -> dict[int, np.ndarray]:
    """Per scan index, the default leg MHT's person positions (M, 2) on recording ``key``:
    the reference that ``--trackers`` splits hidden rows by (near a person or not)."""
    bag, topics, mounts = BAGS[key]
    pipe = build(bag, topics=topics, mounts=mounts, detector=AdaBoostLegDetector.default())
    out, _ = track_all(pipe)
    return {
        t.scan_index: np.array([p.position for p in t.of_kind("person")]).reshape(-1, 2)
        for t in out
    }


@dataclass(frozen=True)
class HiddenSplit:
    """Person-seconds of the rows ``static_tracks`` kept and hid, near (within 0.5 m) a
    person of the default leg MHT and elsewhere."""

    near_kept: float
    near_hidden: float
    far_kept: float
    far_hidden: float


def run_tracker(
    key: str,
    name: str,
    hide: bool,
    walk: float,
    reference: dict[int, np.ndarray],
    config: Path | None = None,
) -> tuple[RealCount, HiddenSplit | None]:
    """Track one recording's people with the registered tracker ``name`` (its section of
    ``config`` and the static world models' sections, as ``laserpeople track --config``
    reads them; None: defaults), its person tracks on static places left out when ``hide``
    (``static_tracks.hide``); with ``hide``, also where the hidden rows were (see
    :class:`HiddenSplit`)."""
    bag, topics, mounts = BAGS[key]
    entry = registry.get(name)
    tracker = entry.make(load_config(entry.params_cls, config))
    detector = AdaBoostLegDetector.default() if "legs" in tracker.consumes else None
    static = load_static_world(config)
    static = replace(static, static_tracks=replace(static.static_tracks, hide=hide))
    pipe = build(
        bag, tracker=tracker, topics=topics, mounts=mounts, detector=detector, static_world=static
    )
    seconds = np.zeros((2, 2))  # [near, far] x [kept, hidden]
    stage = next((i for i in pipe.identify if isinstance(i, StaticTrackFilter)), None)
    if stage is not None:
        update = stage.update
        last: list[float] = []

        def split(tracks: Tracks, frame: Frame) -> Tracks:
            out = update(tracks, frame)
            dt = tracks.stamp - last[0] if last else 0.0
            last[:] = [tracks.stamp]
            kept = {t.track_id for t in out.of_kind("person")}
            ref = reference.get(tracks.scan_index, np.zeros((0, 2)))
            for t in tracks.of_kind("person"):
                far = len(ref) == 0 or float(np.min(np.hypot(*(ref - t.position).T))) >= 0.5
                seconds[int(far), int(t.track_id not in kept)] += dt
            return out

        stage.update = split  # type: ignore[method-assign]
    out, ms = track_all(pipe)
    hidden = HiddenSplit(*seconds.ravel().tolist()) if stage is not None else None
    return replace(count(out, walk), ms=ms), hidden


def main_trackers(
    bags: list[str], names: list[str], walk: float, config: Path | None = None
) -> None:
    """The table of other trackers' people (``--trackers``), with ``static_tracks.hide``
    false (the papers: every track) and true (the default), and where the hidden rows were:
    near a person of the default leg MHT (4 ids for 4 walkers on the demo bag) or not."""
    print(
        "bag      tracker        hide   ids  walkers  person-s  walker-s  static-s  gaps  "
        "ms/frame  | person-s near a leg-MHT person: kept / hidden, elsewhere: kept / hidden"
    )
    for key in bags:
        reference = leg_mht_people(key)
        for name in names:
            for hide in (False, True):
                c, h = run_tracker(key, name, hide, walk, reference, config)
                where = (
                    f"  | {h.near_kept:6.1f} / {h.near_hidden:5.1f}, "
                    f"{h.far_kept:6.1f} / {h.far_hidden:5.1f}"
                    if h is not None
                    else ""
                )
                print(
                    f"{key:8s} {name:13s} {hide!s:5s} {c.ids:4d} {c.walker_ids:8d} "
                    f"{c.person_seconds:9.1f} {c.walker_seconds:9.1f} {c.static_seconds:9.1f} "
                    f"{c.gaps:5d} {c.ms:8.2f}{where}",
                    flush=True,
                )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bags", nargs="+", default=list(BAGS), choices=list(BAGS))
    ap.add_argument("--policies", nargs="+", default=["arras", "tracks"])
    ap.add_argument("--backgrounds", nargs="+", default=["none", "auto"])
    ap.add_argument("--walk", type=float, default=1.0, help="m")
    ap.add_argument("--groups", action="store_true", help="count the group tracker's groups")
    ap.add_argument(
        "--config",
        type=Path,
        help="TOML whose [leg_tracker] section the leg MHT uses and the static world models' "
        "sections ([group_tracker] with --groups; with --trackers each tracker's own section)",
    )
    ap.add_argument(
        "--trackers", nargs="+", default=[], help="count the people of these registered trackers"
    )
    args = ap.parse_args()
    if args.trackers:
        main_trackers(args.bags, args.trackers, args.walk, args.config)
        return
    if args.groups:
        main_groups(args.bags, args.walk, args.config)
        return
    print(
        "bag      policy        background  ids  walkers  person-s  walker-s  static-s  gaps  "
        "ms/frame (detection included)"
    )
    for key in args.bags:
        for policy in args.policies:
            for background in args.backgrounds if policy != "arras" else ["none"]:
                c = run(key, policy, background, args.walk, args.config)
                print(
                    f"{key:8s} {policy:13s} {background:10s} {c.ids:4d} {c.walker_ids:8d} "
                    f"{c.person_seconds:9.1f} {c.walker_seconds:9.1f} {c.static_seconds:9.1f} "
                    f"{c.gaps:5d} {c.ms:8.2f}   {c.model}",
                    flush=True,
                )


if __name__ == "__main__":
    main()
