"""The parameters of the Cluster Sorting Algorithm (002 Sec. 2), with their sources."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType

from laserpeople.config import param


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
            "jump_back": False,
            "leg_reid": False,
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
    jump_back: bool = param(
        True,
        "extension of 002 (whose KFA keeps one state; false restores 002): on the real "
        "followed-person recording the target of the person, unseen for 0.3 s, takes a "
        "7-point blob 0.89 m aside seen in that scan only, runs off at 3 m/s, and the "
        "person's points, back 4 scans later, start a new id; identity recall 0.404 -> "
        "0.666 (docs/csa.md, 'Real data')",
        "a single target that takes selected measurements after a scan without any, "
        "their mean farther than init_distance from its prediction (a jump), having had "
        "selected measurements in every scan for jump_back_seen before that scan, keeps "
        "its state before them (predicted on) for max_unseen from when it last had "
        "points; when the target then has a scan without selected measurements and at "
        "least min_points foreground points no object selects lie inside that older "
        "state's gate, the target goes back to it, updated with their mean (the jump "
        "was someone else)",
    )
    jump_back_seen: float = param(
        0.5,
        "assumption, checked on the recordings: the real followed person had points for "
        "0.8 s before its jump; the targets on flickering clutter that jumped on "
        "random-groups seeds 12, 14 and 101 (moving lasers) 0.0-0.2 s; without it "
        "held-back seed 101 MOTA 0.557 -> 0.541 (docs/csa.md)",
        "under jump_back, a jump counts only for a target that had selected "
        "measurements in every scan for at least this long before the scan it missed "
        "(0: every target)",
        "s",
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
        "more measurement point (tracking/csa/leg_people.py)",
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

    leg_reid: bool = param(
        True,
        "measured (docs/trackers.md, the real followed-person recording): identity recall "
        "of the followed person 0.67 -> 0.98; false in the paper preset (002 has none)",
        "give people who come back after a loss their old id by their leg widths ([leg_reid], "
        "identity/leg_width.py)",
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
        for name in (
            "moving_travel",
            "moving_unseen",
            "moving_wall",
            "lost_keep",
            "jump_back_seen",
        ):
            if not 0.0 <= getattr(self, name) < math.inf:
                raise ValueError(f"{name} must be finite and not negative")

    @property
    def gate(self) -> float:
        """Squared Mahalanobis radius of a validation gate: the chi-square quantile with 2
        degrees of freedom, -2 ln(1 - p)."""
        return -2.0 * math.log1p(-self.gate_probability)
