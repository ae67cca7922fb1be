"""The Cluster Sorting Algorithm (CSA) of 002 Sec. 2 (Kräußling et al.).

The CSA tracks people directly on the raw foreground laser points of a frame. Every tracked
object has a validation gate; the points inside a gate are that object's *selected
measurements*. Two kinds of objects:

- a *single target* (one person) is tracked by the Kalman Filter Algorithm (KFA): its
  constant-velocity Kalman filter is updated with the unweighted mean of its selected
  measurements;
- a *cluster* (at least two interacting people) is tracked by the Viterbi-based algorithm
  (VBA): it keeps one position estimate and gate per old selected measurement; the new
  selected measurements are those inside at least one of these gates, and each of them gets
  the estimate of its most likely predecessor (a Viterbi step, :func:`viterbi_step`), so
  the cluster's belief is multi-modal.

Objects whose gates share a measurement merge (person+person, person+cluster,
cluster+cluster), and the cluster remembers which people it holds. A cluster splits
back into single targets when its estimates form as many sub-clusters (leader clustering
at 1.5 m) as it holds people and every pair of sub-clusters is more than 3.0 m apart
(002 split conditions 1 and 2). 002 leaves the identities after a split to the colour
stage (:mod:`laserpeople.identity`); on its own the CSA hands each sub-cluster the person
most of its estimates' Viterbi paths started from (an extension: the laser-only guess).

Initiation and deletion are not in 002 (an assumption here): foreground points selected by
no object are grouped by leader clustering, each group of at least ``min_points`` points
starts a single target, reported once it had points in ``confirm_scans`` scans in a row;
an object unseen for ``max_unseen`` is no longer reported, and deleted ``lost_keep`` later.

Output: one ``person`` track per single target, and per cluster either its people at its
sub-clusters (when there are as many sub-clusters as people, 002 split condition 3 "to
indicate them in the graphics") or one ``group`` track holding its people in ``members``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.clustering.single_linkage import components
from laserpeople.config import param
from laserpeople.frame import Frame, FrameField
from laserpeople.lazy_scipy import linear_sum_assignment
from laserpeople.tracking import kalman
from laserpeople.tracking.csa_people import LegPeople, missed_legs, unheld_people
from laserpeople.tracking.robot_motion import MotionWatch
from laserpeople.tracks import Track, Tracks

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class CSAParams:
    """Parameters of the Cluster Sorting Algorithm (002 Sec. 2)."""

    config_section = "csa"
    paper_preset = MappingProxyType(
        {  # 002 where the defaults depart from it (docs/papers.md)
            "adopt_escaped": False,
            "fragment_rule": False,
            "person_scores": False,
            "adopt_orphans": False,
            "confirm_scans": 1,
            "moving_travel": 0.0,
            "cut_free": False,
            "moving_unseen": 0.0,
            "moving_wall": 0.0,
            "count_people": False,
            "person_mixture": False,
            "background_people": False,
            "moving_people": False,
            "lost_keep": 0.0,
            "split_apart": False,
            "coast_people": False,
        }
    )

    subcluster_distance: float = param(
        1.5,
        "002 Sec. 2, split condition 1 (150 cm, the largest distance between the legs of a "
        "walking person)",
        "estimates closer than this to a sub-cluster's first estimate join that sub-cluster",
        "m",
    )
    separation_distance: float = param(
        3.0,
        "002 Sec. 2, split condition 2 (300 cm)",
        "a cluster splits only when every pair of sub-clusters is farther apart than this "
        "(distance between sub-cluster centroids)",
        "m",
    )
    gate_probability: float = param(
        0.99,
        "assumption (002 cites Bar-Shalom & Fortmann for the gates, no value)",
        "probability mass of each validation gate (chi-square, 2 dof)",
    )
    max_gate_distance: float = param(
        1.0,
        "assumption: bounds the gate of a long-unseen target",
        "Euclidean cap on every validation gate",
        "m",
    )
    point_std: float = param(
        0.15,
        "assumption: laser points of a person lie on two legs about 0.1-0.3 m from its centre",
        "spread of one laser point about the tracked position (gates; VBA updates)",
        "m",
    )
    mean_std: float = param(
        0.08,
        "assumption: the mean of the leg points swings with the gait",
        "noise of the mean of the selected measurements (KFA update)",
        "m",
    )
    person_accel_psd: float = param(
        4.0,
        "assumption: a walking person's centre accelerates by ~1 m/s^2",
        "process noise of single targets (KFA)",
        "m^2/s^3",
    )
    point_accel_psd: float = param(
        32.0,
        "assumption: as the leg tracker's Kalman filter (tracking/kalman.py), an estimate "
        "follows single leg points",
        "process noise of the per-measurement estimates of a cluster (VBA)",
        "m^2/s^3",
    )
    init_velocity_std: float = param(
        1.0, "assumption", "velocity uncertainty of a new single target", "m/s"
    )
    init_distance: float = param(
        0.6,
        "assumption (002 does not describe initiation): a person's leg points lie within "
        "0.6 m of each other",
        "unselected points within this of a group's first point start one new target",
        "m",
    )
    min_points: int = param(3, "assumption", "points needed to start a new single target")
    max_unseen: float = param(
        1.0, "assumption", "an object without selected measurements this long is deleted", "s"
    )
    lost_keep: float = param(
        0.5,
        "extension (002 has no deletion): on the real followed-person recording the leg "
        "detector misses the standing person, whose points come back 1.3 and 1.1 s after "
        "they were last seen, as a new id (ids 5 -> 3); random-groups tuning seeds "
        "0-19 MOTA 0.487 / 0.486 / 0.483 / 0.474 for 0 / 0.5 / 1 / 2 s, held back 100-119 "
        "MOTA 0.493 -> 0.493, IDF1 0.447 -> 0.456 (docs/csa.md, 'Real data')",
        "an object without selected measurements for max_unseen is no longer reported but "
        "kept, predicted and gated, this much longer: points inside its gates continue it "
        "with its id (0: deleted at max_unseen)",
        "s",
    )
    max_dt: float = param(1.0, "assumption", "longest prediction step", "s")
    fragment_age: float = param(
        1.0,
        "assumption; a simulated robot following a person without poses (20 s, seed 0, "
        "tests/test_track_leg_foreground_e2e.py): person MOTA 0.05 -> 0.49",
        "with fragment_rule, a target younger than this that merges is a fragment of the "
        "people it merges with, not another person (when all are this young, the oldest "
        "is the one person): a burst of foreground starts many targets at once",
        "s",
    )
    adopt_escaped: bool = param(
        True,
        "extension of 002 (its Sec. 4 names the failure); crossing-3 123 -> 321 seeds 0-4: "
        "people correct with colour 6/15 -> 15/15 (docs/csa.md)",
        "a cluster short of sub-clusters splits with the targets started since it formed "
        "when all are pairwise separated (they take its remaining people)",
    )

    split_apart: bool = param(
        True,
        "extension of 002 (whose cluster splits only when all its people are apart; false "
        "restores 002); real demo bag ids 30 -> 23, walkers 26 -> 17; random-groups "
        "held-back 100-119 IDF1 0.449 -> 0.455, MOTA 0.502 -> 0.502 (tuning 0-19 0.500 -> "
        "0.497) (docs/csa.md)",
        "a person whose main sub-cluster (the one holding most of its Viterbi paths, and "
        "nobody else's) lies farther than separation_distance from every other sub-cluster "
        "of its cluster (002 condition 2 for that person alone) leaves the cluster as a "
        "single target with its identity",
    )
    coast_people: bool = param(
        True,
        "extension of 002 (whose VBA ends every path no measurement continues; false "
        "restores 002), as the KFA's single targets coast for max_unseen: real demo bag "
        "ids 23 -> 18, walkers 17 -> 15, ids moving from one walker to another inside a "
        "cluster 9 -> 4; random-groups held back 100-119 MOTA 0.502 -> 0.511, IDF1 0.455 "
        "-> 0.469; 002's crossings without colour 83 -> 81/135 (docs/csa.md)",
        "a person of a cluster none of whose Viterbi paths is continued by a measurement "
        "(its points were missed, or all went to other people's paths) keeps its paths, "
        "predicted, until it had continued paths max_unseen ago: its points, back, "
        "continue them, instead of another person's paths taking them over",
    )
    confirm_scans: int = param(
        2,
        "assumption (002 does not describe initiation); real demo bag ids 67 -> 32, "
        "corridor 15 -> 7; random-groups held-back 100-119 person MOTA 0.20 -> 0.27 "
        "(docs/csa.md)",
        "a target started from unselected points is reported once it had selected "
        "measurements in this many scans in a row (1: at once); fragments merging back "
        "or adopted by a person before then, and clutter seen now and then, are never "
        "reported",
    )
    moving_travel: float = param(
        0.5,
        "extension of 002 (a still laser's background explains the static world; 002 "
        "Sec. 3 does not track from a moving robot): on a moving laser with poses the "
        "leg detector fires on furniture the occupancy grid has not learned yet; as "
        "static_tracks.min_travel; random-groups moving-sensor scenes (docs/csa.md)",
        "in a world-frame run once the laser has moved from its first pose "
        "(tracking/robot_motion.py), a target started from unselected points (also one "
        "started while the laser still stood) is reported only once the mean of its "
        "selected measurements lay this far from where it started (0: at once, 002); a "
        "target on a person who walks does so within a second, furniture never",
        "m",
    )
    moving_wall: float = param(
        1.0,
        "extension of 002, as moving_travel: on a moving laser the leg detector fires on "
        "pieces of wall that move with the laser's view, and a target following them "
        "walks; random-groups moving-sensor tuning seeds (docs/csa.md; tried 1.2 m, and "
        "0.1 m for WALL_TOLERANCE)",
        "under moving_travel, a target's travel does not count while its own points (within "
        "0.35 m) lie on a straight line that the scan's points continue for this length "
        "within this distance of it (a wall; 0: travel always counts)",
        "m",
    )
    moving_window: float = param(
        3.0,
        "extension of 002, as moving_travel: a target held on a round piece of furniture "
        "(a torso-shaped run at torso height, [leg_foreground] torso_blobs) drifts with "
        "the view and the odometry, 0.9 m in 25 s on tuning seed 13, and walked "
        "moving_travel from where it started; a walker at 0.2 m/s covers 0.5 m in 3 s "
        "(docs/csa.md, 'Torso blobs on a moving laser')",
        "under moving_travel, the travel must be covered within this time: where a target "
        "is measured from moves to where it is once it is this old (0: from where it "
        "started, however long ago)",
        "s",
    )
    moving_adopt_near: float = param(
        0.5,
        "extension of 002, as moving_travel: on the moving tuning seeds people who had "
        "walked and were found again by a target started next to them waited to walk "
        "0.5 m once more; tried 0.5, 1 and 2 m (mean MOTA 0.272, 0.274, 0.259; 1 m reports "
        "furniture 0.95 m from a lost person; docs/csa.md, 'Torso blobs on a moving "
        "laser')",
        "under moving_travel, a person who walked keeps having walked when the target that "
        "continues it (adopt_orphans, adopt_escaped) was started within this distance of "
        "where the person was last estimated (0: the person takes the target's travel, "
        "whatever it was)",
        "m",
    )
    moving_people: bool = param(
        True,
        "extension of 002 (which prescribes neither its detector nor how targets start): "
        "random-groups moving-sensor tuning seeds person MOTA 0.255 -> 0.284, IDF1 0.326 "
        "-> 0.383; held back 100-119 0.457 -> 0.481 (docs/csa.md, 'The leg MHT's people as "
        "births and detections')",
        "in a world-frame run with poses and leg detections, once the laser has moved, new "
        "targets start where a person of the shipped leg MHT (000's people layer with the "
        "people's static world model, run on the frame's leg detections) is that no object "
        "of the CSA holds within 0.75 m, reported at once, instead of from unselected "
        "points; and a leg of such a person with no foreground point within 0.2 m is one "
        "more measurement point (tracking/csa_people.py)",
    )
    moving_unseen: float = param(
        0.3,
        "extension of 002, as moving_travel: on a moving laser with poses the points "
        "near leg detections flicker and a target coasting without them drifts off its "
        "person or sits on furniture; random-groups moving-sensor scenes (docs/csa.md)",
        "in a world-frame run once the laser has moved, a single target without selected "
        "measurements for longer than this is not reported (it is tracked on until "
        "max_unseen; 0: reported until deleted, 002)",
        "s",
    )
    cut_free: bool = param(
        True,
        "extension of 002 (whose VBA lets a cluster take every point inside a gate of its "
        "estimates, so people who walk up to a group become part of it and are never "
        "tracked); random-groups still-sensor scenes (docs/csa.md)",
        "a sub-cluster of a cluster (leader clustering at subcluster_distance) that holds "
        "no person's main paths (the sub-cluster with most of its paths), that no lost "
        "person of the cluster claims and whose estimates all lie farther than "
        "subcluster_distance from those of the main sub-clusters leaves the cluster: "
        "with at least min_points estimates as a new single target started next to the "
        "cluster, with fewer dropped",
    )
    count_people: bool = param(
        True,
        "extension of 002 (whose cluster holds only the people who merged into it as "
        "targets, so people who walk in together or walk up to a group are never "
        "counted); random-groups still-sensor scenes (docs/csa.md)",
        "a person-sized group (person_width) of at least count_points of a cluster's "
        "estimates that holds no person's main paths and lies farther than leg_gap from "
        "the main group of every person whose paths it holds, seen near the same place "
        "for count_seconds, becomes a new person of the cluster (its paths that person's)",
    )
    person_width: float = param(
        0.6,
        "assumption: two legs 0.1-0.5 m apart (or a torso) fit within 0.6 m; people "
        "standing side by side do not",
        "largest distance between two estimates of one person-sized group (complete "
        "linkage) when a cluster's people are counted (count_people)",
        "m",
    )
    leg_gap: float = param(
        0.5,
        "assumption: the two legs of one person are 0.1-0.5 m apart",
        "an unheld person-sized group whose centre lies within this of the main group of "
        "a person whose paths it holds may be that person's other leg and is not counted "
        "(count_people)",
        "m",
    )
    count_points: int = param(
        2,
        "assumption: a person 6 m from a 1 degree scanner returns two or three beams",
        "estimates an unheld person-sized group needs to be counted (count_people)",
    )
    count_seconds: float = param(
        1.0,
        "assumption: a walking person's legs come together within a step (0.5 s), so "
        "a leg seen apart does not stay a group of its own for a second",
        "how long an unheld person-sized group must be seen near the same place (within "
        "person_width) before it becomes a person of the cluster (count_people)",
        "s",
    )
    torso_count_seconds: float = param(
        0.3,
        "extension of 002, as count_people: at torso height a person is one blob, so a "
        "group apart is never a leg seen apart (the leg count_seconds waits out); "
        "random-groups tuning seeds 0-19 person MOTA 0.477 -> 0.487 (0.479 at 0.5 s), held "
        "back 100-119 0.481 -> 0.493, IDF1 0.445 -> 0.447 (docs/csa.md, 'Counting people "
        "sooner at torso height')",
        "count_seconds for a laser the recording states at torso height (0.7 m or higher; "
        "unknown or lower: count_seconds)",
        "s",
    )
    background_people: bool = param(
        True,
        "measured (docs/csa.md, 'The people of the learning period'): crossing-3 cli IDF1 "
        "at or above 0.95 on all six permutations of seed 7 (worst 0.83 without); "
        "random-groups person MOTA / IDF1 within noise of false (held back 100-119); "
        "false: 004's histogram (002 learns no background)",
        "with --background auto on still lasers: the ranges of the people a leg MHT "
        "confirms while the per-beam histogram learns are not learned as static, and the "
        "wall behind every leg detection is guessed from the beams beside them "
        "([leg_foreground] learn_people_warmup; [beam_histogram] "
        "people_share, people_settle_seconds)",
    )
    group_rows: bool = param(
        False,
        "002 Sec. 2 keeps every person's identity through a cluster (the Viterbi paths); "
        "the cluster itself is a tracker state, reported only when asked",
        "also report one group track per cluster (its people in members); the people of a "
        "cluster are always reported as person tracks",
    )
    member_coast: float = param(
        0.5,
        "assumption: a person inside a cluster whose Viterbi paths were all taken over by "
        "another's keeps walking as last estimated for about a step",
        "a member of a cluster without estimates of its own is reported at its last "
        "position moved by its last velocity for at most this long, then held",
        "s",
    )
    person_mixture: bool = param(
        True,
        "extension of 002 (whose VBA gives a point to the single best path; false "
        "restores 002): a person's paths multiply with its leg points, and a person with "
        "many paths has more chances that one of them fits another person's leg best, "
        "so one person's paths take over another's legs and the rows of a cluster's "
        "people change places; random-groups still-sensor scenes (docs/csa.md)",
        "a point of a cluster first picks its person: the one whose paths gating it "
        "explain it best, sum of exp(path score) over them divided by the square root of "
        "their number (person_first); then the best path of that person (the Viterbi "
        "recursion)",
    )

    adopt_orphans: bool = param(
        True,
        "extension of 002 (false restores 002); crossing-3 seed 7 (docs/csa.md)",
        "a person of a cluster none of whose Viterbi paths survive is the target started "
        "next to the cluster since it formed and nearest to where that person was last "
        "estimated (within separation_distance): that target takes the person's identity",
    )
    person_scores: bool = param(
        True,
        "extension of 002 (whose VBA compares the paths of a cluster by their whole "
        "log-likelihood; false restores 002): summed over many scans, one person's paths "
        "drift ahead of another's and take over their points, so the people of a cluster "
        "lose their identities (docs/csa.md)",
        "Viterbi path scores are compared over their whole history only between paths of "
        "the same person; between people only the last step's fit decides",
    )
    fragment_rule: bool = param(
        True,
        "extension of 002 (which has a cluster remember everyone who merged into it; "
        "false restores 002); docs/papers.md 'Cluster Sorting'",
        "a target started beside a cluster (within init_distance + max_gate_distance of "
        "one of its estimates) that merges back into that cluster is taken for a fragment "
        "of the cluster's people (a leg seen apart), not another person: it is not added "
        "to the cluster's members",
    )

    def __post_init__(self) -> None:
        if not 0.0 < self.gate_probability < 1.0:
            raise ValueError("gate_probability must be in (0, 1)")
        for name in (
            "subcluster_distance",
            "separation_distance",
            "max_gate_distance",
            "point_std",
            "mean_std",
            "person_accel_psd",
            "point_accel_psd",
            "init_velocity_std",
            "init_distance",
            "max_unseen",
            "max_dt",
            "member_coast",
            "person_width",
            "leg_gap",
        ):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive")
        for name in ("count_seconds", "torso_count_seconds"):
            if not 0.0 <= getattr(self, name) < math.inf:
                raise ValueError(f"{name} must be finite and not negative")
        if self.fragment_age < 0:
            raise ValueError("fragment_age must not be negative")
        if self.min_points < 1 or self.count_points < 1:
            raise ValueError("min_points and count_points must be at least 1")
        if self.confirm_scans < 1:
            raise ValueError("confirm_scans must be at least 1")
        for name in ("moving_travel", "moving_unseen", "moving_wall", "lost_keep"):
            if not 0.0 <= getattr(self, name) < math.inf:
                raise ValueError(f"{name} must be finite and not negative")

    @property
    def gate(self) -> float:
        """Squared Mahalanobis radius of a validation gate: the chi-square quantile with 2
        degrees of freedom, -2 ln(1 - p)."""
        return -2.0 * math.log1p(-self.gate_probability)


@dataclass(frozen=True, eq=False)
class ViterbiStep:
    """The result of one VBA step (:func:`viterbi_step`) on M measurements and E estimates.

    Attributes:
        selected: (M,) bool, measurements inside at least one estimate's gate.
        predecessor: (S,) index of the old estimate each selected measurement continues.
        means: New estimates (S, 4), the predecessors updated with their measurements.
        covs: Their covariances (S, 4, 4).
        scores: Path log-likelihoods (S,), shifted so that the best is 0.
    """

    selected: NDArray[np.bool_]
    predecessor: IntArray
    means: FloatArray
    covs: FloatArray
    scores: FloatArray


def _gate_loglik(
    means: FloatArray, covs: FloatArray, z: FloatArray, point_var: float, gate: float, cap: float
) -> tuple[NDArray[np.bool_], FloatArray]:
    """Gate membership and log N(z_m; H x_e, H P_e H^T + point_var I), both (E, M), for
    one measurement noise shared by all measurements (cheaper than
    :func:`kalman.mahalanobis_and_loglik`, which takes one covariance per measurement)."""
    a = covs[:, 0, 0] + point_var
    b = covs[:, 0, 1]
    d = covs[:, 1, 1] + point_var
    det = a * d - b * b
    vx = z[None, :, 0] - means[:, 0, None]
    vy = z[None, :, 1] - means[:, 1, None]
    d2 = (d[:, None] * vx * vx - 2.0 * b[:, None] * vx * vy + a[:, None] * vy * vy) / det[:, None]
    inside = (d2 <= gate) & (vx * vx + vy * vy <= cap * cap)
    loglik = -0.5 * d2 - kalman.LOG_2PI - 0.5 * np.log(det)[:, None]
    return inside, loglik


def viterbi_step(
    pred_means: FloatArray,
    pred_covs: FloatArray,
    scores: FloatArray,
    z: FloatArray,
    point_var: float,
    gate: float,
    max_gate_distance: float,
    origin: IntArray | None = None,
) -> ViterbiStep:
    """One step of the Viterbi-based algorithm (002 Sec. 2; Kräußling et al. 2004a).

    Every old estimate e (predicted to ``pred_means[e]``) has a validation gate; a
    measurement in at least one gate is selected, and its new estimate continues the old
    estimate with the best path score ``scores[e] + log N(z; H x_e, H P_e H^T + R)`` among
    the estimates gating it (the Viterbi recursion), updated with the measurement.

    Args:
        pred_means: Predicted estimates (E, 4).
        pred_covs: Their covariances (E, 4, 4).
        scores: Path log-likelihoods of the old estimates (E,).
        z: Measurements (M, 2) [m].
        point_var: Variance of one measurement about the estimate, R = point_var * I [m^2].
        gate: Squared Mahalanobis radius of a gate.
        max_gate_distance: Euclidean cap on a gate [m].
        origin: The person (E,) each estimate's path started from, or None (002). With
            it, a measurement first picks its person (:func:`person_first`), then the
            best of that person's estimates (``person_mixture``).
    """
    z = np.asarray(z, dtype=np.float64).reshape(-1, 2)
    m = z.shape[0]
    r = np.broadcast_to(np.eye(2) * point_var, (m, 2, 2))
    inside, loglik = _gate_loglik(pred_means, pred_covs, z, point_var, gate, max_gate_distance)
    selected: NDArray[np.bool_] = np.asarray(inside.any(axis=0), dtype=bool)
    total = np.where(inside, np.asarray(scores, dtype=np.float64)[:, None] + loglik, -np.inf)
    total = total[:, selected]
    if origin is not None and total.size:
        total = person_first(total, origin)
    pred = np.argmax(total, axis=0).astype(np.int64)
    best = total[pred, np.arange(pred.size)]
    zs = z[selected]
    means, covs = kalman.update_batch(pred_means[pred], pred_covs[pred], zs, r[: zs.shape[0]])
    if best.size:
        best = best - best.max()
    return ViterbiStep(selected, pred, means, covs, best)


def person_first(total: FloatArray, origin: IntArray) -> FloatArray:
    """Path scores ``total`` (E, S) of E old estimates for S measurements (path score plus
    transition log-likelihood, -inf outside a gate) with every estimate that is not of the
    measurement's person set to -inf (see ``person_mixture``).

    A measurement's person is argmax over people p of sum(exp(total[e])) / sqrt(n_p) over
    the n_p paths e of p that gate it: a person with many paths (one per leg point) gets
    no more chances to take a point than one with few (the sum alone), yet a person whose
    two legs both gate a point is not diluted by its other leg (the mean). ``origin`` (E,)
    gives the person each path started from."""
    _, inv = np.unique(origin, return_inverse=True)
    n_people = int(inv.max()) + 1
    w = np.exp(total - np.max(total, axis=0, keepdims=True))  # (E, S); 0 outside gates
    mix = np.zeros((n_people, total.shape[1]))
    cnt = np.zeros_like(mix)
    np.add.at(mix, inv, w)
    np.add.at(cnt, inv, np.isfinite(total).astype(np.float64))
    best = np.argmax(mix / np.sqrt(np.maximum(cnt, 1.0)), axis=0)  # (S,) each one's person
    return np.where(inv[:, None] == best[None, :], total, -np.inf)


def leader_clusters(positions: FloatArray, distance: float) -> IntArray:
    """Sub-cluster label (N,) of each position (N, 2) by 002's procedure: the first
    unassigned position opens a sub-cluster, every unassigned position closer than
    ``distance`` to it joins; repeat until all are assigned."""
    pts = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    labels = np.full(pts.shape[0], -1, dtype=np.int64)
    k = 0
    while True:
        free = np.flatnonzero(labels < 0)
        if free.size == 0:
            return labels
        first = pts[free[0]]
        near = np.linalg.norm(pts[free] - first, axis=1) < distance
        labels[free[near]] = k
        k += 1


def split_ready(
    positions: FloatArray, n_people: int, params: CSAParams, labels: IntArray | None = None
) -> tuple[bool, IntArray]:
    """002's split conditions 1 and 2 for a cluster of ``n_people`` with estimates at
    ``positions`` (E, 2); returns (split?, sub-cluster label per estimate). ``labels``:
    the estimates' sub-clusters when already computed (:func:`leader_clusters` at
    ``subcluster_distance``)."""
    if labels is None:
        labels = leader_clusters(positions, params.subcluster_distance)
    n_sub = int(labels.max()) + 1 if labels.size else 0
    if n_sub != n_people:
        return False, labels
    centroids = np.array([positions[labels == s].mean(axis=0) for s in range(n_sub)])
    d = np.linalg.norm(centroids[:, None] - centroids[None], axis=-1)
    iu = np.triu_indices(n_sub, 1)
    separated = int((d[iu] > params.separation_distance).sum())
    return separated == n_sub * (n_sub - 1) // 2, labels


@dataclass
class _Single:
    pid: int
    mean: FloatArray
    cov: FloatArray
    last_seen: float
    spawned_by: int = -1  # the cluster it was started next to (a fragment of its people?)
    born: float = -math.inf  # when it was started from unselected points
    hits: int = 0  # scans in a row with selected measurements (see confirm_scans)


@dataclass
class _Cluster:
    cid: int
    members: tuple[int, ...]
    means: FloatArray
    covs: FloatArray
    scores: FloatArray
    origin: IntArray  # person each estimate's Viterbi path started from
    last_seen: float
    shown: dict[int, FloatArray] = field(default_factory=dict)  # person -> last shown at
    motion: dict[int, tuple[FloatArray, float]] = field(default_factory=dict)  # velocity, stamp
    born_pid: int = 0  # single targets with a larger id were started after this cluster
    labels: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    """Sub-cluster of each estimate (leader clustering at subcluster_distance), computed
    once per scan in :meth:`ClusterSortingTracker.update`, after the VBA step."""
    uncounted: list[tuple[FloatArray, float]] = field(default_factory=list)
    """Where (2,) [m] and since when [s] the cluster shows a person-sized group nobody
    holds (count_people)."""
    continued: dict[int, float] = field(default_factory=dict)
    """Person -> when [s] a measurement last continued one of its Viterbi paths
    (coast_people)."""


@dataclass(frozen=True)
class CSAEvent:
    """A merge or split, for inspection and tests.

    Attributes:
        stamp: Time [s].
        kind: "merge person+person", "merge person+cluster", "merge cluster+cluster",
            "split", "split apart" (``members``: the people who left), "adopt orphan" or
            "count people" (``members``: the people added).
        members: The people of the cluster after a merge / before a split.
    """

    stamp: float
    kind: str
    members: tuple[int, ...]


@dataclass
class _State:
    singles: dict[int, _Single] = field(default_factory=dict)
    clusters: dict[int, _Cluster] = field(default_factory=dict)
    next_pid: int = 0
    next_cid: int = 0


class ClusterSortingTracker:
    """The CSA as a :class:`~laserpeople.frame.FrameTracker` on raw foreground points.

    Attributes:
        events: Every merge and split so far (:class:`CSAEvent`).
    """

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})
    wants_torso_runs = True
    """At torso height its foreground keeps torso-shaped runs too (``[leg_foreground]
    torso_blobs``, :func:`~laserpeople.pipeline.leg_foreground.wants_torso_runs`)."""

    def __init__(self, params: CSAParams | None = None) -> None:
        self.params = params or CSAParams()
        self.learns_behind_people = self.params.background_people
        """Whether the pipeline's per-beam histogram leaves out the people standing while
        it learns (:func:`~laserpeople.pipeline.leg_foreground.learns_behind_people`)."""
        self._s = _State()
        self._last: float | None = None
        self.events: list[CSAEvent] = []
        self._motion = MotionWatch()
        self._moving = False
        """Whether the laser of this world-frame run has moved (see ``moving_travel``)."""
        self._posed = False
        """Whether this is a world-frame run with the laser's poses (see ``moving_travel``)."""
        self._scan_points = np.empty((0, 2))
        self._unwalked: dict[int, tuple[FloatArray, float]] = {}
        """Person -> where (2,) [m] and when [s] its travel is measured from (where it was
        started, moved on every ``moving_window``), while it has not walked
        ``moving_travel`` from there (world-frame runs with poses)."""
        self._stamp = 0.0
        self._people: LegPeople | None = LegPeople() if self.params.moving_people else None
        """The leg MHT's people (``moving_people``), run on the frames with poses and legs
        once the laser has moved (before, only their last seconds are held)."""
        if self._people is not None:
            self.consumes = self.consumes | {"legs"}
        self.at_torso_height = False
        """Whether the recording states the laser at torso height
        (:meth:`use_torso_height`): people are counted into clusters after
        ``torso_count_seconds`` instead of ``count_seconds``."""

    def use_people_static_model(self, model: StaticWorldModel | None) -> None:
        """The static world model the leg MHT's people of ``moving_people`` ask (the
        pipeline feeds it each frame; None: none). Nothing to do without the setting."""
        if self._people is not None:
            self._people.use_static_model(model)

    def use_torso_height(self, torso: bool) -> None:
        """Whether the recording states the laser at torso height (the pipeline tells it,
        :func:`~laserpeople.pipeline.background.set_laser_height`)."""
        self.at_torso_height = torso

    # ------------------------------------------------------------------ helpers
    def _new_single(self, pos: FloatArray, stamp: float) -> None:
        p = self.params
        pid = self._s.next_pid
        self._s.next_pid += 1
        spawned_by = -1
        reach = p.init_distance + p.max_gate_distance
        for c in self._s.clusters.values():
            if np.min(np.linalg.norm(c.means[:, :2] - pos, axis=1)) < reach:
                spawned_by = c.cid
                break
        self._s.singles[pid] = _Single(
            pid, np.r_[pos, 0.0, 0.0], self._init_cov(), stamp, spawned_by, stamp, 1
        )
        self._started(pid, pos)

    def _init_cov(self) -> FloatArray:
        """Covariance (4, 4) of a new single target."""
        p = self.params
        v = p.init_velocity_std**2
        return np.diag([p.mean_std**2, p.mean_std**2, v, v])

    def _points(self, frame: Frame) -> FloatArray:
        if frame.points is None or frame.foreground is None:
            from laserpeople.errors import LaserPeopleError

            raise LaserPeopleError(
                "the CSA needs the frame's points and foreground mask",
                scan=frame.index,
                hint="run the preprocess stage before the csa tracker",
            )
        return frame.points.points[np.asarray(frame.foreground, dtype=bool)]

    # ------------------------------------------------------------------ update
    def update(self, frame: Frame) -> Tracks:
        """Process one frame's foreground points; return the tracks after it."""
        p = self.params
        z = self._points(frame)
        assert frame.points is not None
        self._scan_points = np.asarray(frame.points.points, dtype=np.float64)
        stamp = frame.stamp
        self._stamp = float(stamp)
        if frame.frame == "world":
            self._moving = self._motion(frame.sensor_pose)
            self._posed = frame.sensor_pose is not None
        world = self._posed and frame.frame == "world" and frame.legs is not None
        people = self._people if world else None
        if people is not None and not self._moving:
            people.hold(frame)  # nothing of it is used before the laser moves
        elif people is not None:
            people.update(frame)
            # the legs the leg MHT holds and the foreground lacks
            z = np.vstack([z, missed_legs(z, people.legs)])
        dt = 0.0 if self._last is None else min(max(stamp - self._last, 0.0), p.max_dt)
        self._last = stamp
        point_var = p.point_std**2
        gate2 = p.gate
        s = self._s

        singles = list(s.singles.values())
        clusters = list(s.clusters.values())
        # predict every single target and every cluster estimate
        if singles:
            sm, sc = kalman.predict(
                np.array([t.mean for t in singles]),
                np.array([t.cov for t in singles]),
                np.full(len(singles), dt),
                p.person_accel_psd,
            )
        else:
            sm, sc = np.empty((0, 4)), np.empty((0, 4, 4))
        cpred = [
            kalman.predict(c.means, c.covs, np.full(len(c.means), dt), p.point_accel_psd)
            for c in clusters
        ]
        # validation gates of every object over the measurements
        cap = p.max_gate_distance
        gates = np.zeros((len(singles) + len(clusters), z.shape[0]), dtype=bool)
        if singles and z.size:
            gates[: len(singles)] = _gate_loglik(sm, sc, z, point_var, gate2, cap)[0]
        for k, (cm, cc) in enumerate(cpred):
            if z.size and cm.size:
                g = _gate_loglik(cm, cc, z, point_var, gate2, cap)[0]
                gates[len(singles) + k] = g.any(axis=0)
        comps = gate_components(gates)
        selected_any = gates.any(axis=0)

        new_singles: dict[int, _Single] = {}
        new_clusters: dict[int, _Cluster] = {}
        for comp in comps:
            objs_s = [i for i in comp if i < len(singles)]
            if len(comp) == 1 and objs_s:
                i = objs_s[0]
                t = singles[i]
                sel = gates[i]
                if sel.any():  # KFA: the mean of the selected measurements
                    centre = z[sel].mean(axis=0)
                    mean, cov = kalman.update(sm[i], sc[i], centre, np.eye(2) * p.mean_std**2)
                    new_singles[t.pid] = _Single(
                        t.pid,
                        mean,
                        cov,
                        stamp,
                        t.spawned_by,
                        t.born,
                        t.hits + 1,
                    )
                    self._walked(t.pid, centre)
                elif stamp - t.last_seen <= p.max_unseen + p.lost_keep:
                    # a miss before confirmation starts the count again
                    hits = t.hits if t.hits >= p.confirm_scans else 0
                    new_singles[t.pid] = _Single(
                        t.pid, sm[i], sc[i], t.last_seen, t.spawned_by, t.born, hits
                    )
                continue
            cl = self._vba(comp, singles, sm, sc, clusters, cpred, z, stamp, point_var)
            if cl is None:
                continue
            cl.labels = leader_clusters(cl.means[:, :2], p.subcluster_distance)
            if p.adopt_orphans:
                self._orphans_claim(cl)
            if p.cut_free:
                self._cut_free(cl, stamp, new_singles)
            if p.count_people:
                self._count_people(cl, stamp)
            done = self._maybe_split(cl, stamp, new_singles)
            if not done and p.split_apart:
                done = self._split_apart(cl, stamp, new_singles)
            if not done:
                new_clusters[cl.cid] = cl
        if p.adopt_orphans:
            self._adopt_orphans(new_singles, new_clusters, stamp)
        if p.adopt_escaped:
            self._adopt_escaped(new_singles, new_clusters, stamp)
        s.singles = new_singles
        s.clusters = new_clusters
        if self._unwalked:  # forget the people deleted
            alive = set(new_singles).union(*(c.members for c in new_clusters.values()))
            self._unwalked = {k: v for k, v in self._unwalked.items() if k in alive}
        if people is not None and self._moving:
            self._people_births(people.people, stamp)
        else:
            self._initiate(z[~selected_any], stamp)
        return self._report(frame)

    def _people_births(self, people: FloatArray, stamp: float) -> None:
        """``moving_people``: a single target for each of the leg MHT's ``people`` (P, 2)
        [m] that no object holds (:func:`~laserpeople.tracking.csa_people.unheld_people`),
        reported at once (the MHT confirmed it, on a place not static for long)."""
        s = self._s
        objects = [t.mean[:2] for t in s.singles.values()]
        objects += [c.means[:, :2] for c in s.clusters.values()]
        held = np.vstack(objects) if objects else np.empty((0, 2))
        for xy in unheld_people(people, held):
            pid = s.next_pid
            self._new_single(xy, stamp)
            self._unwalked.pop(pid, None)
            s.singles[pid].hits = self.params.confirm_scans

    def _confirmed(self, t: _Single) -> bool:
        """Whether single target ``t`` is reported (see ``confirm_scans``)."""
        if not self._shown_walker(t.pid):
            return False
        return t.born == -math.inf or t.hits >= self.params.confirm_scans

    def _started(self, pid: int, xy: FloatArray) -> None:
        """Remember where person ``pid`` was started at (2,) [m] in a world-frame run with
        poses, until it walked ``moving_travel`` from there (see :meth:`_walked`)."""
        if self._posed and self.params.moving_travel > 0:
            self._unwalked[pid] = (np.array(xy, dtype=np.float64), self._stamp)

    def _walked(self, pid: int, xy: FloatArray) -> None:
        """Person ``pid`` was seen at ``xy`` (2,) [m]: once that lies ``moving_travel``
        from where it was started (or, after ``moving_window``, from where it was then),
        it has walked, for good."""
        held = self._unwalked.get(pid)
        if held is None:
            return
        start, since = held
        if float(np.hypot(*(xy - start))) < self.params.moving_travel:
            window = self.params.moving_window
            if window > 0 and self._stamp - since >= window:  # too slow: measure anew
                self._unwalked[pid] = (np.array(xy, dtype=np.float64), self._stamp)
            return
        wall = self.params.moving_wall
        if wall > 0 and on_a_wall(xy, self._scan_points, wall):
            return  # sliding along a wall as the laser's view moves
        del self._unwalked[pid]

    def _adopted(self, target: int, person: int, last: FloatArray | None = None) -> None:
        """Person ``person``, last estimated at ``last`` (2,) [m] (None: unknown), is
        continued by the single target ``target`` (adopt_orphans, adopt_escaped): when that
        target has not walked ``moving_travel``, neither has the person, from where the
        target was started. On a moving laser new targets start on furniture all over the
        scene; one that took a walked person's identity was reported at once, wherever it
        stood. A target started within ``moving_adopt_near`` of where a person who walked
        was last estimated is that person found again: it keeps having walked."""
        start = self._unwalked.pop(target, None)
        if start is None:
            return
        near = self.params.moving_adopt_near
        gap = math.inf if last is None else float(np.hypot(*(start[0] - last)))
        if person not in self._unwalked and near > 0 and gap <= near:
            return  # the person found again next to where it was lost
        self._unwalked[person] = start

    def _shown_walker(self, pid: int) -> bool:
        """Whether person ``pid`` may be reported under ``moving_travel``: the laser has not
        moved, or the person walked since it was started from unselected points (as a
        single target, a person of a cluster, or a target split from one)."""
        return not (self._moving and pid in self._unwalked)

    def _shown_unseen(self, t: _Single, stamp: float) -> bool:
        """Whether single target ``t``, unseen since ``t.last_seen``, is still reported at
        ``stamp`` [s] (see ``moving_unseen``; never once unseen for ``max_unseen``, while
        ``lost_keep`` keeps it)."""
        limit = self.params.moving_unseen
        if stamp - t.last_seen > self.params.max_unseen:
            return False
        return not (self._moving and limit > 0 and stamp - t.last_seen > limit)

    def _vba(
        self,
        comp: list[int],
        singles: list[_Single],
        sm: FloatArray,
        sc: FloatArray,
        clusters: list[_Cluster],
        cpred: list[tuple[FloatArray, FloatArray]],
        z: FloatArray,
        stamp: float,
        point_var: float,
    ) -> _Cluster | None:
        """Run the VBA on a cluster, merging the objects of ``comp`` first."""
        p = self.params
        ns = len(singles)
        objs_s = [i for i in comp if i < ns]
        objs_c = [i - ns for i in comp if i >= ns]
        means = [sm[objs_s]] + [cpred[k][0] for k in objs_c]
        covs = [sc[objs_s]] + [cpred[k][1] for k in objs_c]
        scores = [np.zeros(len(objs_s))] + [
            clusters[k].scores - clusters[k].scores.max() for k in objs_c
        ]
        origin = [np.array([singles[i].pid for i in objs_s], dtype=np.int64)] + [
            clusters[k].origin for k in objs_c
        ]
        # with the fragment rule (extension of 002), a target started next to one of
        # these clusters and merging back into it is a fragment of the cluster's people
        cids = {clusters[k].cid for k in objs_c} if p.fragment_rule else set()
        joining = {singles[i].pid for i in objs_s if singles[i].spawned_by not in cids}
        if p.fragment_rule:
            # a target younger than fragment_age is not yet a person: merging, it is a
            # fragment of the others (of the oldest of the young, when all are young)
            young = {singles[i].pid for i in objs_s if stamp - singles[i].born < p.fragment_age}
            older = (joining - young) | {m for k in objs_c for m in clusters[k].members}
            joining -= young
            if not older and young:
                joining = {min(young)}
        members = tuple(sorted(joining.union(*[clusters[k].members for k in objs_c])))
        last_seen = max(
            [singles[i].last_seen for i in objs_s] + [clusters[k].last_seen for k in objs_c]
        )
        if len(comp) > 1:
            kind = (
                "merge person+person"
                if not objs_c
                else "merge cluster+cluster"
                if len(objs_c) > 1
                else "merge person+cluster"
            )
            self.events.append(CSAEvent(stamp, kind, members))
        shown = {singles[i].pid: sm[i, :2] for i in objs_s}
        motion = {singles[i].pid: (sm[i, 2:], stamp) for i in objs_s}
        continued = {singles[i].pid: singles[i].last_seen for i in objs_s}
        for k in objs_c:
            shown.update(clusters[k].shown)
            motion.update(clusters[k].motion)
            continued.update(clusters[k].continued)
        born = min([clusters[k].born_pid for k in objs_c], default=self._s.next_pid)
        since = [u for k in objs_c for u in clusters[k].uncounted]
        if objs_c:
            cid = clusters[objs_c[0]].cid
        else:
            cid = self._s.next_cid
            self._s.next_cid += 1
        all_means = np.concatenate(means)
        all_covs = np.concatenate(covs)
        all_scores = np.concatenate(scores)
        all_origin = _fragment_origins(np.concatenate(origin), members, shown)
        if p.person_scores:
            all_scores = per_person_scores(all_scores, all_origin)
        step = viterbi_step(
            all_means,
            all_covs,
            all_scores,
            z,
            point_var,
            p.gate,
            p.max_gate_distance,
            all_origin if p.person_mixture else None,
        )
        if step.predecessor.size == 0:  # nothing seen: coast every estimate
            if stamp - last_seen > p.max_unseen + p.lost_keep:
                return None
            return _Cluster(
                cid,
                members,
                all_means,
                all_covs,
                all_scores,
                all_origin,
                last_seen,
                shown,
                motion,
                born,
                uncounted=since,
                continued=continued,
            )
        kept: Estimates = (step.means, step.covs, step.scores, all_origin[step.predecessor])
        if p.coast_people:
            kept = coast_people(
                kept,
                (all_means, all_covs, all_scores, all_origin),
                continued,
                (stamp, last_seen),
                p.max_unseen,
            )
        return _Cluster(
            cid,
            members,
            *kept,
            stamp,
            shown,
            motion,
            born,
            uncounted=since,
            continued=continued,
        )

    def _maybe_split(self, cl: _Cluster, stamp: float, out: dict[int, _Single]) -> bool:
        """Split ``cl`` into single targets when 002's conditions 1 and 2 hold."""
        ok, labels = split_ready(cl.means[:, :2], len(cl.members), self.params, cl.labels)
        if not ok:
            return False
        ids = self._subcluster_ids(cl, labels)
        for sub, pid in enumerate(ids):
            sel = labels == sub
            out[pid] = _Single(pid, cl.means[sel].mean(axis=0), self._init_cov(), stamp)
        self.events.append(CSAEvent(stamp, "split", cl.members))
        return True

    def _split_apart(self, cl: _Cluster, stamp: float, out: dict[int, _Single]) -> bool:
        """Let every person of ``cl`` that is apart leave it (``split_apart``): its main
        sub-cluster (``cl.labels``) holds no other person's main paths and its centroid
        lies farther than ``separation_distance`` from every other sub-cluster's centroid
        (002 condition 2 for that person alone). Its estimates become the single target
        written to ``out`` with its identity (at their mean, as 002's split starts its
        targets), the others stay; when every sub-cluster is apart, nobody leaves (002's
        split, or ``adopt_escaped`` for a cluster short of sub-clusters, decides). Returns
        True when the cluster is left with one person and became a single target itself
        (the cluster is gone), else False."""
        p = self.params
        labels = cl.labels
        n_sub = int(labels.max()) + 1 if labels.size else 0
        if n_sub < 2:
            return False
        cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in range(n_sub)])
        d = np.linalg.norm(cents[:, None] - cents[None], axis=-1)
        np.fill_diagonal(d, np.inf)
        mains: dict[int, list[int]] = {}
        for m in cl.members:
            own = cl.origin == m
            if own.any():
                k = int(np.argmax(np.bincount(labels[own], minlength=n_sub)))
                mains.setdefault(k, []).append(m)
        leaving = [
            (k, ms[0])
            for k, ms in mains.items()
            if len(ms) == 1 and d[k].min() > p.separation_distance
        ]
        if not leaving or len(leaving) == n_sub:  # all apart: 002's split (or none) decides
            return False
        keep = np.ones(labels.size, dtype=bool)
        for k, m in leaving:
            sel = labels == k
            keep &= ~sel
            out[m] = _Single(m, cl.means[sel].mean(axis=0), self._init_cov(), cl.last_seen)
        gone = tuple(m for _, m in leaving)
        self.events.append(CSAEvent(stamp, "split apart", gone))
        cl.members = tuple(m for m in cl.members if m not in gone)
        cl.means, cl.covs, cl.scores = cl.means[keep], cl.covs[keep], cl.scores[keep]
        cl.origin = cl.origin[keep]
        cl.labels = leader_clusters(cl.means[:, :2], p.subcluster_distance)
        if len(cl.members) != 1:
            return False
        m = cl.members[0]
        out[m] = _Single(m, cl.means.mean(axis=0), self._init_cov(), cl.last_seen)
        return True

    @staticmethod
    def _subcluster_ids(cl: _Cluster, labels: IntArray) -> list[int]:
        """The person for each sub-cluster (see :meth:`_assign_members`)."""
        n_sub = int(labels.max()) + 1
        cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in range(n_sub)])
        return ClusterSortingTracker._assign_members(cl, cents, labels)

    @staticmethod
    def _assign_members(cl: _Cluster, positions: FloatArray, labels: IntArray) -> list[int]:
        """The person for each of K positions (K, 2) of a cluster, one-to-one by the
        Hungarian algorithm: nearest to where each person was last shown (as a single target
        or a sub-cluster of this cluster), or, when some person was never shown, the one
        most estimates' Viterbi paths started from (``labels`` (E,) gives each estimate's
        position, -1 for none). An extension of 002, which leaves identities after a split
        to colour."""
        n = len(cl.members)
        k = positions.shape[0]
        if all(m in cl.shown for m in cl.members):
            prev = np.array([cl.shown[m] for m in cl.members])
            cost = np.linalg.norm(positions[:, None] - prev[None], axis=-1)
        else:
            index = {m: c for c, m in enumerate(cl.members)}
            cost = np.zeros((k, n))
            for lab, org in zip(labels, cl.origin, strict=True):
                if lab >= 0 and int(org) in index:
                    cost[lab, index[int(org)]] -= 1.0
        rows, cols = linear_sum_assignment(cost)
        ids = [-1] * k
        for r_, c_ in zip(rows, cols, strict=True):
            ids[int(r_)] = cl.members[int(c_)]
        return ids

    def _adopt_escaped(
        self, singles: dict[int, _Single], clusters: dict[int, _Cluster], stamp: float
    ) -> None:
        """Extension of 002 (its Sec. 4 names the failure: a person who walks away in the
        shadow of the others is lost by the VBA and found again as a new target). When a
        cluster shows k sub-clusters fewer than it holds people and exactly k targets were
        started since it formed, the sub-clusters and those targets are its people: if
        they are all pairwise separated (002 condition 2) the cluster splits, and the new
        targets take the remaining identities."""
        p = self.params
        in_clusters = {m for c in clusters.values() for m in c.members}
        for cl in list(clusters.values()):
            labels = cl.labels
            n_sub = int(labels.max()) + 1
            missing = len(cl.members) - n_sub
            if missing <= 0:
                continue
            new = [t for t in singles.values() if t.pid >= cl.born_pid and t.pid not in in_clusters]
            if len(new) != missing:
                continue
            cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in range(n_sub)])
            pos = np.concatenate([cents, np.array([t.mean[:2] for t in new])])
            d = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
            if not (d[np.triu_indices(len(pos), 1)] > p.separation_distance).all():
                continue
            ids = self._assign_members(cl, pos, labels)
            for sub in range(n_sub):
                mean = cl.means[labels == sub].mean(axis=0)
                singles[ids[sub]] = _Single(ids[sub], mean, self._init_cov(), stamp)
            for t, pid in zip(new, ids[n_sub:], strict=True):
                del singles[t.pid]
                singles[pid] = _Single(pid, t.mean, t.cov, t.last_seen)
                self._adopted(t.pid, pid, cl.shown.get(pid))
            del clusters[cl.cid]
            self.events.append(CSAEvent(stamp, "split", cl.members))

    @staticmethod
    def _main_subclusters(cl: _Cluster) -> set[int]:
        """The sub-clusters of ``cl`` (``cl.labels``) that hold most of some person's
        Viterbi paths (each person's *main* sub-cluster)."""
        n_sub = int(cl.labels.max()) + 1
        return {
            int(np.argmax(np.bincount(cl.labels[cl.origin == m], minlength=n_sub)))
            for m in {int(o) for o in cl.origin}
        }

    def _cut_free(self, cl: _Cluster, stamp: float, out: dict[int, _Single]) -> None:
        """Cut off every sub-cluster of ``cl`` (leader clustering at
        ``subcluster_distance``) that holds none of its people's main paths and lies
        farther than ``subcluster_distance`` from every estimate of the sub-clusters that
        do (a person's legs are never that far apart): with at least ``min_points``
        estimates it becomes a new single target started next to the cluster, at the mean
        of those estimates, written to ``out``; fewer are dropped (see ``cut_free``).
        Called after the orphans' claim, so a person of the cluster who lost its paths
        takes such a sub-cluster first."""
        p = self.params
        if cl.labels.size == 0:
            return
        main = self._main_subclusters(cl)
        n_sub = int(cl.labels.max()) + 1
        held = cl.means[np.isin(cl.labels, list(main)), :2]
        keep = np.ones(cl.labels.size, dtype=bool)
        for k in range(n_sub):
            sel = cl.labels == k
            if k in main:
                continue
            gap = np.linalg.norm(cl.means[sel, None, :2] - held[None], axis=-1).min()
            if gap <= p.subcluster_distance:  # leader clustering cut a person's legs apart
                continue
            keep &= ~sel
            if int(sel.sum()) < p.min_points:  # too few to start a target: dropped
                continue
            pid = self._s.next_pid
            self._s.next_pid += 1
            mean = cl.means[sel].mean(axis=0)
            out[pid] = _Single(pid, mean, self._init_cov(), stamp, cl.cid, stamp, 1)
        if keep.all():
            return
        cl.means, cl.covs, cl.scores = cl.means[keep], cl.covs[keep], cl.scores[keep]
        cl.origin = cl.origin[keep]
        cl.labels = leader_clusters(cl.means[:, :2], p.subcluster_distance)

    def _count_people(self, cl: _Cluster, stamp: float) -> None:
        """Give ``cl`` a new person for every person-sized group of its estimates
        (:func:`person_groups` at ``person_width``) with at least ``count_points``
        estimates that holds no person's main paths (the group holding most of them) and
        whose centre lies farther than ``leg_gap`` from the main group of every person
        whose paths it holds (so it is not that person's other leg), once a group
        so was seen within ``person_width`` of the same place for ``count_seconds``
        (``torso_count_seconds`` at torso height; see ``count_people``): the group's paths
        continue as the new person's."""
        p = self.params
        wait = p.torso_count_seconds if self.at_torso_height else p.count_seconds
        if cl.means.shape[0] < p.count_points:
            cl.uncounted = []
            return
        xy = cl.means[:, :2]
        groups = person_groups(xy, p.person_width)
        n_groups = int(groups.max()) + 1
        cents = np.array([xy[groups == g].mean(axis=0) for g in range(n_groups)])
        main = {
            m: int(np.argmax(np.bincount(groups[cl.origin == m], minlength=n_groups)))
            for m in {int(o) for o in cl.origin}
        }
        sizes = np.bincount(groups, minlength=n_groups)
        seen: list[tuple[FloatArray, float]] = []
        added = []
        origin = cl.origin.copy()
        for g in range(n_groups):
            if sizes[g] < p.count_points:
                continue
            owners = {int(o) for o in cl.origin[groups == g]}
            gap = min(float(np.hypot(*(cents[g] - cents[main[m]]))) for m in owners)
            # (a person's own main group lies at 0: never counted)
            if gap <= p.leg_gap:  # may be an owner's other leg
                continue
            since = min(
                (t for c, t in cl.uncounted if np.hypot(*(c - cents[g])) <= p.person_width),
                default=stamp,
            )
            if stamp - since < wait:
                seen.append((cents[g], since))
                continue
            pid = self._s.next_pid
            self._s.next_pid += 1
            sel = groups == g
            origin[sel] = pid
            cl.shown[pid] = cents[g]
            cl.motion[pid] = (cl.means[sel, 2:].mean(axis=0), stamp)
            added.append(pid)
        cl.uncounted = seen
        if added:
            cl.origin = origin
            cl.members = tuple(sorted((*cl.members, *added)))
            self.events.append(CSAEvent(stamp, "count people", tuple(added)))

    def _orphans_claim(self, cl: _Cluster) -> None:
        """Orphans of cluster ``cl`` (people none of whose Viterbi paths survive) take the
        sub-clusters (leader clustering at ``subcluster_distance``) that are no person's
        main sub-cluster (the one holding most of its paths), nearest first to where the
        orphan was last estimated (Hungarian, within ``separation_distance``); the paths of
        a claimed sub-cluster continue as the orphan's. Another person's paths that took a
        second person's points (people who passed within a leg's width) are given back
        once the two are ``subcluster_distance`` apart."""
        p = self.params
        own = {int(o) for o in cl.origin}
        orphans = [m for m in cl.members if m not in own and m in cl.shown]
        if not orphans:
            return
        labels = cl.labels
        n_sub = int(labels.max()) + 1
        main = self._main_subclusters(cl)
        free = [k for k in range(n_sub) if k not in main]
        if not free:
            return
        cents = np.array([cl.means[labels == k, :2].mean(axis=0) for k in free])
        prev = np.array([cl.shown[m] for m in orphans])
        d = np.linalg.norm(prev[:, None] - cents[None], axis=-1)
        rows, cols = linear_sum_assignment(np.where(d < p.separation_distance, d, 1e6))
        origin = cl.origin.copy()
        for r, c in zip(rows, cols, strict=True):
            if d[r, c] < p.separation_distance:
                origin[labels == free[int(c)]] = orphans[int(r)]
        cl.origin = origin

    def _adopt_orphans(
        self, singles: dict[int, _Single], clusters: dict[int, _Cluster], stamp: float
    ) -> None:
        """A person of a cluster none of whose Viterbi paths survive (an *orphan*: its
        points fell outside every gate, or another person's paths took them) is the target
        started next to the cluster since it formed: the nearest such target within
        ``separation_distance`` of where the orphan was last estimated takes its identity
        (Hungarian on distance) and the orphan leaves the cluster; a cluster left with one
        person becomes a single target again. An extension of 002 (whose VBA keeps a
        cluster's people until the split conditions hold)."""
        p = self.params
        in_clusters = {m for c in clusters.values() for m in c.members}
        for cl in list(clusters.values()):
            own = {int(o) for o in cl.origin}
            orphans = [m for m in cl.members if m not in own and m in cl.shown]
            new = [
                t
                for t in singles.values()
                if t.pid >= cl.born_pid and t.pid not in in_clusters and t.spawned_by == cl.cid
            ]
            if not orphans or not new:
                continue
            prev = np.array([cl.shown[m] for m in orphans])
            pos = np.array([t.mean[:2] for t in new])
            d = np.linalg.norm(prev[:, None] - pos[None], axis=-1)
            rows, cols = linear_sum_assignment(np.where(d < p.separation_distance, d, 1e6))
            taken = []
            for r, c in zip(rows, cols, strict=True):
                if d[r, c] >= p.separation_distance:
                    continue
                m, t = orphans[int(r)], new[int(c)]
                del singles[t.pid]
                singles[m] = _Single(m, t.mean, t.cov, t.last_seen)
                self._adopted(t.pid, m, cl.shown[m])
                taken.append(m)
            if not taken:
                continue
            self.events.append(CSAEvent(stamp, "adopt orphan", tuple(taken)))
            cl.members = tuple(m for m in cl.members if m not in taken)
            if len(cl.members) == 1:
                m = cl.members[0]
                singles[m] = _Single(m, cl.means.mean(axis=0), self._init_cov(), stamp)
                del clusters[cl.cid]

    def _initiate(self, free: FloatArray, stamp: float) -> None:
        if free.shape[0] < self.params.min_points:
            return
        labels = leader_clusters(free, self.params.init_distance)
        counts = np.bincount(labels)
        for k in np.flatnonzero(counts >= self.params.min_points):
            self._new_single(free[labels == k].mean(axis=0), stamp)

    def member_estimates(self, cl: _Cluster, stamp: float) -> dict[int, tuple[FloatArray, ...]]:
        """Where each person of cluster ``cl`` is: person -> (position (2,) [m], velocity
        (2,) [m/s], covariance (2, 2) [m^2]).

        002 keeps every person's identity through a cluster: each estimate of the VBA
        continues a Viterbi path that started at one person (``origin``). A person's
        position is the mean of its estimates (its legs); when its estimates lie in several
        sub-clusters (leader clustering at ``subcluster_distance``), those of the
        sub-cluster holding most of them. A person none of whose paths survived (another's
        took them over) is moved from where it was last estimated by its last velocity for
        up to ``member_coast``, then held, and gets a covariance of one gate.
        Updates the cluster's memory of where and how each person was last seen."""
        p = self.params
        labels = cl.labels
        out: dict[int, tuple[FloatArray, ...]] = {}
        for m in cl.members:
            own = cl.origin == m
            if own.any():
                counts = np.bincount(labels[own])
                sel = own & (labels == int(np.argmax(counts)))
                pos = cl.means[sel, :2]
                vel = cl.means[sel, 2:].mean(axis=0)
                cov = np.cov(pos.T) if pos.shape[0] > 1 else np.zeros((2, 2))
                cov = cov + np.eye(2) * p.mean_std**2
                xy = pos.mean(axis=0)
                self._walked(m, xy)
                cl.shown[m] = xy
                # a person coasting (coast_people) was last moved when last continued
                since = cl.continued.get(m, stamp) if p.coast_people else stamp
                cl.motion[m] = (vel, since)
                out[m] = (xy, vel, cov)
                continue
            if m not in cl.shown:  # never seen in this cluster's memory: its centre
                xy = cl.means[:, :2].mean(axis=0)
                out[m] = (xy, np.zeros(2), np.eye(2) * p.max_gate_distance**2)
                continue
            vel, since = cl.motion.get(m, (np.zeros(2), stamp))
            if stamp - since > p.max_unseen:  # lost inside the cluster: not reported
                continue
            coast = min(max(stamp - since, 0.0), p.member_coast)
            out[m] = (
                cl.shown[m] + vel * coast,
                vel if stamp - since < p.member_coast else np.zeros(2),
                np.eye(2) * p.max_gate_distance**2,
            )
        return out

    def _report(self, frame: Frame) -> Tracks:
        p = self.params
        out: list[Track] = []
        for t in self._s.singles.values():
            if self._confirmed(t) and self._shown_unseen(t, frame.stamp):
                out.append(Track(t.pid, "person", t.mean[:2], t.mean[2:], t.cov[:2, :2]))
        for c in self._s.clusters.values():
            if frame.stamp - c.last_seen > p.max_unseen:  # kept by lost_keep: not reported
                continue
            for pid, (xy, vel, cov) in self.member_estimates(c, frame.stamp).items():
                if not self._shown_walker(pid):
                    continue
                out.append(Track(pid, "person", xy, vel, cov, score=0.5))
            if not p.group_rows:
                continue
            pos = c.means[:, :2]
            cov = np.cov(pos.T) if pos.shape[0] > 1 else np.eye(2) * p.point_std**2
            out.append(
                Track(
                    c.cid,
                    "group",
                    pos.mean(axis=0),
                    c.means[:, 2:].mean(axis=0),
                    cov + np.eye(2) * 1e-6,
                    size=len(c.members),
                    members=c.members,
                )
            )
        frame_name = frame.points.frame if frame.points is not None else frame.frame
        return Tracks(frame.stamp, frame.index, tuple(out), frame_name, frame.sensor_pose)

    @property
    def clusters(self) -> dict[int, tuple[int, ...]]:
        """Cluster id -> the people it holds (the memory of who merged)."""
        return {c.cid: c.members for c in self._s.clusters.values()}


