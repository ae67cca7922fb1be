"""The multi-hypothesis leg tracker with adaptive occlusion probabilities (000 Sec. 3).

Legs are tracked individually by the MHT core with a constant-velocity Kalman filter. The
label probabilities of a leg track are conditioned on its class (000 eqs. 9-15): legs of a
validated person are *approved* and are far more likely to be occluded (by the other leg)
than deleted; all others are *free*. People are built from leg pairs (000 Sec. 3.3) after
every scan, and the set of approved legs they define is used by the next scan's hypotheses.
The non-adaptive mode uses one class's probabilities for every track (000 Sec. 3.4).

Tracking happens in the world frame when the detections carry a sensor pose (a moving
sensor; odometry or tf), otherwise in the sensor frame.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.config import param
from laserpeople.scan import CoordinateFrame
from laserpeople.tracking.frames import in_frame, tracking_frame
from laserpeople.tracking.guard import InputGuard
from laserpeople.tracking.kalman import KalmanParams
from laserpeople.tracking.mht.core import K_BEST, MHT, MIN_RATIO, N_SCAN, MHTParams, StepStats
from laserpeople.tracking.mht.probability import LabelProbabilities
from laserpeople.tracking.mht.tracktree import OCCLUDED, TrackNode
from laserpeople.tracking.people import LegState, PersonFuser, PersonParams
from laserpeople.tracking.person_tracks import (
    PersonTracker,
    PersonTrackParams,
    leg_observations,
)
from laserpeople.tracking.point_model import KalmanPointModel, PointMeasurements
from laserpeople.tracking.seen_ids import SeenIds
from laserpeople.tracks import Detections, Track, Tracks

FloatArray = NDArray[np.float64]

PEOPLE_POLICIES = ("arras", "tracks")
"""Person layers: 000's leg pairs (``arras``) or person tracks of their own (``tracks``)."""

POLICY_MIN_RATIO = {"arras": MIN_RATIO, "tracks": 1e-2}
"""Ratio pruning of leg hypotheses per people policy where ``mht.min_ratio`` is unset.
``arras`` keeps the value 000's reproduction has used (the generic
:data:`~.mht.core.MIN_RATIO`, 1e-3; 000 names ratio pruning without a value). ``tracks``
drops hypotheses below 1 % of their cluster's best (issue 10, sessions 7-8): the leg MHT
0.78x / 0.74x CPU per scan on ``bench_track`` at 4 / 20 people; real person-following dev
recording identity recall / recall / ids 0.979 / 0.985 / 2 -> 0.977 / 0.984 / 2, the other
real bags' ids and static seconds unchanged; held-back randomised seeds 100-119 MOTA / IDF1
0.335 / 0.403 -> 0.338 / 0.410."""

POLICY_K_BEST = {"arras": K_BEST, "tracks": 5}
"""Children per cluster and scan per people policy where ``mht.k_best`` is unset. ``arras``
keeps :data:`~.mht.core.K_BEST` (20, an assumption: 000 averages k over 2..200); ``tracks``
keeps 5 (issue 10).
With N-scan 4: tuning seeds (randomised 0-9; crossing-3, narrow-corridor, entrance-hall 1-4)
MOTA / IDF1 0.288 / 0.323 -> 0.302 / 0.326, crossing-3 unchanged, narrow-corridor 0.348 /
0.369 -> 0.345 / 0.363, entrance-hall 0.346 / 0.380 -> 0.335 / 0.371, at 0.52-0.76x of the
CPU per scan; real dev recording identity recall / recall / ids 0.977 / 0.984 / 2 -> 0.979 /
0.985 / 2, the unlabelled real bags' ids, walkers and static seconds unchanged. Held back
(with ``[occupancy] learn_period``): randomised 100-119 MOTA / IDF1 0.343 / 0.413 -> 0.336 /
0.413, crossing-3 0.924 / 0.901 -> 0.923 / 0.893, narrow-corridor 0.365 / 0.392 -> 0.365 /
0.393, entrance-hall 0.352 / 0.389 -> 0.357 / 0.383, at 0.50-0.91x of Stone Soup GNN's CPU
per scan (1.2-3.6x before); demo seeds 0-4 MOTA 0.865 -> 0.844."""

