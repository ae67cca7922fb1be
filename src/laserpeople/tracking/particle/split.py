"""Splitting a feet filter that stands on two people (a departure from 004, whose filters
never split).

In a party (people 0.5-0.8 m apart) at 10-20 Hz the merge -> split of one person's leg
with a neighbour's leg can refresh a filter onto both: one foot on each person, the
filter between them, and the birth exclusion then keeps a filter from starting on either.
Such a filter's Voronoi cell holds two person-sized blobs that stay apart, while a single
walker's two legs come together at every step (twice per gait period).
:class:`PartySplitter` follows, per filter, how long its cell has held two such blobs and
reports the filters to split: the filter keeps the blob nearer its predicted feet
midpoint, and a new filter starts on the other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import cluster_covariances, single_linkage
from laserpeople.tracking.particle.objects import largest_eigenvalue, two_feet

if TYPE_CHECKING:
    from laserpeople.tracking.particle.feet import FeetParams


def two_people(
    points: NDArray[np.float64],
    link: float,
    min_points: int,
    max_eigenvalue: float,
    distance: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """The two largest blobs (single linkage at ``link`` [m]) of ``points`` (N, 2) [m]
    that are person-sized (at least ``min_points`` points, covariance's largest
    eigenvalue at most ``max_eigenvalue`` [m^2]), as their points (K, 2) and (L, 2), if
    their centres lie more than ``distance`` [m] apart; else None."""
    if len(points) < 2 * min_points:
        return None
    labels = single_linkage(points, link)
    n = int(labels.max()) + 1
    mean, cov, count = cluster_covariances(points, labels, n)
    ok = (count >= min_points) & (largest_eigenvalue(cov) <= max_eigenvalue)
    good = np.flatnonzero(ok)
    if len(good) < 2:
        return None
    a, b = good[np.argsort(-count[good], kind="stable")[:2]]
    if float(np.hypot(*(mean[a] - mean[b]))) <= distance:
        return None
    return points[labels == a], points[labels == b]


@dataclass(frozen=True)
class Split:
    """A filter to split: its index, the feet (2, 2) [m] it keeps and the feet (2, 2) [m]
    a new filter starts from."""

    filter: int
    keep: NDArray[np.float64]
    new: NDArray[np.float64]


class PartySplitter:
    """Per filter (by identity), the stamp since which its cell holds two person-sized
    blobs more than ``split_distance`` apart (:func:`two_people`); a filter whose cell
    has held them for ``split_time`` is split."""

    def __init__(self, params: FeetParams) -> None:
        self.params = params
        self._since: dict[int, float] = {}

    def splits(
        self,
        points: NDArray[np.float64],
        owner: NDArray[np.int64],
        ids: NDArray[np.int64],
        est: NDArray[np.float64],
        stamp: float,
    ) -> list[Split]:
        """The splits due at ``stamp`` [s] given the cell points ``points`` (N, 2) [m]
        of filter ``owner`` (N,), the filters' identities ``ids`` (F,) and their
        predicted feet midpoints ``est`` (F, 2) [m]."""
        p = self.params
        since: dict[int, float] = {}
        out: list[Split] = []
        for f in np.unique(owner):
            pair = two_people(
                points[owner == f],
                p.split_link,
                p.blob_leg_points,
                p.still_eigenvalue,
                p.split_distance,
            )
            if pair is None:
                continue
            key = int(ids[f])
            first = self._since.get(key, stamp)
            if stamp - first < p.split_time:
                since[key] = first
                continue
            feet = [_feet(blob) for blob in pair]
            d = [float(np.hypot(*(ft.mean(axis=0) - est[f]))) for ft in feet]
            k = int(np.argmin(d))
            out.append(Split(int(f), feet[k], feet[1 - k]))
        self._since = since
        return out


def _feet(blob: NDArray[np.float64]) -> NDArray[np.float64]:
    """The two feet (2, 2) [m] of a blob's points (K, 2) (:func:`two_feet`)."""
    mean, cov, _ = cluster_covariances(blob, np.zeros(len(blob), dtype=np.int64), 1)
    return two_feet(blob, mean[0], cov[0])


__all__ = ["PartySplitter", "Split", "two_people"]