WALL_TOLERANCE = 0.05
"""Points within this distance [m] of a line lie on it (``on_a_wall``): a wall's returns
scatter a few centimetres about it, a leg's arc bulges 0.07 m from its chord."""
WALL_OWN = 0.35
"""The points within this distance [m] of a target are its own (``on_a_wall``; the
``[leg_foreground] radius`` that keeps them)."""


def on_a_wall(xy: FloatArray, points: FloatArray, length: float) -> bool:
    """Whether a target at ``xy`` (2,) [m] sits on a wall of the scan's ``points`` (N, 2)
    [m]: its own points (those within :data:`WALL_OWN`, at least 3) lie on a straight line
    (RMS distance from their principal axis at most :data:`WALL_TOLERANCE`), and the
    points within ``length`` [m] of it that lie on that line span at least ``length``.
    A person's legs are two arcs, and their line does not continue beyond them."""
    d = np.linalg.norm(points - xy, axis=1)
    own = points[d <= WALL_OWN]
    if own.shape[0] < 3:
        return False
    centre = own.mean(axis=0)
    _, _, vt = np.linalg.svd(own - centre, full_matrices=False)
    if math.sqrt(float(np.mean(((own - centre) @ vt[1]) ** 2))) > WALL_TOLERANCE:
        return False
    near = points[d <= length] - centre
    along = near[np.abs(near @ vt[1]) <= WALL_TOLERANCE] @ vt[0]
    return bool(along.max() - along.min() >= length)