POLICY_N_SCAN = {"arras": N_SCAN, "tracks": 4}
"""N-scan-back depth per people policy where ``mht.n_scan`` is unset: ``arras`` keeps 000's
eight (:data:`~.mht.core.N_SCAN`), ``tracks`` 4 (with :data:`POLICY_K_BEST`; with k 5 a
depth of 8 gave 0.293 / 0.319 on randomised 0-9 and 0.333 / 0.349 on entrance-hall 1-4)."""


@dataclass(frozen=True)
class LegTrackerParams:
    """Parameters of the multi-hypothesis leg tracker (000 Sec. 3, Table 10)."""

    config_section = "leg_tracker"
    paper_preset = MappingProxyType(
        {  # 000 Sec. 3 where the defaults depart from it (docs/papers.md)
            "people_policy": "arras",
            "max_report_unseen": float("inf"),
            "kalman": MappingProxyType({"coast_velocity_time": float("inf")}),
            "person": MappingProxyType(
                {
                    "validate_still": False,
                    "relink_time": 0.0,
                    "max_leg_separation": float("inf"),
                    "max_spread": float("inf"),
                    "dissolve_wide": False,
                }
            ),
        }
    )

    p_det_free: float = param(0.3, "000 Table 10", "P(detected | free track)")
    p_occ_free: float = param(0.63, "000 Table 10", "P(occluded | free track)")
    p_del_free: float = param(0.07, "000 Table 10", "P(deleted | free track)")
    p_det_approved: float = param(0.2, "000 Table 10", "P(detected | approved track)")
    p_occ_approved: float = param(0.79, "000 Table 10", "P(occluded | approved track)")
    p_del_approved: float = param(0.01, "000 Table 10", "P(deleted | approved track)")
    lambda_new: float = param(0.001, "000 Table 10", "density of new tracks", "1/m^2")
    lambda_fal: float = param(0.003, "000 Table 10", "density of false alarms", "1/m^2")
    adaptive: bool = param(
        True, "000 Sec. 3.3.1", "condition label probabilities on free/approved tracks"
    )
    nonadaptive_class: str = param(
        "free",
        "000 Sec. 3.4 (free by default; approved for Fig. 9)",
        "without adaptation, every track uses this class's probabilities: free or approved",
    )
    max_report_unseen: float = param(
        1.0,
        "departure from 000 Sec. 3 (inf: every track reported; --preset paper), an "
        "assumption: with p_occ = 0.79 an approved leg lives on unseen "
        "for seconds; a walker unseen for 1 s may be ~1 m (the evaluation gate) from the "
        "held estimate. 1/2/3 s left the demo seeds 0-4 unchanged (0.5 s cost 0.003 MOTA); "
        "1 s drops 6% of the person rows on demo_stationary_simple_environment.bag",
        "a leg track unseen for longer is kept in the MHT but not reported, and a person "
        "is not reported while neither of its legs is (inf: report all)",
        "s",
    )
    people_policy: str = param(
        "tracks",
        "departure from 000 Sec. 3.3 (arras; --preset paper); measured "
        "(docs/people-benchmarks.md): real following robot identity recall 0.24 -> 0.98 "
        "with tracks",
        "how people are made from legs: arras (000: a person exists while a validated leg "
        "pair does) or tracks (people as tracks of their own, fed by their legs, with an "
        "existence score)",
    )
    kalman: KalmanParams = param(  # noqa: RUF009 (a frozen default instance)
        KalmanParams(), "nested table kalman.*", "leg motion model"
    )
    mht: MHTParams = param(  # noqa: RUF009 (a frozen default instance)
        MHTParams(),
        "nested table mht.*; mht.min_ratio, k_best and n_scan unset: by people policy "
        "(POLICY_MIN_RATIO, POLICY_K_BEST, POLICY_N_SCAN: arras 1e-3, 20, 8; tracks 1e-2, 5, 4)",
        "hypothesis branching and pruning",
    )
    person: PersonParams = param(  # noqa: RUF009 (a frozen default instance)
        PersonParams(), "nested table person.*", "people from leg pairs (policy arras)"
    )
    people: PersonTrackParams = param(  # noqa: RUF009 (a frozen default instance)
        PersonTrackParams(), "nested table people.*", "people as tracks (policy tracks)"
    )

    def __post_init__(self) -> None:
        for label, make in (("free", self.free), ("approved", self.approved)):
            try:
                make()
            except ValueError as exc:  # name the keys as a config file writes them
                keys = f"p_det_{label}, p_occ_{label}, p_del_{label}"
                raise ValueError(f"{label} tracks ({keys}): {exc}") from exc
        if self.people_policy not in PEOPLE_POLICIES:
            raise ValueError(f"people_policy must be one of {', '.join(PEOPLE_POLICIES)}")
        if self.nonadaptive_class not in ("free", "approved"):
            raise ValueError("nonadaptive_class must be 'free' or 'approved'")
        if not (0 < self.lambda_new < np.inf and 0 < self.lambda_fal < np.inf):
            raise ValueError("lambda_new and lambda_fal must be positive and finite")
        if not self.max_report_unseen >= 0:
            raise ValueError("max_report_unseen must be non-negative (inf: report all)")

    def mht_params(self) -> MHTParams:
        """The MHT's parameters in use: ``mht`` with an unset ``min_ratio``, ``k_best`` and
        ``n_scan`` resolved by the people policy (:data:`POLICY_MIN_RATIO`,
        :data:`POLICY_K_BEST`, :data:`POLICY_N_SCAN`). Resolved here, at use, so that
        ``replace(params, people_policy=...)`` changes them too."""
        policy = self.people_policy
        return self.mht.with_defaults(
            POLICY_MIN_RATIO[policy], POLICY_K_BEST[policy], POLICY_N_SCAN[policy]
        )

    def free(self) -> LabelProbabilities:
        """Label probabilities of free tracks."""
        return LabelProbabilities(self.p_det_free, self.p_occ_free, self.p_del_free)

    def approved(self) -> LabelProbabilities:
        """Label probabilities of approved tracks."""
        return LabelProbabilities(self.p_det_approved, self.p_occ_approved, self.p_del_approved)


