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

Modules: :mod:`.params` (the parameters), :mod:`.viterbi` (the VBA step and its paths),
:mod:`.clusters` (merges, sub-clusters, splits, person-sized groups, walls),
:mod:`.tracker` (the tracker), :mod:`.leg_people` (the leg MHT's people on a moving laser).
"""

from laserpeople.tracking.csa.clusters import (
    gate_components,
    leader_clusters,
    on_a_wall,
    person_groups,
    split_ready,
)
from laserpeople.tracking.csa.params import CSAParams
from laserpeople.tracking.csa.tracker import ClusterSortingTracker, CSAEvent
from laserpeople.tracking.csa.viterbi import (
    ViterbiStep,
    coast_people,
    per_person_scores,
    person_first,
    viterbi_step,
)

__all__ = [
    "CSAEvent",
    "CSAParams",
    "ClusterSortingTracker",
    "ViterbiStep",
    "coast_people",
    "gate_components",
    "leader_clusters",
    "on_a_wall",
    "per_person_scores",
    "person_first",
    "person_groups",
    "split_ready",
    "viterbi_step",
]