Estimates = tuple[FloatArray, FloatArray, FloatArray, IntArray]
"""A cluster's estimates: means (E, 4), covariances (E, 4, 4), path scores (E,) and the
person each path started from (E,)."""


def coast_people(
    new: Estimates,
    predicted: Estimates,
    continued: dict[int, float],
    times: tuple[float, float],
    max_unseen: float,
) -> Estimates:
    """The estimates ``new`` after a VBA step at ``times[0]`` [s], with the ``predicted``
    estimates (the old ones, predicted to then) of every person none of whose paths the
    step continued appended unchanged, while that person's paths were last continued at
    most ``max_unseen`` [s] ago (see ``coast_people``). Updates ``continued`` (person ->
    when its paths were last continued [s]; a person it lacks, e.g. one counted into the
    cluster, counts from ``times[1]``, the cluster's last scan with measurements)."""
    stamp, before = times
    kept = {int(o) for o in new[3]}
    for o in kept:
        continued[o] = stamp
    old_origin = predicted[3]
    for o in {int(o) for o in old_origin}:
        continued.setdefault(o, before)  # its clock runs from the cluster's last scan
    coast = [
        o for o in sorted({int(o) for o in old_origin} - kept) if stamp - continued[o] <= max_unseen
    ]
    if not coast:
        return new
    sel = np.isin(old_origin, coast)
    means, covs, scores, origin = (
        np.concatenate([a, b[sel]]) for a, b in zip(new, predicted, strict=True)
    )
    return means, covs, scores, origin.astype(np.int64)