class LegLabelModel:
    """Label probabilities of leg tracks by class (000 eqs. 9-15).

    Attributes:
        approved: Families (leg ids) that belong to validated persons.
    """

    def __init__(self, params: LegTrackerParams) -> None:
        self.params = params
        self.approved: frozenset[int] = frozenset()
        self._free = params.free().log()
        self._approved = params.approved().log()
        fixed: Literal["free", "approved"] = (
            "approved" if params.nonadaptive_class == "approved" else "free"
        )
        self._fixed = self._approved if fixed == "approved" else self._free
        self._by_class = np.stack([self._free, self._approved])  # rows: free, approved
        self._log_new = float(np.log(params.lambda_new))
        self._log_fal = float(np.log(params.lambda_fal))
        self._rates = self._rate_rows(16)

    def track_log_probs(self, nodes: Sequence[TrackNode]) -> FloatArray:
        """(T, 3) log p of detected/occluded/deleted for each node's class."""
        if not self.params.adaptive:
            return np.tile(self._fixed, (len(nodes), 1))
        approved = self.approved
        if not approved:  # (no person confirmed: every track free, without the test per node)
            return np.repeat(self._free[None, :], len(nodes), axis=0)
        # (row 1, approved, or 0, free, of each node's class: one list and one take, a
        # third of the CPU of a generator into np.fromiter and np.where; the same floats)
        rows = [1 if n.family in approved else 0 for n in nodes]
        return self._by_class.take(np.array(rows, dtype=np.intp), axis=0)

    def measurement_log_rates(
        self, measurements: PointMeasurements
    ) -> tuple[FloatArray, FloatArray]:
        """log lambda_new, log lambda_fal for every measurement (read-only views of rows
        kept between scans: two slices instead of two ``np.full`` a scan)."""
        m = len(measurements)
        if self._rates[0].shape[0] < m:
            self._rates = self._rate_rows(max(m, 2 * self._rates[0].shape[0]))
        new, fal = self._rates
        return new[:m], fal[:m]

    def _rate_rows(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n`` copies (n,) of log lambda_new and of log lambda_fal, read-only."""
        new, fal = np.full(n, self._log_new), np.full(n, self._log_fal)
        new.setflags(write=False)
        fal.setflags(write=False)
        return new, fal


class LegMHTTracker:
    """Leg and person tracker: ``update(detections) -> Tracks`` once per scan.

    Output: ``kind="leg"`` tracks of the best hypothesis (id = leg track family) and
    ``kind="person"`` tracks (members = their leg ids), in the tracking frame.

    Args:
        params: Parameters; ``people_policy`` chooses the person layer.
        static_model: A static world model (policy ``tracks`` only): people standing on
            places static for long are not confirmed until they move. The caller feeds it
            each scan's frame before :meth:`update`, in the tracking frame.
    """

    def __init__(
        self,
        params: LegTrackerParams | None = None,
        static_model: StaticWorldModel | None = None,
    ) -> None:
        self.params = params if params is not None else LegTrackerParams()
        self.person_tracks: PersonTracker | None = (
            PersonTracker(self.params.people, static_model)
            if self.params.people_policy == "tracks"
            else None
        )
        self.labels = LegLabelModel(self.params)
        # (one model per parent: nothing reads the nodes' own predictions)
        model = KalmanPointModel(self.params.kalman, node_predictions=False)
        self.mht: MHT[PointMeasurements] = MHT(self.params.mht_params(), model, self.labels)
        self.people = PersonFuser(self.params.person)
        self.frame: CoordinateFrame | None = None
        self.last_stats: StepStats | None = None
        self.leg_ids_reported = SeenIds()
        """Distinct leg ids reported since the start (``len``), in bounded memory."""
        self.dropped_detections = 0
        """Detections with a non-finite position, left out (counted, never silently): the
        input guard's and those made non-finite by the move to the tracking frame."""
        self._dropped_in_frame = 0
        self.static_legs_left_out = 0
        """Leg detections left out of the MHT as furniture (``people.static_legs`` false):
        on places static for long with nobody who has walked near."""
        self.guard = InputGuard()
        """Counts of hostile input (repeated/backward stamps, non-finite values)."""
        self._kept: NDArray[np.intp] = np.empty(0, dtype=np.intp)
        self._all_rows: NDArray[np.intp] = np.empty(0, dtype=np.intp)
        self.hidden_tracks = 0
        """Leg and person tracks of the last scan left out of the output (unseen too long)."""

    def _measurements(self, detections: Detections) -> PointMeasurements:
        if self.frame is None:
            self.frame = tracking_frame(detections)
            if self.person_tracks is not None:
                self.person_tracks.world_frame = self.frame == "world"
        detections = in_frame(detections, self.frame)
        meas = PointMeasurements.from_detections(detections, self.params.kalman.measurement_std)
        pos = meas.positions
        # (None: every row kept, the usual case, without the arrays of rows)
        keep: NDArray[np.bool_] | None = None
        if not np.isfinite(pos).all():  # e.g. a sensor pose with a NaN
            finite_rows = np.asarray(np.isfinite(pos).all(axis=1))
            self._dropped_in_frame += int(np.count_nonzero(~finite_rows))
            keep = finite_rows
        if self.person_tracks is not None:
            finite = None if keep is None else keep.nonzero()[0]
            on = self.person_tracks.on_furniture(pos if finite is None else pos.take(finite, 0))
            if on.any():
                if keep is None or finite is None:
                    keep, finite = np.ones(len(meas), dtype=bool), self._rows(len(meas))
                keep[finite[on]] = False
                self.static_legs_left_out += int(np.count_nonzero(on))
        if keep is None:
            self._kept = self._rows(len(meas))
            return meas
        self._kept = keep.nonzero()[0]
        return PointMeasurements(pos.take(self._kept, axis=0), meas.covariances.take(self._kept, 0))

    def _rows(self, n: int) -> NDArray[np.intp]:
        """0, 1, ..., n - 1 (a read-only slice of rows kept between scans)."""
        if self._all_rows.shape[0] < n:
            self._all_rows = np.arange(max(n, 2 * self._all_rows.shape[0]), dtype=np.intp)
            self._all_rows.setflags(write=False)
        return self._all_rows[:n]

    def update(self, detections: Detections) -> Tracks:
        """Track one scan's leg detections (checked by :class:`InputGuard` first)."""
        detections = self.guard.check(detections)
        meas = self._measurements(detections)
        self.dropped_detections = self.guard.dropped_detections + self._dropped_in_frame
        self.last_stats = self.mht.step(meas, detections.stamp)
        if self.last_stats.degraded_clusters:
            self.guard.degraded(detections.scan_index)
        # (one node per family, by family; the probability of each family's cluster)
        best, probs = self.mht.best_nodes()
        stamp = detections.stamp
        unseen = [n.unseen_for(stamp) for n in best]  # (once per node: output and people)
        if self.person_tracks is None:
            legs = {n.family: LegState(n.family, n.mean, n.cov, probs[n.family]) for n in best}
            persons = self.people.update(legs, detections.stamp)
            self.labels.approved = self.people.approved_legs
        else:
            persons = self._people_as_tracks(best, unseen, detections)
            self.labels.approved = self.person_tracks.approved_legs
        # legs unseen for too long stay in the MHT and the person layer, but are not reported
        limit = self.params.max_report_unseen
        nodes = [n for n, u in zip(best, unseen, strict=True) if u <= limit]
        shown = {n.family for n in nodes}
        n_tracks = len(best) + len(persons)
        persons = [p for p in persons if any(m in shown for m in p.members)]
        self.hidden_tracks = n_tracks - len(nodes) - len(persons)
        self.leg_ids_reported.prune(self.mht.tree.nodes_by_family)
        self.leg_ids_reported.add(shown)
        # (positional: track_id, kind, position, velocity, covariance, size, labels, score;
        # a sixth of the cost of passing them by keyword)
        leg_tracks = [
            Track(n.family, "leg", n.mean[:2], n.mean[2:4], n.cov[:2, :2], 1, "", probs[n.family])
            for n in nodes
        ]
        assert self.frame is not None
        return Tracks(
            detections.stamp,
            detections.scan_index,
            tuple(leg_tracks + persons),
            self.frame,
            detections.sensor_pose,
        )

    def _people_as_tracks(
        self, best: list[TrackNode], unseen: list[float], detections: Detections
    ) -> list[Track]:
        """Person tracks of the ``tracks`` policy from the best hypothesis's leg nodes and
        the time [s] each is unseen for."""
        assert self.person_tracks is not None
        stamp = detections.stamp
        kept = self._kept.tolist()  # (plain ints: no numpy scalar per leg)
        rows = [
            (
                n.family,
                n.mean,
                u,
                kept[n.measurement]
                if n.label != OCCLUDED and n.measurement >= 0 and n.stamp == stamp
                else -1,
            )
            for n, u in zip(best, unseen, strict=True)
        ]
        segments = [s.points for s in detections.segments]
        obs = leg_observations(rows, segments, detections.scores, self.params.people)
        return self.person_tracks.update(obs, stamp, self.params.max_report_unseen)

    @property
    def persons_created(self) -> int:
        """People created since the start (either policy)."""
        if self.person_tracks is not None:
            return self.person_tracks.persons_created
        return self.people.persons_created

    def state_counts(self) -> dict[str, int]:
        """Sizes of what the tracker keeps between scans: live leg families, track nodes,
        hypotheses, cluster links of the MHT and the person layer's stored people and leg
        histories (for the soak benchmark and the bounded-state tests)."""
        mht = self.mht
        if self.person_tracks is not None:
            persons = len(self.person_tracks.persons)
            memory = 0
        else:
            persons = len(self.people._persons) + len(self.people._lost)
            memory = len(self.people._history)
        return {
            "families": mht.tree.n_families,
            "nodes": mht.tree.n_nodes,
            "hypotheses": sum(len(c.hypotheses) for c in mht.clusters),
            "links": len(mht.links),
            "persons": persons,
            "leg_history": memory,
        }

    @property
    def n_hypotheses(self) -> int:
        """Hypotheses after the last scan, summed over clusters."""
        return 0 if self.last_stats is None else self.last_stats.n_hypotheses
