"""The group tracker's output on a simulated entrance hall and on the real demo bag, as
flat arrays, for the regression test that keeps its decisions identical while its
internals are made faster (tests/test_track_groups_regression.py).

    PYTHONPATH=src LASERPEOPLE_SHARED_DATA=/work/shared/data \
        python tests/group_tracker_reference.py   # rewrites tests/data/group_tracker_reference.npz

Only rewrite the reference when a change to the group tracker's decisions is intended
(the bag's arrays are written only when the shared data are there).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.mht.core import MHTParams

REFERENCE = Path(__file__).parent / "data" / "group_tracker_reference.npz"
SIM = ("entrance-hall", 30.0, 0)
"""Scenario, seconds, seed of the simulated run (d_P = 1.3 m, 000's; up to 16 people in
view)."""
PEOPLE_ONLY = ("entrance-hall", 15.0, 1)
"""Scenario, seconds, seed of the people-only run (no split/merge, d_P = 0.5 m)."""
EXTENSIONS = ("entrance-hall", 20.0, 2)
"""Scenario, seconds, seed of the run with the non-default options (joined observations,
re-clustering by blobs, rms Hausdorff, normalised priors, compatibility merge term)."""
DEMO_BAG = "leg_tracker/rosbags/demos/demo_stationary_simple_environment.bag"
BAG_SCANS = 300
"""Scans of the demo bag tracked (its first ones)."""
REFERENCE_MHT = MHTParams(min_ratio=1e-3)
"""Ratio pruning of every run here: the group tracker's default until session 9 (now
``GROUP_MIN_RATIO``, 3e-3, docs/groups.md "Settings", ratio pruning), pinned so that the reference
recorded before keeps checking that speed work leaves the decisions unchanged."""
REFERENCE_D_P = 1.3
"""d_P of the group runs (000's; the default is 1.0 m, docs/groups.md "Groups within
1 m"), pinned for the same reason."""
REFERENCE_REPORTING: dict[str, float] = {
    "confirm_scans": 1,
    "confirm_window": 0,
    "confirm_event_scans": 1,
    "id_memory": 0.0,
    "coast_time": 0.0,
    "merged_coast_time": 0.0,
}
"""Every group of the best hypothesis reported in every scan under its own id (000; the
default confirms a group after 3 scans, docs/groups.md "Confirmed groups", and hands a
vanished group's id to the group taking its place, ``id_memory``, and reports a vanished
group at its prediction for a second, ``coast_time``, longer among another group's points,
``merged_coast_time``), pinned so that the
reference recorded before keeps checking the tracker's decisions."""
REFERENCE_SIZE_COUNT = "legs"
REFERENCE_SIZE_STD = 0.25
"""How the reference counted and filtered group sizes (the defaults are now "resolved"
and 0.15, docs/groups.md "Group size"), pinned for the same reason. No likelihood reads
the size, but with a range of counts (``stride_near``, ``stride_far``) the size read
decides a tie where two tracks of one group coincide (the hall at 25.5 s: one track kept
instead of a merge), so the reference was recorded again with the range."""


def track_frames(
    frames: list,  # type: ignore[type-arg]
    prefix: str,
    params: GroupTrackerParams | None = None,
) -> dict[str, NDArray]:  # type: ignore[type-arg]
    """Track ``frames`` with a fresh group tracker (000's setting,
    :class:`GroupTrackerParams` (defaults) with :data:`REFERENCE_MHT` and
    :data:`REFERENCE_REPORTING`, unless
    ``params`` are given). Arrays
    (``prefix`` + name):

    * ``rows`` (R, 33): per reported track and frame: frame, track id, size (rounded),
      mean (5), covariance (25, row-major);
    * ``labels`` (R,): the track's label string;
    * ``events`` (E,): "stamp kind labels" of every split and merge reported;
    * ``points`` (P,): the group (track id) of every point, frame after frame, and
      ``point_frames`` (F + 1,) the offsets of the frames in it;
    * ``stats`` (F, 3): hypotheses, models generated so far, live track nodes.
    """
    from laserpeople.tracking.groups import GroupMHTTracker

    if params is None:
        params = GroupTrackerParams(
            cluster_distance=REFERENCE_D_P,
            mht=REFERENCE_MHT,
            size_count=REFERENCE_SIZE_COUNT,
            size_std=REFERENCE_SIZE_STD,
            **REFERENCE_REPORTING,
        )
    tracker = GroupMHTTracker(params)
    rows: list[list[float]] = []
    labels: list[str] = []
    points: list[NDArray[np.int64]] = []
    stats: list[tuple[int, int, int]] = []
    for k, frame in enumerate(frames):
        out = tracker.update(frame)
        for g, t in zip(tracker.last_groups, out, strict=True):
            rows.append([k, g.family, float(t.size), *g.mean, *g.cov.ravel()])
            labels.append(t.labels)
        points.append(tracker.point_labels(len(frame.points)))
        assert tracker.last_stats is not None
        stats.append(
            (
                tracker.last_stats.n_hypotheses,
                tracker.branches.models_generated,
                tracker.last_stats.n_live_nodes,
            )
        )
    offsets = np.concatenate([[0], np.cumsum([p.size for p in points])])
    return {
        f"{prefix}rows": np.asarray(rows, dtype=np.float64).reshape(-1, 33),
        f"{prefix}labels": np.asarray(labels, dtype=np.str_),
        f"{prefix}events": np.asarray(
            [f"{e.stamp!r} {e.kind} {','.join(e.labels)}" for e in tracker.events], dtype=np.str_
        ),
        f"{prefix}points": np.concatenate(points) if points else np.empty(0, dtype=np.int64),
        f"{prefix}point_frames": offsets.astype(np.int64),
        f"{prefix}stats": np.asarray(stats, dtype=np.int64).reshape(-1, 3),
    }


def sim_arrays() -> dict[str, NDArray]:  # type: ignore[type-arg]
    """The simulated run's arrays (prefix ``sim_``) and its clustering and size errors
    (``sim_errors``: tracker clustering error, under rate, over rate, size mean error,
    share of exact sizes)."""
    from laserpeople.evaluation.groups import frames_from_scans, run_groups
    from laserpeople.sim.scenarios import run_scenario

    name, seconds, seed = SIM
    scans = run_scenario(name, seconds=seconds, seed=seed).scans
    out = track_frames([lf.frame for lf in frames_from_scans(scans)], "sim_")
    reference = GroupTrackerParams(
        cluster_distance=REFERENCE_D_P,
        mht=REFERENCE_MHT,
        size_count=REFERENCE_SIZE_COUNT,
        size_std=REFERENCE_SIZE_STD,
        **REFERENCE_REPORTING,
    )
    run = run_groups(scans, reference)
    out["sim_errors"] = np.array(
        [
            run.clustering.error,
            run.clustering.under_rate,
            run.clustering.over_rate,
            run.size.mean_error,
            run.size.exact_share,
        ]
    )
    return out


def people_only_arrays() -> dict[str, NDArray]:  # type: ignore[type-arg]
    """The people-only tracker's arrays on :data:`PEOPLE_ONLY` (prefix ``people_``)."""
    from laserpeople.evaluation.groups import frames_from_scans
    from laserpeople.sim.scenarios import run_scenario

    name, seconds, seed = PEOPLE_ONLY
    scans = run_scenario(name, seconds=seconds, seed=seed).scans
    frames = [lf.frame for lf in frames_from_scans(scans)]
    params = GroupTrackerParams.people_only(
        mht=REFERENCE_MHT,
        size_count=REFERENCE_SIZE_COUNT,
        size_std=REFERENCE_SIZE_STD,
        **REFERENCE_REPORTING,
    )
    return track_frames(frames, "people_", params)


def extensions_arrays() -> dict[str, NDArray]:  # type: ignore[type-arg]
    """The arrays (prefix ``ext_``) of :data:`EXTENSIONS` with every optional path on."""
    from dataclasses import replace

    from laserpeople.evaluation.groups import frames_from_scans
    from laserpeople.sim.scenarios import run_scenario

    name, seconds, seed = EXTENSIONS
    scans = run_scenario(name, seconds=seconds, seed=seed).scans
    frames = [lf.frame for lf in frames_from_scans(scans)]
    params = replace(
        GroupTrackerParams(),
        join_observations=True,
        recluster_blobs=True,
        hausdorff="rms",
        model_prior="normalised",
        merge_likelihood="compatibility",
        cluster_distance=REFERENCE_D_P,
        mht=REFERENCE_MHT,
        size_count=REFERENCE_SIZE_COUNT,
        size_std=REFERENCE_SIZE_STD,
        **REFERENCE_REPORTING,  # type: ignore[arg-type]
    )
    return track_frames(frames, "ext_", params)


def bag_frames(root: Path) -> list:  # type: ignore[type-arg]
    """Frames of the demo bag's first :data:`BAG_SCANS` scans as the pipeline makes them
    for the group tracker (foreground from the static world model)."""
    from laserpeople.io import open_recording
    from laserpeople.pipeline import FrameChooser, Pipeline, laser_frames, observe_stages_for
    from laserpeople.tracking.groups import GroupMHTTracker

    rec = open_recording(root / DEMO_BAG)
    try:
        scans = list(rec.scans(None))[:BAG_SCANS]
    finally:
        rec.close()
    pre, obs = observe_stages_for(GroupMHTTracker.consumes, None)
    pipe = Pipeline(FrameChooser()(laser_frames(scans)), preprocess=pre, observe=obs)
    return [step.frame for step in pipe]


def bag_arrays(root: Path) -> dict[str, NDArray]:  # type: ignore[type-arg]
    """The demo bag run's arrays (prefix ``bag_``)."""
    return track_frames(bag_frames(root), "bag_")


def shared_root() -> Path:
    return Path(os.environ.get("LASERPEOPLE_SHARED_DATA", "/work/shared/data"))


if __name__ == "__main__":
    arrays = sim_arrays()
    arrays.update(people_only_arrays())
    arrays.update(extensions_arrays())
    root = shared_root()
    if (root / DEMO_BAG).is_file():
        arrays.update(bag_arrays(root))
    else:
        print(f"demo bag not found under {root}: writing the simulated run only", file=sys.stderr)
    REFERENCE.parent.mkdir(exist_ok=True)
    np.savez_compressed(REFERENCE, **arrays)
    print(f"wrote {REFERENCE}")