def per_person_scores(scores: FloatArray, origin: IntArray) -> FloatArray:
    """Path scores (E,) shifted so that the best path of every person (``origin`` (E,),
    the person each path started from) scores 0: paths compete on their whole history
    only with the paths of the same person, and between people only the last step's fit
    counts."""
    s = np.asarray(scores, dtype=np.float64)
    if s.size == 0:
        return s.copy()
    _, inv = np.unique(origin, return_inverse=True)
    best = np.full(int(inv.max()) + 1, -np.inf)
    np.maximum.at(best, inv, s)
    return s - best[inv]


def _fragment_origins(
    origin: IntArray, members: tuple[int, ...], shown: dict[int, FloatArray]
) -> IntArray:
    """``origin`` (E,) with every path that started at a target which is not one of the
    cluster's ``members`` (a fragment, see ``fragment_rule``) given to the member last
    shown nearest to that target (``shown``: person -> position (2,)); unchanged where no
    member was shown."""
    known = [m for m in members if m in shown]
    stray = sorted({int(o) for o in origin} - set(members))
    if not known or not stray:
        return origin
    out = origin.copy()
    ref = np.array([shown[m] for m in known])
    for o in stray:
        if o in shown:
            out[origin == o] = known[int(np.argmin(np.linalg.norm(ref - shown[o], axis=1)))]
    return out


