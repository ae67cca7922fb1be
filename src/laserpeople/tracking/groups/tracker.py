"""The group tracker of 000 Sec. 4: a multi-model MHT over groups of people.

Each frame: the foreground points are clustered by single linkage (d_P) into observations
with their number of human-sized blobs (Sec. 4.1); the MHT core predicts the group tracks,
the branch generator spawns the continue/split/merge models of every parent hypothesis with
re-predicted tracks and re-clustered observations (Secs. 4.3-4.4), and the core lists the k
best children over all models and parents with the hypothesis probability of eqs. 33-37,
prunes (ratio, N-scan-back) and updates the matched groups (eqs. 28-31).

Reported are the groups of the best hypothesis that are confirmed (in it for
``confirm_scans`` consecutive scans, :mod:`.confirm`; 1 reports every group, as 000) and,
with a static world model, not on a static place. A group first reported where a
reported group vanished takes its id (``id_memory``, :mod:`.handover`).

The people-only mode (:meth:`GroupTrackerParams.people_only`) inhibits splits and merges
and clusters with a small d_P, the comparison tracker of 000 Fig. 17 (right).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from laserpeople.background import StaticWorldModel
from laserpeople.config import param
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame, FrameField
from laserpeople.scan import visible_area
from laserpeople.tracking.groups.coast import CoastedReports
from laserpeople.tracking.groups.confirm import Candidate, Confirmation, ConfirmSettings
from laserpeople.tracking.groups.handover import IdHandover
from laserpeople.tracking.groups.interaction import (
    GroupBranches,
    GroupLabelModel,
    InteractionSettings,
)
from laserpeople.tracking.groups.labels import format_labels, sort_labels
from laserpeople.tracking.groups.model import GroupModel, GroupModelSettings, group_payload
from laserpeople.tracking.groups.observations import GroupObservations, SizeCounting
from laserpeople.tracking.groups.occlusion import FrameShadows
from laserpeople.tracking.kalman import chi2_quantile_2dof
from laserpeople.tracking.mht.core import MHT, N_SCAN, MHTParams, StepStats
from laserpeople.tracking.mht.tracktree import TrackNode
from laserpeople.tracks import Track, Tracks

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


LABEL_MEMO = 4096
"""Label sets whose displayed and formatted forms a tracker remembers at most (then it
forgets all); below that, :meth:`GroupMHTTracker.forget_gone` keeps only the label sets of
tracks alive in some hypothesis."""
FORGET_EVERY = 64
"""Scans between two rounds of :meth:`GroupMHTTracker.forget_gone` (what it keeps of gone
tracks in between is at most this many scans' worth)."""
EVENTS_KEPT = 1024
"""Splits and merges :attr:`GroupMHTTracker.events` keeps at least (the latest; at most
twice as many, all are counted in :attr:`GroupMHTTracker.event_counts`): the 20-people
hall records about 75 per 1,000 scans, some 65,000 in a robot's day at 10 scans/s."""
GROUP_MIN_RATIO = 3e-3
"""Ratio pruning of group hypotheses where ``mht.min_ratio`` is unset: drop a hypothesis
below 0.3 % of its cluster's best (000 Sec. 4.5.2 names ratio pruning without a value; the
generic :data:`~laserpeople.tracking.mht.core.MIN_RATIO` is 1e-3). Chosen
for speed (issue 12: under 5 ms at 20 people) on entrance-hall seeds 0 and 1 (60 s, d_P
1.3 m: clustering error 0.2417, group size and events the same for 1e-3, 2e-3 and 3e-3;
5e-3 0.2413, 1e-2 0.2445); held out (seeds 2-4, 5-7) and on the real demo bag see
docs/groups.md "Settings", ratio pruning."""
GROUP_N_SCAN = 3
"""N-scan-back depth of group hypotheses where ``mht.n_scan`` is unset (000's scan-back depth
of eight, :data:`~laserpeople.tracking.mht.core.N_SCAN`, under ``--preset paper``): a merge
of two groups passing each other that lost in its scan no longer stays among the
hypotheses to win a few scans later. Measured with ``model_prior`` normalised on held-back
random-groups seeds 100-119 and the real recordings (docs/groups.md, "Eq. 32 normalised and
N-scan-back 3")."""


@dataclass(frozen=True)
class GroupTrackerParams:
    """Parameters of the group tracker (000 Sec. 4)."""

    config_section = "group_tracker"
    paper_preset = MappingProxyType(
        {  # 000 Sec. 4 where the defaults depart from it (docs/papers.md)
            "eps_n": 0.1,
            "size_count": "blobs",
            "stride_near": 0.0,
            "stride_far": 0.0,
            "max_blob_size": 0.0,
            "merge_likelihood": "density",
            "model_prior": "literal",
            "observation_area": 0.0,
            "share_parts": False,
            "prune_labels": True,
            "join_observations": False,
            "recluster_blobs": False,
            "hausdorff": "mean",
            "static_groups": True,
            "confirm_scans": 1,
            "confirm_event_scans": 1,
            "reuse_ids": False,
            "id_memory": 0.0,
            "coast_time": 0.0,
            "merged_coast_time": 0.0,
            "velocity_window": 0.0,
            "shadow_occlusion": False,
            "mht": MappingProxyType({"n_scan": N_SCAN}),  # 000's scan-back depth of eight
        }
    )

    p_m: float = param(0.79, "000 Sec. 4.6", "P(matched) of a group track")
    p_o: float = param(0.19, "000 Sec. 4.6", "P(occluded) of a group track")
    p_t: float = param(0.02, "000 Sec. 4.6", "P(obsolete, terminated) of a group track")
    p_f: float = param(0.06, "000 Sec. 4.6", "P(false alarm) of an observation")
    p_n: float = param(0.02, "000 Sec. 4.6", "P(new track) of an observation")
    shadow_occlusion: bool = param(
        True,
        "extension of 000 Sec. 4.5 by its Sec. 3.3.1 (adaptive occlusion probabilities, "
        "there for legs); measured on random-groups and the real recordings in "
        "docs/groups.md",
        "a group whose predicted contour lies wholly behind closer returns of the scan takes "
        "p_m_shadowed, p_o_shadowed, p_t_shadowed instead of p_m, p_o, p_t (False: 000's "
        "one set for every group)",
    )
    p_m_shadowed: float = param(
        0.2, "000 Table 10 (approved leg)", "P(matched) of a group in the shadow of closer returns"
    )
    p_o_shadowed: float = param(
        0.79, "000 Table 10 (approved leg)", "P(occluded) of a group in the shadow"
    )
    p_t_shadowed: float = param(
        0.01, "000 Table 10 (approved leg)", "P(obsolete) of a group in the shadow"
    )
    shadow_margin: float = param(
        0.3,
        "assumption: a leg's width and the range noise",
        "a point is in the shadow when the beam at its bearing ended more than this in front of it",
        "m",
    )
    shadow_hits: int = param(
        10,
        "analogue of 000 Sec. 3.3.1 (only the approved legs of validated people adapt); "
        "chosen on the real demo bag (with 1: group ids 74 -> 89, groups born from a few "
        "points coasting behind a wall edge; with 10 or 30: 73), random-groups tuning seeds "
        "the same with 1 and 10",
        "scans a group must have been detected in before it takes the shadowed probabilities",
    )
    p_c: float = param(0.63, "000 Sec. 4.6", "prior of a continuation")
    p_s: float = param(0.16, "000 Sec. 4.6", "prior of a split")
    p_g: float = param(0.21, "000 Sec. 4.6", "prior of a merge (times N_ij, eq. 32)")
    sigma_pos: float = param(0.1, "000 Sec. 4.6", "initial position std sigma_x, sigma_y", "m")
    sigma_vel: float = param(0.5, "000 Sec. 4.6", "initial velocity std", "m/s")
    sigma_n: float = param(0.2, "000 Sec. 4.6", "initial group size std", "people")
    eps_pos: float = param(
        0.2, "000 Sec. 4.6", "process noise epsilon_x, epsilon_y per period", "m"
    )
    eps_vel: float = param(0.3, "000 Sec. 4.6", "process noise of the velocity per period", "m/s")
    eps_n: float = param(
        1.0,
        "departure from 000 Sec. 4.6 (0.1): the size follows the people visible in a "
        "group, which changes from scan to scan as members occlude each other; chosen on "
        "entrance-hall seeds 0 and 1 (size error 0.41 -> 0.22 people on seed 0)",
        "process noise of the size per period",
        "people",
    )
    period: float = param(
        1.0,
        "our reading of 000 Sec. 4.6 (the epsilons per second, Q = diag(eps^2) dt): read "
        "per 0.1 s scan, the velocity is unobservable (steady-state std 0.87 m/s) and a "
        "person passing a pair is merged with it (Fig. 18 fails); see docs/groups.md",
        "time the process noise variances diag(eps^2) accumulate over; Q = diag(eps^2) dt / period",
        "s",
    )
    cluster_distance: float = param(
        1.3, "000 Sec. 4.6.1 (least clustering error)", "single-linkage distance d_P", "m"
    )
    blob_distance: float = param(
        0.3, "000 Sec. 4.6.3", "single-linkage distance d_hs of human-sized blobs", "m"
    )
    max_blob_size: float = param(
        2.0,
        "extension of 000 (its foreground holds people only): on the simulated hall the "
        "largest blob of people at d_hs is 1.71 m across (99.9th percentile 0.97 m, "
        "entrance-hall seeds 0 and 1); walls a moving robot has not yet learned are longer, "
        "and cost seconds a scan as group observations",
        "points of blobs (single linkage at d_hs) wider than this (bounding-box diagonal) "
        "are left out of the observations, as not people (0: keep every point)",
        "m",
    )
    size_count: str = param(
        "resolved",
        "extension of 000 Sec. 4.1 (legs: chosen on entrance-hall seeds 0 and 1, 93 % exact "
        "on true groups against 65 % for blobs at d_hs = 0.3 m; resolved: calibrated on "
        "random-groups seeds 0-9, held-back results in docs/groups.md)",
        "how n_hs counts people: blobs (000: one per blob at d_hs) | legs (two leg-sized "
        "blobs that are mutual nearest neighbours within leg_pair_distance are one person) "
        "| resolved (as legs, and a wider blob holds the legs its beams' arc covers at their "
        "range, leg_width each)",
    )
    leg_pair_distance: float = param(
        0.7,
        "simulated walkers at 30 cm: one person's leg centres are 0.63 m apart at the 90th "
        "percentile, two neighbours' nearest legs 0.53 m at the 5th; chosen on seeds 0, 1",
        "largest distance between one person's two leg blobs (size_count legs)",
        "m",
    )
    leg_width: float = param(
        0.18,
        "calibrated on random-groups seeds 0-9 (legs 0.10-0.18 m wide; docs/groups.md)",
        "arc one leg covers (size_count resolved: a blob wider than a leg holds "
        "round(arc / leg_width) legs, the arc the sum of its points' beam spacings)",
        "m",
    )
    leg_radius: float = param(
        0.12,
        "chosen on entrance-hall seeds 0 and 1 (a leg is about 0.1-0.15 m across)",
        "largest radius of a blob that may be one leg (size_count legs)",
        "m",
    )
    person_width: float = param(
        0.6,
        "chosen on random-groups seeds 0-19 (at feet height 0.2 % of one person's blobs are "
        "wider, 39 % of those of two people or more; docs/groups.md)",
        "widest one person is at the laser (size_count resolved: a blob wider, twice its "
        "radius, holds at least ceil(2 radius / person_width) people; 0: not used)",
        "m",
    )
    pair_arc: float = param(
        0.22,
        "chosen on random-groups seeds 0-19 (one leg's blob covers an arc of 0.21 m at the "
        "99th percentile; docs/groups.md)",
        "arc from which a leg-sized blob holds two legs, one person, and is not paired with "
        "another blob (size_count resolved; 0: every leg-sized blob may be paired)",
        "m",
    )
    surface_gap: float = param(
        0.15,
        "chosen on random-groups seeds 0-19 (0.15 and 0.18 m run; a torso's scan neighbours "
        "are 0.12-0.14 m apart at the median, the legs of two people run together into one "
        "blob 0.25-0.27 m; docs/groups.md)",
        "largest gap between scan neighbours of a blob that is one continuous surface "
        "(size_count resolved: such a blob of three legs' arc, no wider than person_width, "
        "is one person; 0: not used)",
        "m",
    )
    stride_near: float = param(
        0.6,
        "chosen on random-groups seeds 0-19 and entrance-hall seeds 0 and 1 (0.55-0.7 m "
        "tried; docs/groups.md)",
        "the most people a cluster may hold pair only the leg blobs closer than this: the "
        "size read in the update is the track's predicted size within [count with pairs "
        "within stride_far, count with pairs within stride_near] (size_count legs or "
        "resolved; 0 with stride_far 0: the count at leg_pair_distance alone)",
        "m",
    )
    stride_far: float = param(
        0.8,
        "chosen on random-groups seeds 0-19 and entrance-hall seeds 0 and 1 (0.8-1.0 m "
        "tried; docs/groups.md)",
        "the fewest people a walking cluster may hold pair the leg blobs closer than this "
        "(see stride_near and stride_speed; 0 with stride_near 0: no range)",
        "m",
    )
    stride_speed: float = param(
        0.3,
        "chosen on random-groups seeds 0-19 and entrance-hall seeds 0 and 1 (0 and 0.3 m/s "
        "tried; docs/groups.md)",
        "predicted speed from which a group's size may be read down to the count with pairs "
        "within stride_far (slower groups: not below the count at leg_pair_distance; "
        "standing people take no long strides)",
        "m/s",
    )
    torso_pairs: bool = param(
        False,
        "extension of 000 Sec. 4.1 (its laser was at leg height); measured on random-groups "
        "seeds 0-19 and held back in docs/groups.md",
        "at a laser the recording states at torso height, blobs are paired as one person's "
        "legs as at leg height (false: a blob there is a body, and two neighbours' torsos "
        "closer than leg_pair_distance count two people; size_count legs or resolved)",
    )
    point_std: float = param(
        0.05,
        "assumption: range noise of a SICK LMS plus beam footprint",
        "std of a measured point (R_l of eq. 23)",
        "m",
    )
    centroid_std: float = param(
        0.1,
        "assumption: the centroid of a group moves with its members' legs",
        "std of the observed centroid in the update (eq. 30)",
        "m",
    )
    size_std: float = param(
        0.05,
        "assumption, chosen on random-groups seeds 0-19 with the maximum leg matching (0.15 "
        "before, from seeds 0-9 with size_count resolved; 0.25 from entrance-hall seeds 0 "
        "and 1 with size_count legs; held-back results in docs/groups.md)",
        "std of the observed number of people in the update (eq. 30)",
        "people",
    )
    gate_probability: float = param(
        0.99,
        "assumption (000 Sec. 4.4 names a significance level alpha without its value)",
        "gate: d_HD^2 below the chi-square quantile with 2 degrees of freedom",
    )
    max_gate_gap: float = param(
        2.0,
        "assumption (speed only): far beyond any gate at these covariances",
        "no gate is computed between a contour and a cluster farther apart than this",
        "m",
    )
    max_dt: float = param(1.0, "assumption", "longest prediction step", "s")
    split_merge: bool = param(
        True, "000 Sec. 4.4", "hypothesise splits and merges (False: people-only tracker)"
    )
    join_observations: bool = param(
        False,
        "extension of 000 (the converse of re-clustering), off: on the simulated hall "
        "(seed 0) it lowers the error at d_P 0.7 m (0.360 -> 0.292, memory-less 0.353) "
        "but raises it at 1.0-1.3 m (0.198 -> 0.232 at 1.3), see docs/groups.md",
        "also offer every model with the observations that only one continued group gates "
        "joined into one (a group seen as two clusters for a moment need not split)",
    )
    hausdorff: str = param(
        "mean",
        "000 eq. 20 (mean of the nearest Mahalanobis distances)",
        "directed distance of eq. 20: mean | rms (root mean square)",
    )
    merge_likelihood: str = param(
        "density",
        "000 eq. 27 (the normal density N_ij); 'compatibility' is an extension (see "
        "docs/groups.md): eq. 27's normaliser 1/((2 pi)^2 sqrt det(C_i + C_j)) is 6-8 at the "
        "group covariances here, so p_G N_ij exceeds one",
        "N_ij of eq. 32: density (eq. 27) | compatibility (exp(-d_min^2 / 2), at most 1)",
    )
    observation_area: float = param(
        1.0,
        "departure from 000 eqs. 36-37 (V m^2, the lasers' view: 0 here), measured in "
        "docs/papers.md: with V = 1 m^2 new groups and false alarms weigh p_N and p_F "
        "against likelihoods N_i in 1/m^2, as the tracker did before the setting existed",
        "observation volume V of eqs. 36-37: new tracks and false alarms have the rates "
        "p_N / V and p_F / V per m^2 (0: the area the lasers saw in each scan)",
        "m^2",
    )
    share_parts: bool = param(
        True,
        "departure from 000 (false here), see GroupModel.score and docs/groups.md: "
        "dividing an observation among tracks adds a factor p_M N_i > 1 per part, so a "
        "merge could never explain one observation better than the tracks re-clustered",
        "a part of a re-clustered observation counts as its share of one matched "
        "observation (false: every part is a matched observation of its own)",
    )
    prune_labels: bool = param(
        True,
        "000 Sec. 4.2.4 (optional there)",
        "a merge that unites both halves X-0 and X-1 of a split X relabels them X",
    )
    max_events: int = param(
        12,
        "assumption (speed only: at most 2^max_events models per parent are enumerated; "
        "000 bounds models only by binary events and gating)",
        "candidate split and merge events per parent hypothesis kept for model "
        "enumeration (the likeliest)",
    )
    recluster_blobs: bool = param(
        False,
        "extension of 000 Sec. 4.3 (its rule is per point): a person's legs near the "
        "border of two tracks are otherwise cut between them",
        "re-cluster by human-sized blobs (d_hs): a blob goes where most of its points' "
        "nearest track is",
    )
    model_prior: str = param(
        "normalised",
        "our reading of 000 eq. 32 (P(M | parent) must sum to one over the models, eq. 35); "
        "'literal' charges p_C to every continued track and 'choice' only to tracks an "
        "event could involve: both let a wrong merge overtake the continuation of two "
        "tracks sharing an observation by p_C per scan; normalised with GROUP_N_SCAN 3 "
        "measured on held-back random-groups seeds and the real recordings (docs/groups.md)",
        "how eq. 32 becomes P(M | parent): normalised | choice | literal",
    )
    velocity_window: float = param(
        1.0,
        "departure from 000 (0: eqs. 25-27 compare the Kalman velocities, known to about "
        "0.27 m/s, so parties passing 0.5-1.0 m/s apart merge as parties that meet); "
        "chosen on random-groups seeds 0-9 (group MOTA 0.577 -> 0.601; 0.5 s was worse "
        "than the Kalman velocity); held-back seeds, the entrance hall and the real "
        "recordings in docs/groups.md",
        "the velocity eqs. 25-27 compare when two groups may merge: the least-squares "
        "slope of the group's observed centroids over this many seconds (variance "
        "centroid_std^2 / sum (t - mean t)^2), once they span half of it (0: the Kalman "
        "filter's, 000)",
        "s",
    )
    max_models: int = param(
        16,
        "assumption (000 bounds models only by binary events and gating)",
        "most models per parent hypothesis (the likeliest by eq. 32)",
    )
    static_groups: bool = param(
        False,
        "extension of 000, measured on real data: on the leg_tracker demo bag a static object "
        "was reported as a group for 95 s under five ids, and returns at the edges of walls "
        "as some 50 groups of 1-3 scans (docs/groups.md 'Real recordings')",
        "report groups on places static for longer than static_time that have never been "
        "seen walking (true: every group of the best hypothesis, as 000); false hides them "
        "(still tracked, counted and reported by laserpeople track)",
    )
    static_time: float = param(
        10.0,
        "as people.static_time",
        "a group whose points lie on places static for longer is hidden (see arrival_slack)",
        "s",
    )
    min_travel: float = param(
        0.5,
        "as people.min_travel (leg_tracker's distance travelled to initiate a person)",
        "distance from where a group last walked (or was first tracked) that is a walk; "
        "the walks of its labels (and of the groups they split from) tell how long it has "
        "stood (see arrival_slack)",
        "m",
    )
    arrival_slack: float = param(
        2.0,
        "as people.arrival_slack",
        "a group that stands since its last walk is hidden only on places static this much "
        "longer than it has stood there",
        "s",
    )
    static_share: float = param(
        0.75,
        "assumption: a person who passes something static within d_P is one observation "
        "with it, half of whose points are on static places",
        "a group lies on a static place when at least this share of its contour points do",
    )
    confirm_scans: int = param(
        3,
        "extension of 000 (1: every group of the best hypothesis is reported in every scan, "
        "as 000): on the real demo bag 173 -> 152 group ids (reported in at most 3 scans "
        "69 -> 54; the walkers' group-seconds -0.6 %), dev recording 1718 -> 1131 ids; "
        "chosen on the real recordings and entrance-hall seeds 0 and 1 (docs/groups.md "
        "'Confirmed groups')",
        "scans a group born from an observation must have been in the best hypothesis "
        "(within confirm_window) before it is reported; the MHT is not changed",
    )
    reuse_ids: bool = param(
        True,
        "extension of 000, from its labels (Sec. 4.6.1: 'from the history of group splits "
        "and merges stored in the group labels, the correct group relations can be "
        "determined'); docs/groups.md 'Ids from labels'",
        "a group whose labels are those of a group reported before (its parts merged back) "
        "is reported with that group's id (false: every track its own id, as before)",
    )
    id_memory: float = param(
        3.0,
        "extension of 000 (0: a split, merge or new group is reported under a new id after "
        "confirm_scans, as 000); chosen on random-groups seeds 0-19 (2 s: group MOTA the "
        "same, proxemic 0.001 lower), held-back seeds and the real recordings in "
        "docs/groups.md",
        "a group first reported may take the id of a group reported within this many "
        "seconds and not reported now, whose constant-velocity prediction lies within "
        "id_gate of it; a new group there is reported at once, and a new group within "
        "take_over_distance of a reported group that is coasting (unseen) takes its place "
        "and id (with reuse_ids; 0: never)",
        "s",
    )
    id_gate: float = param(
        1.5,
        "chosen on random-groups seeds 0-19 (1.0 m: group MOTA 0.001 and proxemic MOTA "
        "0.001 lower; docs/groups.md)",
        "farthest a new group may be from a vanished group's prediction to take its id (id_memory)",
        "m",
    )
    take_over_distance: float = param(
        1.0,
        "chosen on the held-out entrance hall (1.5 m: size exact 91.0 -> 90.9 %) and "
        "random-groups seeds (docs/groups.md)",
        "farthest a new group may be from a reported group that is coasting (unseen) to take "
        "its place and id (id_memory)",
        "m",
    )
    coast_time: float = param(
        1.0,
        "extension of 000 (0: a group is reported while its track is in the best hypothesis, "
        "as 000); chosen on random-groups seeds 0-19 (group / proxemic MOTA: 0 s 0.617 / "
        "0.704, 0.6 s 0.639 / 0.717, 1 s 0.647 / 0.718, 1.5 s 0.650 / 0.712, 2 s 0.648 / "
        "0.702, before the two stops; with them 1 s 0.643 / 0.718, 1.5 s 0.647 / 0.719, 2 s "
        "0.649 / 0.718, 3 s 0.648 / 0.712: 1 s adds least on the real recordings; the stops "
        "chosen on the real recordings; docs/groups.md)",
        "a reported group that vanishes (its track deleted, or its points taken by a merge) "
        "is reported at its constant-velocity prediction, with score 0, for up to this many "
        "seconds after its last report and no longer than it had been reported, until its "
        "id is reported again or the scan sees past its predicted contour (0: never)",
        "s",
    )
    merged_coast_time: float = param(
        3.0,
        "extension of 000 (0: coast_time for every vanished group); chosen on random-groups "
        "seeds 0-19 (group / proxemic MOTA: 0 s 0.643 / 0.718, 3 s 0.651 / 0.719, 6 s 0.650 / "
        "0.714; docs/groups.md)",
        "a vanished group whose predicted contour has a point within blob_distance of a "
        "point of a group reported in this scan (a merge took its points) is coasted as "
        "coast_time says for up to this many seconds after its last report, while it "
        "does (0: coast_time for every vanished group)",
        "s",
    )
    confirm_window: int = param(
        0,
        "chosen on the real recordings (3 of 4 or 5 scans: the same or more ids than 3 "
        "consecutive)",
        "the last scans confirm_scans and confirm_event_scans are counted over "
        "(0: the larger of the two, i.e. consecutive scans)",
    )
    confirm_event_scans: int = param(
        1,
        "000 (1: at once); with 2 the followed person of the dev recording is reported in "
        "91.3 % of its labelled scans instead of 97.3 % (its people vanish while the new "
        "group waits; docs/groups.md 'Confirmed groups')",
        "confirm_scans for a group made by a split or merge of a group already reported "
        "(its people were reported)",
    )
    mht: MHTParams = param(  # noqa: RUF009 (a frozen default instance)
        MHTParams(), "nested table mht.*", "hypothesis branching and pruning"
    )

    def __post_init__(self) -> None:
        for name in ("p_m", "p_o", "p_t", "p_f", "p_n", "p_c", "p_s", "p_g"):
            if not 0.0 < getattr(self, name) < 1.0:
                raise ValueError(f"{name} must be in (0, 1)")
        if abs(self.p_m + self.p_o + self.p_t - 1.0) > 1e-6:
            raise ValueError("p_m + p_o + p_t must be 1")
        shadowed = (self.p_m_shadowed, self.p_o_shadowed, self.p_t_shadowed)
        if not all(0.0 < p < 1.0 for p in shadowed) or abs(sum(shadowed) - 1.0) > 1e-6:
            raise ValueError("p_m_shadowed, p_o_shadowed, p_t_shadowed must be in (0, 1), sum 1")
        if not (self.shadow_margin >= 0.0 and math.isfinite(self.shadow_margin)):
            raise ValueError("shadow_margin must be finite and not negative")
        if self.shadow_hits < 1:
            raise ValueError("shadow_hits must be at least 1")
        if abs(self.p_c + self.p_s + self.p_g - 1.0) > 1e-6:
            raise ValueError("p_c + p_s + p_g must be 1")
        if not 0.0 < self.blob_distance <= self.cluster_distance:
            raise ValueError("need 0 < blob_distance <= cluster_distance")
        if self.model_prior not in ("normalised", "choice", "literal"):
            raise ValueError("model_prior must be 'normalised', 'choice' or 'literal'")
        if self.merge_likelihood not in ("density", "compatibility"):
            raise ValueError("merge_likelihood must be 'density' or 'compatibility'")
        if self.hausdorff not in ("mean", "rms"):
            raise ValueError("hausdorff must be 'mean' or 'rms'")
        if self.size_count not in ("blobs", "legs", "resolved"):
            raise ValueError("size_count must be 'blobs', 'legs' or 'resolved'")
        if self.leg_pair_distance <= 0.0 or self.leg_radius <= 0.0:
            raise ValueError("leg_pair_distance and leg_radius must be positive")
        if (self.stride_near, self.stride_far) != (0.0, 0.0) and not (
            0.0 < self.stride_near <= self.leg_pair_distance <= self.stride_far
            and math.isfinite(self.stride_far)
        ):
            raise ValueError(
                "stride_near and stride_far must both be 0 (no range) or satisfy "
                "0 < stride_near <= leg_pair_distance <= stride_far, finite"
            )
        if not (self.stride_speed >= 0.0 and math.isfinite(self.stride_speed)):
            raise ValueError("stride_speed must be finite and not negative (0: every group)")
        if not (self.surface_gap >= 0.0 and math.isfinite(self.surface_gap)):
            raise ValueError("surface_gap must be finite and not negative (0: not used)")
        if self.max_models < 1 or self.max_events < 0:
            raise ValueError("max_models must be at least 1 and max_events not negative")
        if not (self.observation_area >= 0.0 and math.isfinite(self.observation_area)):
            raise ValueError("observation_area must be finite and not negative (0: per scan)")
        if min(self.static_time, self.min_travel, self.arrival_slack) < 0.0:
            raise ValueError("static_time, min_travel and arrival_slack must not be negative")
        if self.max_blob_size < 0.0:
            raise ValueError("max_blob_size must not be negative (0 keeps every point)")
        if not 0.0 < self.static_share <= 1.0:
            raise ValueError("static_share must be in (0, 1]")
        if not (self.velocity_window >= 0.0 and math.isfinite(self.velocity_window)):
            raise ValueError("velocity_window must be finite and not negative (0: Kalman's)")
        if not (self.id_memory >= 0.0 and math.isfinite(self.id_memory)):
            raise ValueError("id_memory must be finite and not negative (0: never)")
        if not (self.id_gate > 0.0 and math.isfinite(self.id_gate)):
            raise ValueError("id_gate must be positive and finite")
        if not (self.take_over_distance >= 0.0 and math.isfinite(self.take_over_distance)):
            raise ValueError("take_over_distance must be finite and not negative (0: never)")
        if not (self.coast_time >= 0.0 and math.isfinite(self.coast_time)):
            raise ValueError("coast_time must be finite and not negative (0: never)")
        if not (self.merged_coast_time >= 0.0 and math.isfinite(self.merged_coast_time)):
            raise ValueError("merged_coast_time must be finite and not negative (0: coast_time)")
        if self.confirm_window < 0:
            raise ValueError("confirm_window must not be negative (0: consecutive scans)")
        self.confirm_settings()  # checks the confirmation values

    @classmethod
    def people_only(cls, cluster_distance: float = 0.5, **changes: object) -> GroupTrackerParams:
        """The people tracker of 000 Fig. 17 (right): no splits or merges, a small d_P
        (0.5 m by default: two legs of one person, not two people; see docs/groups.md)."""
        base = cls(cluster_distance=cluster_distance, split_merge=False)
        return replace(base, **changes) if changes else base  # type: ignore[arg-type]

    def c0(self) -> FloatArray:
        """C_0 (Sec. 4.2.2)."""
        return np.diag(
            np.square(
                [self.sigma_pos, self.sigma_pos, self.sigma_vel, self.sigma_vel, self.sigma_n]
            )
        )

    def confirm_settings(self) -> ConfirmSettings:
        """When a group of the best hypothesis is reported (:mod:`.confirm`)."""
        longest = max(self.confirm_scans, self.confirm_event_scans)
        return ConfirmSettings(
            scans=self.confirm_scans,
            window=self.confirm_window if self.confirm_window > 0 else longest,
            event_scans=self.confirm_event_scans,
        )

    def counting(self) -> SizeCounting:
        """How n_hs counts people (Sec. 4.1)."""
        return SizeCounting(
            self.size_count,
            self.leg_pair_distance,
            self.leg_radius,
            self.leg_width,
            self.person_width,
            self.pair_arc,
            self.surface_gap,
            stride_range=(self.stride_near, self.stride_far),
        )

    def model_settings(self) -> GroupModelSettings:
        """What the track model needs."""
        return GroupModelSettings(
            c0=self.c0(),
            q=np.diag(
                np.square([self.eps_pos, self.eps_pos, self.eps_vel, self.eps_vel, self.eps_n])
            ),
            period=self.period,
            max_dt=self.max_dt,
            r_point=np.eye(2) * self.point_std**2,
            r_update=np.diag(np.square([self.centroid_std, self.centroid_std, self.size_std])),
            gate_sq=chi2_quantile_2dof(self.gate_probability),
            max_gap=self.max_gate_gap,
            log_p_match=math.log(self.p_m),
            rms=self.hausdorff == "rms",
            share_parts=self.share_parts,
            trail_window=self.velocity_window,
            stride_speed=self.stride_speed,
        )

    def interaction_settings(self) -> InteractionSettings:
        """What the model generator needs."""
        return InteractionSettings(
            p_c=self.p_c,
            p_s=self.p_s,
            p_g=self.p_g,
            d_p=self.cluster_distance,
            d_hs=self.blob_distance,
            split_merge=self.split_merge,
            max_models=self.max_models,
            max_events=self.max_events,
            prune_labels=self.prune_labels,
            join_observations=self.join_observations,
            c0=self.c0(),
            model_prior=self.model_prior,
            merge_likelihood=self.merge_likelihood,
            recluster_blobs=self.recluster_blobs,
            counting=self.counting(),
            trail_window=self.velocity_window,
            centroid_std=self.centroid_std,
        )


@dataclass(frozen=True, eq=False)
class GroupEstimate:
    """One reported group of the best hypothesis after a frame.

    Attributes:
        track_id: The track's family (unique over the run; a split or merge starts new ones).
        labels: Its label set.
        mean: State (5,): x, y [m], vx, vy [m/s], n [people].
        cov: Covariance (5, 5).
        members: Frame point indices (K,) of the observation it was matched with this frame
            (empty when occluded).
        contour: Contour (K, 2) [m], absolute.
        event: "split" or "merge" when a model made this track's family, else "".
    """

    track_id: int
    labels: tuple[str, ...]
    mean: FloatArray
    cov: FloatArray
    members: IntArray
    contour: FloatArray
    event: str

    @property
    def size(self) -> float:
        """Estimated number of people n."""
        return float(self.mean[4])


@dataclass(frozen=True)
class GroupEvent:
    """A split or merge in the reported (best) hypothesis, recorded when a group it made
    is first reported (a split once, though it makes two groups).

    Attributes:
        stamp: Time of that report [s].
        kind: "split" or "merge".
        labels: Labels of the group it made (of a split: the first half reported).
    """

    stamp: float
    kind: str
    labels: tuple[str, ...]


class GroupMHTTracker:
    """Group tracker: ``update(frame) -> Tracks`` with ``kind="group"`` tracks carrying the
    size (rounded n), the labels and the contour (absolute) (see the module doc)."""

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})

    def __init__(self, params: GroupTrackerParams | None = None) -> None:
        self.params = params if params is not None else GroupTrackerParams()
        p = self.params
        self.model = GroupModel(p.model_settings())
        self.label_model = GroupLabelModel(
            p.p_m,
            p.p_o,
            p.p_t,
            p.p_n,
            p.p_f,
            p.observation_area or 1.0,
            (p.p_m_shadowed, p.p_o_shadowed, p.p_t_shadowed) if p.shadow_occlusion else None,
            p.shadow_margin,
            p.shadow_hits,
        )
        self.mht: MHT[GroupObservations] = MHT(
            p.mht.with_defaults(min_ratio=GROUP_MIN_RATIO, n_scan=GROUP_N_SCAN),
            self.model,
            self.label_model,
        )
        self.branches = GroupBranches(
            self.model, self.mht.tree, p.interaction_settings(), self.name
        )
        self.mht.branches = self.branches
        # root family -> reported number (roots of live tracks only, see forget_gone)
        self._roots: dict[int, str] = {}
        self._numbered = 0  # root families numbered so far
        self._shown: dict[tuple[str, ...], tuple[str, ...]] = {}  # labels -> display_labels
        self._formatted: dict[tuple[str, ...], str] = {}  # display labels -> format_labels
        self._reported: set[int] = set()  # live families reported (their event recorded)
        self.events: list[GroupEvent] = []
        """The latest splits and merges of the reported hypothesis, oldest first (all of
        them up to :data:`EVENTS_KEPT`; at most twice that many are kept)."""
        self.event_counts: dict[str, int] = {"split": 0, "merge": 0}
        """Splits and merges recorded since the start (all of them, unlike ``events``)."""
        # (kind, split stem or merged labels) -> frame it was last reported in
        self._event_at: dict[tuple[str, tuple[str, ...]], int] = {}
        self.last_stats: StepStats | None = None
        self.last_groups: list[GroupEstimate] = []
        self.last_observations = GroupObservations.empty()
        self._counting = p.counting()
        self.static_model: StaticWorldModel | None = None
        """Asked how long a group's place has been static (the pipeline sets it when
        ``static_groups`` is false; None: every group is reported)."""
        self.wide_points_left_out = 0
        """Foreground points left out of the observations as parts of blobs wider than
        ``max_blob_size``, summed over the frames."""
        self.static_groups_hidden = 0
        """Group-scans not reported because the group sat on a static place, never walked."""
        self.confirmation = Confirmation(p.confirm_settings())
        """Which groups of the best hypothesis are confirmed (``confirm_scans``)."""
        self._scans = 0
        # family -> (time [s], position) of its last walk, or of when it was first tracked
        self._anchors: dict[int, tuple[float, FloatArray]] = {}
        self._walked_at: dict[str, float] = {}  # internal label -> time [s] of its last walk
        self._ids: dict[tuple[str, ...], int] = {}  # internal labels -> id reported for them
        self._last_at: dict[int, FloatArray] = {}  # reported id -> its last position [m]
        self.handover = IdHandover(p.id_memory if p.reuse_ids else 0.0, p.id_gate)
        """Vanished reported ids handed to the groups taking their place (``id_memory``)."""
        self._taken_over: set[int] = set()  # coasting families a new group replaced
        self.coasting = CoastedReports(p.coast_time, p.merged_coast_time)
        """The last reports of vanished groups, reported at their predictions (``coast_time``)."""

    @property
    def counting(self) -> SizeCounting:
        """How the people of an observation are counted (the parameters' counting, at
        torso height without pairs: :meth:`use_torso_height`)."""
        return self._counting

    def use_torso_height(self, torso: bool) -> None:
        """Whether the recording states the laser at torso height (the pipeline tells it,
        :func:`~laserpeople.pipeline.background.set_laser_height`): there, unless
        ``torso_pairs``, the people of a cluster are counted without pairing blobs as legs
        (:class:`~laserpeople.tracking.groups.observations.SizeCounting`)."""
        counting = replace(self.params.counting(), torso=torso and not self.params.torso_pairs)
        self._counting = counting
        self.branches.s = replace(self.branches.s, counting=counting)

    @property
    def wants_static_model(self) -> bool:
        """True when groups on static places are hidden (``static_groups`` false)."""
        return not self.params.static_groups

    static_model_off = "group_tracker.static_groups = true"
    """Why no static world model is wanted, when it is not (for the user)."""

    def use_static_model(self, model: StaticWorldModel | None) -> None:
        """Ask ``model`` how long a group's place has been static (None: none)."""
        self.static_model = model

    def name(self, node: TrackNode) -> tuple[str, ...]:
        """The internal label set of ``node``: a new group is named by its family until it
        is reported (labels made from it by splits keep that root)."""
        labels = group_payload(node).labels
        return labels if labels else (str(node.family),)

    def display_labels(self, labels: tuple[str, ...]) -> tuple[str, ...]:
        """Labels as reported: each root family is numbered 0, 1, ... in the order the
        groups are first reported (000's naming: ``0`` -> ``0-0``, ``0-1`` on a split)."""
        shown = self._shown.get(labels)
        if shown is not None:  # its roots are numbered already; numbers never change
            return shown
        out = []
        for label in labels:
            root, _, rest = label.partition("-")
            number = self._roots.get(int(root))
            if number is None:
                number = self._roots[int(root)] = str(self._numbered)
                self._numbered += 1
            out.append(f"{number}-{rest}" if rest else number)
        if len(self._shown) >= LABEL_MEMO:
            self._shown.clear()
        shown = self._shown[labels] = sort_labels(out)
        return shown

    def observe(self, frame: Frame) -> GroupObservations:
        """The observation clusters of a frame's foreground points (Sec. 4.1)."""
        if frame.points is None or frame.foreground is None:
            raise LaserPeopleError(
                "the group tracker needs the frame's points and foreground mask",
                scan=frame.index,
                hint="run the preprocessing stage (points, background subtraction) first",
            )
        fg = np.asarray(frame.foreground, dtype=bool)
        if fg.shape != (len(frame.points),):
            raise LaserPeopleError(
                f"foreground mask of {fg.size} values for {len(frame.points)} points",
                scan=frame.index,
                hint="the mask must have one value per point of frame.points",
            )
        idx = np.nonzero(fg)[0].astype(np.int64)
        pts = frame.points.points[idx]
        finite = np.isfinite(pts).all(axis=1)
        if not finite.all():
            pts, idx = pts[finite], idx[finite]
        p = self.params
        spacing = beam_spacing(frame, idx) if p.size_count == "resolved" else None
        obs = GroupObservations.from_points(
            pts, idx, p.cluster_distance, p.blob_distance, self._counting, p.max_blob_size, spacing
        )
        self.wide_points_left_out += len(pts) - len(obs.points)
        return obs

    @staticmethod
    def _visible_area(frame: Frame) -> float:
        """V of eqs. 36-37 for ``observation_area`` 0: the area [m^2] the frame's lasers saw
        (the sum over its scans)."""
        area = sum(visible_area(scan) for scan in frame.scans)
        if not area > 0.0:
            raise LaserPeopleError(
                "the group tracker's observation_area 0 needs the area the lasers saw, and "
                f"this frame has {len(frame.scans)} scans with no valid return",
                scan=frame.index,
                hint="set [group_tracker] observation_area to the field of view in m^2",
            )
        return area

    def update(self, frame: Frame) -> Tracks:
        """Track one frame."""
        obs = self.observe(frame)
        self.last_observations = obs
        if self.params.observation_area == 0.0:
            self.label_model.area = self._visible_area(frame)
        if self.params.shadow_occlusion:
            self.label_model.shadows = FrameShadows.from_frame(frame)
            self.label_model.stamp = frame.stamp
        self.branches.begin_scan(obs, frame.stamp)
        self.model.scan = obs
        self.last_stats = self.mht.step(obs, frame.stamp)
        probs = self.mht.best_probabilities()
        groups: list[GroupEstimate] = []
        tracks: list[Track] = []
        best = self.mht.best_tracks()
        nodes = self._confirmed(best, frame.stamp)
        ids = self._reported_ids(nodes, frame.stamp)
        for node, track_id in zip(nodes, ids, strict=True):
            payload = group_payload(node)
            labels = self.display_labels(self.name(node))
            contour = payload.contour + node.mean[:2]
            members = payload.members  # empty when occluded (coasted)
            groups.append(
                GroupEstimate(
                    node.family, labels, node.mean, node.cov, members, contour, payload.event
                )
            )
            if node.family not in self._reported:
                self._reported.add(node.family)
                if payload.event:
                    self._record(GroupEvent(frame.stamp, payload.event, labels), frame.index)
            tracks.append(
                Track(
                    track_id=track_id,
                    kind="group",
                    position=node.mean[:2],
                    velocity=node.mean[2:4],
                    covariance=node.cov[:2, :2],
                    size=max(1, round(float(node.mean[4]))),
                    labels=self._format(labels),
                    score=probs.get(node.family, 1.0),
                    contour=contour,
                )
            )
        self.last_groups = groups
        if self.coasting.memory > 0.0:
            shown = {node.family for node in nodes}
            hidden = {self._ids.get(self.name(n), n.family) for n in best if n.family not in shown}
            coasted = self.coasting.coasted(
                frame.stamp,
                set(ids) | hidden,
                self._seen_gone(frame),
                self._among(frame, groups),
            )
            self.coasting.record(frame.stamp, tracks)
            tracks += coasted
        self._reported.intersection_update(self.mht.tree.nodes_by_family)
        if self._scans % FORGET_EVERY == 0:
            self.forget_gone(frame.index)
        return Tracks(frame.stamp, frame.index, tuple(tracks), frame.frame, frame.sensor_pose)

    def _among(self, frame: Frame, groups: list[GroupEstimate]) -> Callable[[Track], bool]:
        """Whether a coasted group is among the points of the groups reported in ``frame``
        (``merged_coast_time``): a point of its predicted contour (its position, without a
        contour) within ``blob_distance`` of one of their points."""
        assert frame.points is not None
        seen = [g.members for g in groups if g.members.size]
        points = frame.points.points[np.concatenate(seen)] if seen else np.empty((0, 2))
        reach = self.params.blob_distance

        def among(track: Track) -> bool:
            if not len(points):
                return False
            mine = track.contour if len(track.contour) else track.position[None, :]
            d2 = np.sum((mine[:, None, :] - points[None, :, :]) ** 2, axis=2)
            return bool(d2.min() <= reach * reach)

        return among

    def _seen_gone(self, frame: Frame) -> Callable[[Track], bool] | None:
        """Whether ``frame``'s scans saw past every point of a coasted group's predicted
        contour (or its position, without a contour) by more than ``shadow_margin``; None
        when the scans' poses are unknown."""
        shadows = self.label_model.shadows
        if not self.params.shadow_occlusion:
            shadows = FrameShadows.from_frame(frame)
        if shadows is None:
            return None
        margin = self.params.shadow_margin
        seen = shadows

        def gone(track: Track) -> bool:
            points = track.contour if len(track.contour) else track.position[None, :]
            return seen.seen_empty(points, margin)

        return gone

    def _reported_ids(self, nodes: list[TrackNode], stamp: float) -> list[int]:
        """The id each of ``nodes`` is reported with: its family, or with ``reuse_ids`` the
        id of the group reported before with the same internal labels (a split group whose
        parts merged back: ``0`` -> ``0-0``, ``0-1`` -> ``0``), unless another node of this
        scan has that id; the two halves of a split keep their ids by position
        (:meth:`_follow_halves`); a group whose labels were never reported may take the
        id of a group that vanished near it (``id_memory``, :mod:`.handover`)."""
        if not self.params.reuse_ids:
            return [node.family for node in nodes]
        keys = [self.name(node) for node in nodes]
        out: list[int] = []
        taken: set[int] = set()
        # a node that keeps its own id first, so that a merged-back group never takes it
        for node, key in zip(nodes, keys, strict=True):
            if self._ids.get(key, node.family) == node.family:
                taken.add(node.family)
        fresh: list[int] = []  # nodes whose labels were never reported
        for k, (node, key) in enumerate(zip(nodes, keys, strict=True)):
            track_id = self._ids.get(key)
            if track_id is None:
                if len(self._ids) >= LABEL_MEMO:  # a bound for pathological runs only
                    self._ids = {x: self._ids[x] for x in keys if x in self._ids}
                track_id = self._ids[key] = node.family
                fresh.append(k)
            elif track_id != node.family and track_id in taken:
                track_id = node.family
            taken.add(track_id)
            out.append(track_id)
        handed = self.handover.hand_over(stamp, [nodes[k].mean[:2] for k in fresh], set(out))
        inherited: set[int] = set()  # nodes that took a vanished group's id
        for k, track_id in zip(fresh, handed, strict=True):
            if track_id is not None:
                out[k] = self._ids[keys[k]] = track_id
                inherited.add(k)
        self._follow_halves(nodes, keys, out, inherited)
        self._last_at.update((i, node.mean[:2]) for i, node in zip(out, nodes, strict=True))
        self.handover.record(stamp, out, [node.mean for node in nodes])
        return out

    def _follow_halves(
        self,
        nodes: list[TrackNode],
        keys: list[tuple[str, ...]],
        ids: list[int],
        handed: set[int],
    ) -> None:
        """Give the two halves of one split (labels ``X-0`` and ``X-1``, both reported this
        scan) their ids by where those ids were last reported (in place in ``ids``, and in
        the labels -> id memory for later scans).

        The halves of a split start as two copies of one prediction (000 Sec. 4.2.3), so the
        hypotheses that give observation A to ``X-0`` and B to ``X-1`` or the other way round
        are equally likely; which one is best flips with the next scans' data, and so would
        the ids, at every split and again when the halves split anew after merging back.
        Each id stays with the half nearer to where it was last seen; a half whose id has not
        been reported yet keeps its own."""
        pairs: dict[tuple[str, ...], list[int]] = {}
        for i, key in enumerate(keys):
            ends = {label.rpartition("-")[2] for label in key}
            if len(ends) == 1 and all("-" in label for label in key):
                stem = tuple(label.rpartition("-")[0] for label in key)
                pairs.setdefault(stem, [-1, -1])[int(ends.pop()) & 1] = i
        for a, b in pairs.values():
            if a < 0 or b < 0 or a in handed or b in handed:
                continue
            at_a, at_b = self._last_at.get(ids[a]), self._last_at.get(ids[b])
            if at_a is None or at_b is None:
                continue
            pa, pb = nodes[a].mean[:2], nodes[b].mean[:2]
            kept = math.dist(pa, at_a) ** 2 + math.dist(pb, at_b) ** 2
            swapped = math.dist(pa, at_b) ** 2 + math.dist(pb, at_a) ** 2
            if swapped < kept:
                ids[a], ids[b] = ids[b], ids[a]
                self._ids[keys[a]], self._ids[keys[b]] = ids[a], ids[b]

    @property
    def unconfirmed_groups_withheld(self) -> int:
        """Group-scans not reported because their group was not confirmed yet
        (``confirm_scans``; groups hidden on static places are not counted here)."""
        return self.confirmation.withheld

    def _confirmed(self, nodes: list[TrackNode], stamp: float) -> list[TrackNode]:
        """The groups of the best hypothesis ``nodes`` that are reported: not on a static
        place (:meth:`_off_static_places`, when a static world model is set) and
        confirmed (:mod:`.confirm`; every group counts as present, hidden or not)."""
        shown = nodes if self.static_model is None else self._off_static_places(nodes, stamp)
        visible = {node.family for node in shown}
        candidates = [
            Candidate(n.family, group_payload(n).event, self.name(n), n.family in visible)
            for n in nodes
        ]
        if self.handover.memory > 0.0:
            for node, c in zip(nodes, candidates, strict=True):
                new = not c.event and not self.confirmation.is_confirmed(c.family)
                if new and self.handover.near_vanished(stamp, node.mean[:2]):
                    self.confirmation.confirm(c.family)
            candidates = self._take_over_coasting(nodes, candidates)
        self._scans += 1
        keep = self.confirmation.select(self._scans, candidates)
        return [node for node, k in zip(nodes, keep, strict=True) if k]

    def _take_over_coasting(
        self, nodes: list[TrackNode], candidates: list[Candidate]
    ) -> list[Candidate]:
        """A new group seen within ``take_over_distance`` of a reported group that is coasting
        (unseen this scan) takes its place: the new group is confirmed at once and the
        coasting one is not reported any more (its id goes to the new one, :mod:`.handover`);
        the candidates with those hidden."""
        gate = self.params.take_over_distance
        coasting = [
            k
            for k, (n, c) in enumerate(zip(nodes, candidates, strict=True))
            if c.visible
            and self.confirmation.is_confirmed(c.family)
            and group_payload(n).members.size == 0
            and c.family not in self._taken_over
        ]
        for node, c in zip(nodes, candidates, strict=True):
            if c.event or self.confirmation.is_confirmed(c.family):
                continue
            if group_payload(node).members.size == 0 or not coasting:
                continue
            d = [math.dist(node.mean[:2], nodes[k].mean[:2]) for k in coasting]
            nearest = int(np.argmin(d))
            if d[nearest] <= gate:
                self.confirmation.confirm(c.family)
                self._taken_over.add(nodes[coasting.pop(nearest)].family)
                if not coasting:
                    break
        if not self._taken_over:
            return candidates
        gone = self._taken_over
        return [replace(c, visible=False) if c.family in gone else c for c in candidates]

    def _off_static_places(self, nodes: list[TrackNode], stamp: float) -> list[TrackNode]:
        """``nodes`` without the groups on static places (counted in
        :attr:`static_groups_hidden`).

        A group *walks* when it is ``min_travel`` from where it last walked (or was first
        tracked); the walk of a group of one label is that label's last walk (a merged
        group's centroid also moves as members come and go). Of a group's labels, and the
        labels they came from by splits (:meth:`_walks`), the latest last walk tells
        whether someone in it walked lately, the earliest since when it has stood. A group
        is hidden when nobody in it walked within ``static_time`` and at least
        ``static_share`` of its contour lies on places static for longer than
        ``static_time`` and longer than it has stood there (plus ``arrival_slack``). A
        group that walked in and stands is therefore kept, and so is the half of a group
        that holds something static (a person who walked past it, then on) until
        ``static_time`` after the person's last walk."""
        assert self.static_model is not None
        p = self.params
        anchors: dict[int, tuple[float, FloatArray]] = {}
        asked: list[tuple[TrackNode, float]] = []
        for node in nodes:
            position = node.mean[:2]
            anchor = anchors[node.family] = self._anchors.get(node.family, (stamp, position))
            labels = self.name(node)
            if math.dist(position, anchor[1]) >= p.min_travel:
                anchors[node.family] = (stamp, position)
                if len(labels) == 1:
                    self._walked_at[labels[0]] = stamp
            earliest, latest = self._walks(labels)
            if stamp - latest >= p.static_time:
                stood = stamp - earliest + p.arrival_slack if earliest > -math.inf else 0.0
                asked.append((node, max(p.static_time, stood)))
        self._anchors = anchors
        contours = [group_payload(node).contour + node.mean[:2] for node, _ in asked]
        if not contours:
            return nodes
        static = self.static_model.static_time(np.concatenate(contours))
        hidden: set[int] = set()
        end = 0
        for (node, limit), contour in zip(asked, contours, strict=True):
            end += len(contour)
            on_static = np.count_nonzero(static[end - len(contour) : end] > limit)
            if len(contour) and on_static >= p.static_share * len(contour):
                hidden.add(node.family)
        self.static_groups_hidden += len(hidden)
        return [node for node in nodes if node.family not in hidden]

    def forget_gone(self, index: int) -> None:
        """Forget what only tracks gone from every hypothesis could ask (called every
        :data:`FORGET_EVERY` scans; ``index`` is the frame index of now): reported families,
        numbers of roots no live track's labels hold, last walks of labels and reported ids
        of label sets that are neither a live track's nor stems of one, the label memos of
        sets no live track carries (pure functions of the set and the root numbers, computed
        again if needed) and the events recorded more than N-scan-back frames ago. Family
        ids are never reused, and the labels of every future track are its new family or
        come from the labels of tracks alive now (a split appends ``-0``/``-1``, a merge
        unites two sets and prunes ``X-0``, ``X-1`` to their stem ``X``), so the output is
        the same as with everything kept; the memory is bounded by the live tracks instead
        of growing with the length of the run."""
        live = [n for nodes in self.mht.tree.nodes_by_family.values() for n in nodes]
        names = {self.name(node) for node in live}
        labels = {label for name in names for label in name}
        roots = {int(label.partition("-")[0]) for label in labels}
        self._roots = {r: k for r, k in self._roots.items() if r in roots}
        self._shown = {k: v for k, v in self._shown.items() if k in names}
        shown = set(self._shown.values())
        self._formatted = {k: v for k, v in self._formatted.items() if k in shown}
        self.confirmation.prune(self.mht.tree.nodes_by_family, {str(r) for r in roots})
        self._taken_over.intersection_update(self.mht.tree.nodes_by_family)
        self.branches.forget_gone(names)
        stems = {stem for label in labels for stem in _stems(label)}
        if self._walked_at:  # a label's walk counts for the labels split from it
            self._walked_at = {k: t for k, t in self._walked_at.items() if k in stems}
        # a label set comes back only from its live parts merging back
        self._ids = {k: i for k, i in self._ids.items() if all(x in stems for x in k)}
        kept = set(self._ids.values())
        self._last_at = {i: at for i, at in self._last_at.items() if i in kept}
        n_scan = self.mht.params.depth
        self._event_at = {k: i for k, i in self._event_at.items() if 0 <= index - i <= n_scan}

    def state_counts(self) -> dict[str, int]:
        """Sizes of what the tracker keeps from scan to scan (for soak runs and tests):
        live track nodes and families, hypotheses, and the bookkeeping
        :meth:`forget_gone` bounds."""
        stats = self.last_stats
        return {
            "nodes": self.mht.tree.n_nodes,
            "families": self.mht.tree.n_families,
            "hypotheses": 0 if stats is None else stats.n_hypotheses,
            "reported": len(self._reported),
            "roots": len(self._roots),
            "shown": len(self._shown),
            "formatted": len(self._formatted),
            "event_at": len(self._event_at),
            "events": len(self.events),
            "walked_at": len(self._walked_at),
            "reported_ids": len(self._ids),
            "last_positions": len(self._last_at),
            "anchors": len(self._anchors),
            "taken_over": len(self._taken_over),
            "handover": len(self.handover),
            "coasting": len(self.coasting),
            "merged_labels": self.branches.memo_size,
            **self.confirmation.sizes(),
        }

    def _walks(self, labels: tuple[str, ...]) -> tuple[float, float]:
        """(earliest, latest) over ``labels`` of a label's last walk [s]: its own or that
        of a label it came from by splits (its stems, ``3-0-1`` -> ``3-0``, ``3``); labels
        that never walked are left out, and both are -inf when none walked."""
        walks = []
        for label in labels:
            last = max(self._walked_at.get(stem, -math.inf) for stem in _stems(label))
            if last > -math.inf:
                walks.append(last)
        return (min(walks), max(walks)) if walks else (-math.inf, -math.inf)

    def _format(self, labels: tuple[str, ...]) -> str:
        """:func:`format_labels`, remembered."""
        text = self._formatted.get(labels)
        if text is None:
            if len(self._formatted) >= LABEL_MEMO:
                self._formatted.clear()
            text = self._formatted[labels] = format_labels(labels)
        return text

    def _record(self, event: GroupEvent, index: int = -1) -> None:
        """Append ``event`` unless it is the second half of a split already recorded at
        this stamp (the halves X-0 and X-1 of one split share the stem X), or a split of
        the same stem (a merge of the same labels) recorded at most N-scan-back scans
        before (frame ``index``): the reported hypothesis changed its mind about the scan
        of one event."""
        key = (event.kind, event.labels)
        if event.kind == "split":
            stem = tuple(label.rsplit("-", 1)[0] for label in event.labels)
            for e in reversed(self.events):
                if e.stamp != event.stamp:
                    break
                if e.kind == "split" and tuple(x.rsplit("-", 1)[0] for x in e.labels) == stem:
                    return
            key = ("split", stem)
        last = self._event_at.get(key)
        self._event_at[key] = index
        if last is not None and 0 <= index - last <= self.mht.params.depth:
            return
        self.events.append(event)
        if len(self.events) > 2 * EVENTS_KEPT:
            del self.events[:-EVENTS_KEPT]
        self.event_counts[event.kind] = self.event_counts.get(event.kind, 0) + 1

    def point_labels(self, n_points: int) -> IntArray:
        """Group (track id) of each of the last frame's ``n_points`` points, -1 outside
        every reported group observed this frame (for the clustering error, 000 Sec. 4.6.1;
        the points of a group not reported yet are in none)."""
        out = np.full(n_points, -1, dtype=np.int64)
        for g in self.last_groups:
            out[g.members] = g.track_id
        return out

    @property
    def n_hypotheses(self) -> int:
        """Hypotheses after the last frame, summed over clusters."""
        return 0 if self.last_stats is None else self.last_stats.n_hypotheses


def beam_spacing(frame: Frame, idx: IntArray) -> FloatArray | None:
    """Beam spacing [m] (range x angular step of its scan) at the frame points ``idx``
    (K,); None when the frame does not carry the scans its points came from."""
    assert frame.points is not None
    points = frame.points
    scans = {scan.sensor: scan for scan in frame.scans}
    out = np.empty(idx.size)
    sensor = points.sensor_ids[idx]
    beams = points.beams[idx]
    for s in np.unique(sensor):
        scan = scans.get(points.sensors[int(s)])
        if scan is None:
            return None
        here = sensor == s
        out[here] = scan.ranges[beams[here]] * abs(scan.angle_increment)
    return out


def _stems(label: str) -> list[str]:
    """``label`` and the labels it came from by splits: ``3-0-1`` -> ``3-0-1``, ``3-0``,
    ``3``."""
    parts = label.split("-")
    return ["-".join(parts[:k]) for k in range(len(parts), 0, -1)]


__all__ = [
    "GroupEstimate",
    "GroupEvent",
    "GroupMHTTracker",
    "GroupTrackerParams",
]
