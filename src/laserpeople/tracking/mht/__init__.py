"""Multi-hypothesis tracking core (000 Secs. 3.2-3.3.2 and 4.5; Reid 1979; Cox & Hingorani
1996): a track tree that stores every track estimate once, hypotheses over clusters of
interacting tracks, assignment matrices with the labels detected/occluded/deleted and
matched/new/false alarm, probabilities by 000 eq. 15 in log space, multi-parent Murty k-best
branching, ratio and N-scan-back pruning, and a model-branch hook for multi-model trackers.

The parts to plug in are in :mod:`~laserpeople.tracking.mht.protocols`: a
:class:`~laserpeople.tracking.mht.protocols.TrackModel` (prediction, gating, update), a
:class:`~laserpeople.tracking.mht.protocols.LabelModel` (label probabilities) and optionally a
:class:`~laserpeople.tracking.mht.protocols.BranchGenerator` (models such as split/merge).
"""

from laserpeople.tracking.mht.core import MHT, MHTParams, StepStats
from laserpeople.tracking.mht.hypothesis import (
    Cluster,
    Hypothesis,
    n_scan_prune,
    normalise_hypotheses,
    ratio_prune,
)
from laserpeople.tracking.mht.matrix import AssignmentMatrix, build_matrix, k_best_children
from laserpeople.tracking.mht.probability import LabelProbabilities, log_child_weight
from laserpeople.tracking.mht.protocols import (
    Branch,
    BranchGenerator,
    LabelModel,
    SingleModel,
    TrackModel,
)
from laserpeople.tracking.mht.tracktree import TrackNode, TrackTree

__all__ = [
    "MHT",
    "AssignmentMatrix",
    "Branch",
    "BranchGenerator",
    "Cluster",
    "Hypothesis",
    "LabelModel",
    "LabelProbabilities",
    "MHTParams",
    "SingleModel",
    "StepStats",
    "TrackModel",
    "TrackNode",
    "TrackTree",
    "build_matrix",
    "k_best_children",
    "log_child_weight",
    "n_scan_prune",
    "normalise_hypotheses",
    "ratio_prune",
]