def person_groups(positions: FloatArray, width: float) -> IntArray:
    """Person-sized groups of positions (N, 2) [m] by complete linkage: the two groups
    whose farthest pair of positions is closest are joined while that distance is at most
    ``width`` [m], so every group fits within ``width`` (two legs of a person, a torso)
    and people standing side by side are apart. Returns a group label (N,) per position,
    0 .. K-1 in the order of each group's first position."""
    pts = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
    n = pts.shape[0]
    d = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    label = np.arange(n)
    while n > 1:
        i, j = np.unravel_index(int(np.argmin(d)), d.shape)
        if not d[i, j] <= width:
            break
        i, j = min(i, j), max(i, j)
        d[i] = np.maximum(d[i], d[j])  # complete linkage: the farthest pair
        d[:, i] = d[i]
        d[i, i] = np.inf
        d[j] = np.inf
        d[:, j] = np.inf
        label[label == j] = i
    # every group is labelled by its first position: numbered in that order
    return np.unique(label, return_inverse=True)[1].astype(np.int64).reshape(-1)


def gate_components(gates: NDArray[np.bool_]) -> list[list[int]]:
    """The objects that merge (002 Sec. 2: objects whose validation gates share a
    measurement): groups of the rows of ``gates`` (O, M) connected by sharing at least one
    measurement, each sorted, in the order of their first object."""
    n = gates.shape[0]
    g = gates.astype(np.float64)
    shared = (g @ g.T) > 0  # share at least one measurement
    label = components(n, np.argwhere(np.triu(shared, 1)))
    out: dict[int, list[int]] = {}
    for i, k in enumerate(label.tolist()):
        out.setdefault(k, []).append(i)
    return list(out.values())
