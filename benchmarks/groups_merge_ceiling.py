"""How much the group tracker's merges gain from better velocities (000 eqs. 25-27): the
randomised group scenes (or the entrance hall) tracked with the velocity eq. 26 compares
taken from the simulator's truth (the mean true velocity of the people whose points a
track held in its last observation, with a std of ``--oracle-std`` per component),
against the tracker's own (the trail slope of ``velocity_window``, or the Kalman filter's
with ``--set velocity_window=0``). Also prints how far the tracker's own velocities that
eq. 26 compared were from the truth (error std per component, and the mean of the squared
errors over their variance: 1 when the variance is right).

    PYTHONPATH=src python benchmarks/groups_merge_ceiling.py [--scenario random-groups]
        [--seeds 0-9] [--seconds 40] [--oracle] [--oracle-std 0.1] [--set NAME=VALUE ...]
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from typing import Any

import numpy as np

import laserpeople.evaluation.groups as evaluation_groups
from groups_random import parse_seeds, pooled  # type: ignore[import-not-found]
from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.config import load_config
from laserpeople.evaluation.groups import LabelledFrame, run_groups
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracking.groups.interaction import GroupBranches
from laserpeople.tracking.groups.model import group_payload, with_trail_velocity
from laserpeople.tracking.mht.tracktree import TrackNode
from laserpeople.truth import TruthFrame


class _Truth:
    """The labelled frames and truth of one run, by stamp."""

    def __init__(self, truth: list[TruthFrame]) -> None:
        self.by_index = {t.scan_index: t for t in truth}
        self.person_at: dict[float, np.ndarray] = {}
        self.truth_at: dict[float, TruthFrame] = {}
        self.errors: list[np.ndarray] = []  # (error vx, error vy, var) per compared velocity

    def true_velocity(self, node: TrackNode) -> np.ndarray | None:
        """Mean true velocity (2,) of the people among the node's last observed points."""
        members = group_payload(node).members
        person = self.person_at.get(node.stamp)
        truth = self.truth_at.get(node.stamp)
        if members.size == 0 or person is None or truth is None:
            return None
        who = person[members]
        who = who[who >= 0]
        if who.size == 0:
            return None
        row = {int(p): i for i, p in enumerate(truth.person_ids.tolist())}
        vs = [truth.velocities[row[p]] for p in who.tolist() if p in row]
        return np.mean(vs, axis=0) if vs else None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default="random-groups", help="or entrance-hall")
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--oracle", action="store_true", help="eq. 26 compares true velocities")
    ap.add_argument("--oracle-std", type=float, default=0.1, help="m/s per component")
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    args = ap.parse_args()
    params = _with(load_config(GroupTrackerParams, None, None), args.set)
    state: dict[str, _Truth] = {}
    plain_frames = evaluation_groups.frames_from_scans
    plain_motion = GroupBranches.merge_motion

    def frames(scans: list[Any]) -> Iterator[LabelledFrame]:
        run = state["run"]
        for lf in plain_frames(scans):
            run.person_at[lf.frame.stamp] = lf.true_person
            t = run.by_index.get(lf.frame.index)
            if t is not None:
                run.truth_at[lf.frame.stamp] = t
            yield lf

    def motion(self: GroupBranches, node: TrackNode) -> tuple[np.ndarray, np.ndarray]:
        mean, cov = plain_motion(self, node)
        run = state["run"]
        true = run.true_velocity(node)
        if true is None:
            return mean, cov
        run.errors.append(np.array([*(mean[2:4] - true), 0.5 * (cov[2, 2] + cov[3, 3])]))
        if args.oracle:
            return with_trail_velocity(mean, cov, true, args.oracle_std**2)
        return mean, cov

    evaluation_groups.frames_from_scans = frames  # type: ignore[assignment]
    GroupBranches.merge_motion = motion  # type: ignore[method-assign]
    runs = []
    errors: list[np.ndarray] = []
    for seed in parse_seeds(args.seeds):
        sim = run_scenario(args.scenario, seconds=args.seconds, seed=seed)
        state["run"] = _Truth(list(sim.truth))
        r = run_groups(sim.scans, params, truth=sim.truth)
        runs.append(r)
        errors += state["run"].errors
        print(
            f"seed {seed}: group MOTA {r.group_mot.mota:.3f}, proxemic "
            f"{r.proxemic_mot.mota:.3f}, merges {r.merges}; clustering error "
            f"{r.clustering.error:.3f} (under {r.clustering.under_rate:.3f}, over "
            f"{r.clustering.over_rate:.3f}), memory-less {r.memoryless.error:.3f}",
            flush=True,
        )
    p = pooled(runs)
    frames = sum(r.clustering.true_groups for r in runs)
    error = sum(r.clustering.error * r.clustering.true_groups for r in runs) / max(frames, 1)
    e = np.array(errors).reshape(-1, 3)
    print(
        f"\noracle {args.oracle} (std {args.oracle_std:g}), set {args.set or 'none'}: group "
        f"MOTA {p['mota']:.3f}, proxemic {p['proxemic']:.3f}, size exact "
        f"{100 * p['exact']:.1f} %, clustering error {error:.3f}"
    )
    if e.size:
        sq = e[:, :2] ** 2
        print(
            f"velocities compared by eq. 26: {len(e)}; error std per component "
            f"{np.sqrt(sq.mean()):.3f} m/s (median |error| {np.median(np.sqrt(sq.sum(1))):.3f}), "
            f"mean error^2 / variance {np.mean(sq / e[:, 2:3]):.2f}"
        )


if __name__ == "__main__":
    main()
