"""How good the walkers' velocities are (group tracker's walkers extension,
``tracking/groups/walkers.py``; docs/groups.md "Walkers"), on the simulated entrance hall
against the simulator's true velocities, and what their cut does to memory-less
clustering at d_P (fast: no MHT) and, with ``--groups``, to the group tracker.

Every walker of every scan whose velocity is known is matched to the person most of its
points belong to; its velocity error is reported by the kind of its detection (two legs,
one wider blob, one leg alone) and by the person's true speed. Tuning seeds (0 and 1)
only by default.

    PYTHONPATH=src python benchmarks/walker_velocity.py [--seeds 0 1] [--seconds 30]
        [--set velocity=window window=1.0 ...] [--groups]

``--set NAME=VALUE`` sets a field of ``GroupTrackerParams`` (``walker_*``; ``walkers`` is
set to true).
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from laserpeople.clustering import single_linkage
from laserpeople.evaluation.clustering import ClusteringError
from laserpeople.evaluation.groups import frames_from_scans, run_groups
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.observations import close_pairs, component_labels, within_size
from laserpeople.tracking.groups.walkers import LONE, PAIR, WIDE, WalkerTracker

KIND_NAMES = {PAIR: "two legs", WIDE: "wide blob", LONE: "lone leg"}
SPEEDS = ((0.0, 0.2, "standing < 0.2"), (0.2, 0.5, "0.2-0.5"), (0.5, 9.0, "walking > 0.5"))


def _value(text: str) -> object:
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    for cast in (int, float):
        try:
            return cast(text)
        except ValueError:
            continue
    return text


def params_from(sets: list[str]) -> GroupTrackerParams:
    """``GroupTrackerParams(walkers=True, **sets)``."""
    changes: dict[str, object] = {"walkers": True}
    for item in sets:
        key, _, text = item.partition("=")
        changes[key] = _value(text)
    return dataclasses.replace(GroupTrackerParams(), **changes)  # type: ignore[arg-type]


def _quantiles(errors: list[float]) -> str:
    if not errors:
        return "-"
    e = np.asarray(errors)
    p50, p90 = np.percentile(e, [50, 90])
    return f"p50 {p50:.3f} p90 {p90:.3f} (n {e.size})"


def measure(seed: int, seconds: float, params: GroupTrackerParams, groups: bool) -> None:
    """Print the velocity errors and clustering errors of one seed."""
    result = run_scenario("entrance-hall", seconds=seconds, seed=seed)
    truth = {t.scan_index: t for t in result.truth}
    tracker = WalkerTracker(params.walker_settings())
    errors: dict[tuple[int, int], list[float]] = {}
    moving: list[float] = []
    cut_err, ml_err = ClusteringError(), ClusteringError()
    ms: list[float] = []
    d_p, d_hs = params.cluster_distance, params.blob_distance
    for lf in frames_from_scans(result.scans):
        fg = np.nonzero(np.asarray(lf.frame.foreground))[0]
        assert lf.frame.points is not None
        pts = lf.frame.points.points[fg]
        person = lf.true_person[fg]
        group = lf.true_group[fg]
        t0 = time.process_time()
        pairs, length = close_pairs(pts, d_p)
        blobs = component_labels(len(pts), pairs[length < d_hs])
        keep = within_size(pts, blobs, params.max_blob_size)
        if not keep.all():  # as GroupObservations.from_points
            pts, person, group = pts[keep], person[keep], group[keep]
            pairs, length = close_pairs(pts, d_p)
            blobs = component_labels(len(pts), pairs[length < d_hs])
        links = pairs[length < d_p]
        kept = tracker.coherent_links(pts, blobs, links, lf.frame.stamp)
        ms.append((time.process_time() - t0) * 1e3)
        ml_err.accumulate_labels(group, single_linkage(pts, d_p), lf.frame.stamp)
        cut_err.accumulate_labels(group, component_labels(len(pts), links[kept]), lf.frame.stamp)
        if tracker.last_scan is None or not len(pts):
            continue
        walker, velocity, known, _ = tracker.last_scan
        t = truth[lf.frame.index]
        true_v = {int(p): t.velocities[i] for i, p in enumerate(t.person_ids)}
        scan_kinds = _scan_kinds(tracker, velocity.shape[0])
        for w in np.nonzero(known)[0].tolist():
            mine = person[walker == w]
            if mine.size == 0:
                continue
            who = int(np.bincount(mine).argmax())
            v_true = true_v[who]
            err = float(np.hypot(*(velocity[w] - v_true)))
            speed = float(np.hypot(*v_true))
            band = next(i for i, (lo, hi, _) in enumerate(SPEEDS) if lo <= speed < hi)
            errors.setdefault((int(scan_kinds[w]), band), []).append(err)
            if band == 2:
                moving.append(err)
    ml, cut = ml_err.result(), cut_err.result()
    print(
        f"seed {seed}: walking walkers {_quantiles(moving)}; memory-less {ml.error:.3f}, "
        f"with the cut {cut.error:.3f} (under {cut.under_rate:.3f}, over "
        f"{cut.over_rate:.3f}); walkers {np.median(ms):.2f} ms/scan (median, with the "
        f"links)",
        flush=True,
    )
    for kind, name in KIND_NAMES.items():
        row = [_quantiles(errors.get((kind, band), [])) for band in range(len(SPEEDS))]
        cells = [f"{band[2]}: {r}" for band, r in zip(SPEEDS, row, strict=True)]
        print(f"  {name:10s} " + " | ".join(cells))
    if groups:
        g = run_groups(result.scans, params)
        print(
            f"  group tracker: {g.clustering.error:.3f} (under {g.clustering.under_rate:.3f}, "
            f"over {g.clustering.over_rate:.3f}), memory-less {g.memoryless.error:.3f}, "
            f"{g.median_ms:.2f} ms/scan (median)",
            flush=True,
        )


def _scan_kinds(tracker: WalkerTracker, n: int) -> np.ndarray:
    """Kind (n,) of this scan's detection of each of its ``n`` walkers (in the order of
    ``last_scan``): the tracker's ``last_kind`` of the walkers seen, by id."""
    assert tracker.last_scan is not None
    ids = tracker.last_scan[3]
    kind_of = dict(zip(tracker.ids.tolist(), tracker.last_kind.tolist(), strict=True))
    return np.array([kind_of.get(i, -1) for i in ids.tolist()], dtype=np.int64).reshape(n)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    ap.add_argument("--groups", action="store_true", help="also run the group tracker")
    args = ap.parse_args()
    params = params_from(args.set)
    print(params.walker_settings(), flush=True)
    for seed in args.seeds:
        measure(seed, args.seconds, params, args.groups)


if __name__ == "__main__":
    main()
