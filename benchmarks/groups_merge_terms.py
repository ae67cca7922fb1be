"""Why the group tracker's merges win (000 eqs. 24-32): for every parent hypothesis that
has both a model merging two tracks and the model continuing them all, the prior term
(eq. 32 read as ``model_prior``, with eq. 27's log N_ij) and the data term (the best
assignment's cost: eq. 24 of the merged track against the shares of the re-clustered
observation) of the merge model against the all-continue model, both in -log, grouped by
how far apart the velocities eqs. 25-27 compare are. A negative difference favours the
merge.

    PYTHONPATH=src python benchmarks/groups_merge_terms.py [--seeds 0-9] [--seconds 40]
        [--set NAME=VALUE ...]
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Hashable, Sequence
from typing import Any

import numpy as np

from groups_random import parse_seeds  # type: ignore[import-not-found]
from groups_table import _with  # type: ignore[import-not-found]
from laserpeople.evaluation.groups import frames_from_scans
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupMHTTracker, GroupTrackerParams
from laserpeople.tracking.groups.interaction import GroupBranches
from laserpeople.tracking.groups.model import group_payload
from laserpeople.tracking.mht import core
from laserpeople.tracking.mht.protocols import Branch
from laserpeople.tracking.mht.tracktree import TrackNode

TRAIL_YOUNG = 5
"""A track with fewer observed centroids in its trail counts as young (a split half or a
new track)."""


class _Recorder:
    """Wraps :meth:`GroupBranches.branches` and :meth:`core.MHT._k_best` to pair each
    parent's merge models with its all-continue model."""

    def __init__(self) -> None:
        # id of a branch's tracks -> (those tracks, parent's tracks, kinds, pair facts)
        self.info: dict[int, tuple[Any, ...]] = {}
        self.rows: list[tuple[int, tuple[str, ...], Any, float, float]] = []
        self._branches = GroupBranches.branches
        self._k_best = core.MHT._k_best

    def install(self) -> None:
        """Put the wrappers in place."""
        rec = self

        def branches(
            self: GroupBranches, tracks: tuple[TrackNode, ...], gate_row: Any, meas_idx: Any
        ) -> list[Branch]:
            out = rec._branches(self, tracks, gate_row, meas_idx)
            if len(out) > 1:
                ids = {t.node_id for t in tracks}
                for b in out:
                    kept = {t.node_id for t in b.tracks}
                    kinds = tuple(
                        sorted(group_payload(t).event for t in b.tracks if t.node_id not in ids)
                    )
                    pair = None
                    gone = [t for t in tracks if t.node_id not in kept]
                    if kinds == ("merge",) and len(gone) == 2:
                        va = self.merge_motion(gone[0])[0][2:4]
                        vb = self.merge_motion(gone[1])[0][2:4]
                        ll = self._merge_ll.get((gone[0].node_id, gone[1].node_id), math.nan)
                        young = min(len(group_payload(g).trail) for g in gone) < TRAIL_YOUNG
                        pair = (float(np.hypot(*(va - vb))), ll, young)
                    rec.info[id(b.tracks)] = (b.tracks, tracks, kinds, pair)
            return out

        def k_best(
            self: core.MHT[Any], tracks_of: Sequence[Any], priors: list[float], *a: Any
        ) -> Any:
            found = rec._k_best(self, tracks_of, priors, *a)
            best: dict[int, float] = {}
            for pi, _, total in found:
                best[pi] = min(best.get(pi, math.inf), total)
            for pi, tracks in enumerate(tracks_of):
                got = rec.info.get(id(tracks))
                if got is not None and got[0] is tracks:
                    rec.rows.append(
                        (id(got[1]), got[2], got[3], priors[pi], best.get(pi, math.inf))
                    )
            return found

        GroupBranches.branches = branches  # type: ignore[method-assign]
        core.MHT._k_best = k_best  # type: ignore[method-assign]

    def pairs(self) -> list[tuple[float, float, bool, float, float]]:
        """This scan's (velocity difference [m/s], log N_ij, young, prior difference, data
        difference) per parent and merge model; then forgets the scan."""
        by_parent: dict[Hashable, list[tuple[Any, ...]]] = {}
        for parent, kinds, pair, prior, total in self.rows:
            by_parent.setdefault(parent, []).append((kinds, pair, prior, total))
        out = []
        for models in by_parent.values():
            cont = [m for m in models if m[0] == ()]
            if not cont or not math.isfinite(cont[0][3]):
                continue
            _, _, c_prior, c_total = cont[0]
            for kinds, pair, prior, total in models:
                if kinds != ("merge",) or pair is None or not math.isfinite(total):
                    continue
                d_prior = prior - c_prior
                d_data = (total - prior) - (c_total - c_prior)
                out.append((pair[0], pair[1], pair[2], d_prior, d_data))
        self.info.clear()
        self.rows.clear()
        return out


def main() -> None:
    """Print the terms per band of velocity difference."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="0-9")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    args = ap.parse_args()
    params = _with(GroupTrackerParams(), args.set)
    rec = _Recorder()
    rec.install()
    rows: list[tuple[float, float, bool, float, float]] = []
    for seed in parse_seeds(args.seeds):
        sim = run_scenario("random-groups", seed=seed, seconds=args.seconds)
        tracker = GroupMHTTracker(params)
        for lf in frames_from_scans(sim.scans):
            tracker.update(lf.frame)
            rows += rec.pairs()
    a = np.array(rows, dtype=np.float64).reshape(-1, 5)
    print(f"parents with a merge model and the all-continue model: {len(a)}")
    print(
        "| velocities apart [m/s] | parents | merge better | prior for it | data for it "
        "| median prior / data diff (wins) | median log N_ij (wins) | young (wins) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for lo, hi in ((0.0, 0.3), (0.3, 0.5), (0.5, math.inf)):
        band = a[(a[:, 0] >= lo) & (a[:, 0] < hi)]
        win = band[band[:, 3] + band[:, 4] < 0.0]
        if not len(win):
            print(f"| {lo}-{hi} | {len(band)} | 0 | | | | | |")
            continue
        print(
            f"| {lo}-{hi} | {len(band)} | {len(win)} | {int((win[:, 3] < 0).sum())} "
            f"| {int((win[:, 4] < 0).sum())} | {np.median(win[:, 3]):+.2f} / "
            f"{np.median(win[:, 4]):+.2f} | {np.nanmedian(win[:, 1]):.2f} "
            f"| {int(win[:, 2].sum())} |"
        )
    print(f"median data difference over all parents: {np.median(a[:, 4]):+.2f}")


if __name__ == "__main__":
    main()
