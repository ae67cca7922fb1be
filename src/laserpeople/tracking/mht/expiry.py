"""Deletion of tracks unseen for long: the deletion mass that N-scan-back pruning throws away.

With the label probabilities of 000 eqs. 8-10 a track that is not detected for ``m``
consecutive scans is, in the full hypothesis tree, either still there (occluded ``m`` times,
probability ``p_occ^m``) or was deleted at one of those scans (``p_occ^(k-1) p_del`` for the
k-th). Every deletion gives the same content (the track is absent), so their sum is the
probability of the deleted interpretation, and the odds of the track still existing are

    odds(m) = p_occ^m / (p_del (1 + p_occ + ... + p_occ^(m-1)))
            = p_occ^m (1 - p_occ) / (p_del (1 - p_occ^m)),

falling geometrically with ``m``. N-scan-back pruning keeps, however, only the branch with
the most mass ``N`` scans back, which is the occluded one: the deletions older than ``N``
scans are cut off, the odds never fall below about ``p_occ / (N p_del)`` and a track that
left the view (an approved leg: 0.79 / (8 x 0.01) ~ 10) lives on for ever, its cluster,
nodes and hypotheses with it (issue 16: live families and cycle time grew without bound on
streamed scenes). :func:`expired` applies the deletion the pruning cut off: a node whose
odds fell below the ratio-pruning threshold (a hypothesis that improbable would have been
ratio-pruned) is removed from every hypothesis, and :func:`drop_nodes` merges the
hypotheses that become equal.

With 000 Table 10 and a ratio of 1e-3 a free leg goes after 19 unseen scans, an approved
leg after 43 (4.3 s at 10 Hz, 1.1 s at the 37.5 Hz of 000).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.mht.hypothesis import Cluster, Hypothesis, normalise_hypotheses
from laserpeople.tracking.mht.probability import DELETED, OCCLUDED
from laserpeople.tracking.mht.tracktree import TrackNode

FloatArray = NDArray[np.float64]


def log_existence_odds(misses: FloatArray, log_probs: FloatArray) -> FloatArray:
    """log odds (m,) that a track unseen for ``misses`` (m,) consecutive scans still exists,
    given its label log probabilities ``log_probs`` (m, 3) (module doc; ``+inf`` at 0
    misses)."""
    m = np.asarray(misses, dtype=np.float64)
    log_occ = log_probs[:, OCCLUDED]
    log_del = log_probs[:, DELETED]
    p_occ = np.exp(log_occ)
    with np.errstate(divide="ignore"):
        # log(1 - p_occ^m) via log(-expm1(m log p_occ)); -inf at m = 0 gives odds +inf
        log_lost = np.log(-np.expm1(m * log_occ))
    return m * log_occ + np.log1p(-p_occ) - log_del - log_lost


def max_misses(p_occ: float, p_del: float, ratio: float) -> float:
    """Consecutive unseen scans after which a track of this class is deleted (the smallest
    ``m`` with odds(m) < ratio): odds(m) < r  <=>  p_occ^m < r p_del / (1 - p_occ + r p_del).
    """
    if ratio <= 0:
        return math.inf
    bound = ratio * p_del / (1.0 - p_occ + ratio * p_del)
    return float(math.floor(math.log(bound) / math.log(p_occ)) + 1)


def expired(nodes: Sequence[TrackNode], log_probs: FloatArray, log_ratio: float) -> set[int]:
    """Ids of the nodes whose existence odds fell below ``exp(log_ratio)``."""
    misses = np.fromiter((n.misses for n in nodes), dtype=np.float64, count=len(nodes))
    if not np.any(misses > 0):
        return set()
    odds = log_existence_odds(misses, log_probs)
    return {n.node_id for n, o in zip(nodes, odds.tolist(), strict=True) if o < log_ratio}


class ExpiryOdds:
    """:func:`expired` with its log odds remembered per (label log probabilities of
    occluded and deleted, misses): the odds depend on nothing else, so a tracker asks
    :func:`log_existence_odds` only for pairs it has not met (a few dozen over a run)
    instead of a dozen numpy calls per scan. Each value is computed by the same function
    (element by element the same floats), so the nodes that expire are the same.

    Args:
        limit: Remembered pairs at most (the table is emptied when full).
    """

    def __init__(self, limit: int = 4096) -> None:
        self.limit = limit
        self._odds: dict[tuple[float, float, int], float] = {}

    def __len__(self) -> int:
        return len(self._odds)

    def expired(
        self, nodes: Sequence[TrackNode], log_probs: FloatArray, log_ratio: float
    ) -> set[int]:
        """:func:`expired` of ``nodes`` with label log probabilities ``log_probs`` (n, 3)."""
        rows = log_probs.tolist()
        keys = [(r[OCCLUDED], r[DELETED], n.misses) for n, r in zip(nodes, rows, strict=True)]
        table = self._odds
        try:  # (the usual call: every pair met before, none at 0 misses: one pass)
            return {n.node_id for n, k in zip(nodes, keys, strict=True) if table[k] < log_ratio}
        except KeyError:  # (a pair not met yet, or 0 misses, which is never in the table)
            pass
        new = list(dict.fromkeys(k for k in keys if k[2] > 0 and k not in table))
        if new:
            if len(table) + len(new) > self.limit:  # full: start afresh with this call's
                table.clear()
                new = list(dict.fromkeys(k for k in keys if k[2] > 0))
            probs = np.zeros((len(new), 3))
            probs[:, OCCLUDED] = [k[0] for k in new]
            probs[:, DELETED] = [k[1] for k in new]
            misses = np.array([k[2] for k in new], dtype=np.float64)
            table.update(zip(new, log_existence_odds(misses, probs).tolist(), strict=True))
        return {
            n.node_id for n, k in zip(nodes, keys, strict=True) if k[2] > 0 and table[k] < log_ratio
        }


def drop_nodes(cluster: Cluster, gone: set[int]) -> Cluster | None:
    """``cluster`` without the nodes ``gone``: hypotheses that become equal are merged
    (probabilities added, the more probable one's history kept); None when no family is
    left."""
    merged: dict[tuple[int, ...], Hypothesis] = {}
    for h in cluster.hypotheses:  # best first
        tracks = tuple(t for t in h.tracks if t.node_id not in gone)
        key = tuple(t.node_id for t in tracks)
        if key in merged:
            m = merged[key]
            m.log_weight = float(np.logaddexp(m.log_weight, h.log_weight))
        elif len(tracks) == len(h.tracks):
            merged[key] = h
        else:
            merged[key] = Hypothesis(h.log_weight, tracks, h.ancestors, model=h.model)
    hyps = normalise_hypotheses(list(merged.values()))
    families = frozenset(t.family for h in hyps for t in h.tracks)
    if not families:
        return None
    return Cluster(families, hyps)
