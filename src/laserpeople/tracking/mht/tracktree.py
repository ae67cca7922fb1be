"""The track tree of the MHT (Cox & Hingorani 1996): every track estimate is stored once.

A *family* is one track identity (one leg, one group) from its birth. Each scan, every live
:class:`TrackNode` of a family branches into at most one child per label it is given by any
hypothesis: one child per measurement it is matched with, one occluded child; deletion
creates no child. The children are cached on the parent node, so hypotheses that give a
track the same label share the same child object instead of duplicating the filter work.

Nodes do not reference their parents, only their ids: a node lives as long as a hypothesis
refers to it, so the tree is garbage-collected with the hypotheses and memory stays bounded
however long the recording. :class:`TrackTree` keeps the per-family index of the live nodes.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Hashable, Iterable
from dataclasses import dataclass, field
from operator import attrgetter
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

NEW, DETECTED, OCCLUDED = "new", "detected", "occluded"


@dataclass(eq=False, slots=True)
class TrackNode:
    """One track estimate at one scan, shared by every hypothesis that contains it.

    Attributes:
        node_id: Unique id of this node.
        family: Track identity (constant from birth to deletion).
        parent_id: ``node_id`` of the node it was derived from (-1 at birth).
        mean: State (D,) after this scan, e.g. (x, y, vx, vy) [m, m/s].
        cov: State covariance (D, D).
        stamp: Time of the state [s].
        label: How this node came about: "new", "detected" or "occluded".
        measurement: Index of the measurement that created/updated it (-1 if occluded).
        hits: Number of scans the family was detected (including birth).
        misses: Consecutive scans without detection.
        detected_stamp: Time [s] of the family's last detection (or birth); NaN (the
            default) means ``stamp``.
        age: Scans since birth.
        loglik: log N(z; z_hat, S) of the update that produced it (0 for new/occluded).
        payload: Model-specific data (a group's contour and labels, ...).
        pred_mean: Predicted state for the scan being processed (set by the model).
        pred_cov: Predicted covariance for the scan being processed.
        children: Cache of the children made this scan, keyed by measurement index (or -1
            for the occluded child; or a model's key of its own observation).
    """

    node_id: int
    family: int
    parent_id: int
    mean: FloatArray
    cov: FloatArray
    stamp: float
    label: str
    measurement: int = -1
    hits: int = 1
    misses: int = 0
    age: int = 0
    loglik: float = 0.0
    payload: Any = None
    pred_mean: FloatArray | None = None
    pred_cov: FloatArray | None = None
    children: dict[Hashable, TrackNode] = field(default_factory=dict)
    detected_stamp: float = math.nan

    def __post_init__(self) -> None:
        if math.isnan(self.detected_stamp):
            self.detected_stamp = self.stamp

    def unseen_for(self, stamp: float) -> float:
        """Time [s] from the family's last detection to ``stamp``."""
        return stamp - self.detected_stamp


BY_FAMILY = attrgetter("family")
"""Sort key of track nodes by family (no Python-level call per node)."""


class TrackTree:
    """Allocates node and family ids and indexes the live nodes by family."""

    def __init__(self) -> None:
        self._node_ids = itertools.count()
        self.new_node_id: Callable[[], int] = self._node_ids.__next__
        """A fresh node id (the counter's own ``__next__``: no Python call per node)."""
        self._family_ids = itertools.count()
        self.nodes_by_family: dict[int, list[TrackNode]] = {}
        self.families_created = 0

    def new_family(self) -> int:
        """A fresh track identity."""
        self.families_created += 1
        return next(self._family_ids)

    def collect(self, live: Iterable[TrackNode]) -> None:
        """Rebuild the index from the nodes still referred to by a hypothesis; everything
        else is dropped (and freed by reference counting). Clears the children caches."""
        index: dict[int, list[TrackNode]] = {}
        for node in live:
            node.children.clear()
            node.pred_mean = None
            node.pred_cov = None
            index.setdefault(node.family, []).append(node)
        self.nodes_by_family = index

    @property
    def n_nodes(self) -> int:
        """Number of live nodes."""
        return sum(len(v) for v in self.nodes_by_family.values())

    @property
    def n_families(self) -> int:
        """Number of live families."""
        return len(self.nodes_by_family)
