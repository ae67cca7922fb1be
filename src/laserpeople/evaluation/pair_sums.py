"""A running sum per (track id, person id) pair: what trajectory-level matching needs.

IDF1 and the adapted MOTP of 004 match whole trajectories once, at the end. Neither needs
the trajectories themselves, only one number per pair of (track, person) summed over the
frames (frames in which both are within the gate; sums of matching values). Memory is one
float per pair of ids ever seen: O(tracks x people), independent of the recording length.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from laserpeople.evaluation.matching import max_weight_assignment


class IdIndex:
    """Dense 0-based indices for arbitrary integer ids, in order of first appearance."""

    def __init__(self) -> None:
        self._index: dict[int, int] = {}
        self._ids: list[int] = []

    def __len__(self) -> int:
        return len(self._ids)

    def indices(self, ids: NDArray[np.int64]) -> NDArray[np.int64]:
        """Indices (N,) of ``ids`` (N,), adding ids not seen before."""
        out = np.empty(len(ids), dtype=np.int64)
        for k, raw in enumerate(ids.tolist()):
            idx = self._index.get(raw)
            if idx is None:
                idx = len(self._ids)
                self._index[raw] = idx
                self._ids.append(raw)
            out[k] = idx
        return out

    @property
    def ids(self) -> NDArray[np.int64]:
        """All ids (K,) in index order."""
        return np.array(self._ids, dtype=np.int64)


class PairSums:
    """Sums of a per-frame value for every (row id, column id) pair, grown on demand."""

    def __init__(self) -> None:
        self.rows = IdIndex()
        self.cols = IdIndex()
        self._sums = np.zeros((8, 8))

    def add(
        self, row_ids: NDArray[np.int64], col_ids: NDArray[np.int64], values: NDArray[np.float64]
    ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        """Add ``values`` (R, C) to the pairs of ``row_ids`` (R,) x ``col_ids`` (C,); returns
        the dense indices (R,), (C,) of those ids."""
        r = self.rows.indices(row_ids)
        c = self.cols.indices(col_ids)
        need = (len(self.rows), len(self.cols))
        if need[0] > self._sums.shape[0] or need[1] > self._sums.shape[1]:
            shape = (
                max(self._sums.shape[0], _grow(need[0])),
                max(self._sums.shape[1], _grow(need[1])),
            )
            grown = np.zeros(shape)
            grown[: self._sums.shape[0], : self._sums.shape[1]] = self._sums
            self._sums = grown
        if r.size and c.size:
            self._sums[np.ix_(r, c)] += values
        return r, c

    @property
    def sums(self) -> NDArray[np.float64]:
        """The sums (rows seen, columns seen), ids in :attr:`rows`/:attr:`cols` order."""
        return self._sums[: len(self.rows), : len(self.cols)].copy()

    def matching(self) -> TrajectoryMatching:
        """The one-to-one matching of row ids to column ids with the largest summed sums."""
        sums = self.sums
        rows, cols = max_weight_assignment(sums)
        return TrajectoryMatching(sums, rows, cols, self.rows.ids, self.cols.ids)


@dataclass(frozen=True, eq=False)
class TrajectoryMatching:
    """A one-to-one matching of the rows and columns of :class:`PairSums`.

    Attributes:
        sums: The pair sums (R, C) it was solved on.
        rows: Matched row indices (K,).
        cols: Matched column indices (K,), partner of ``rows``.
        row_ids: Id (R,) of every row index.
        col_ids: Id (C,) of every column index.
    """

    sums: NDArray[np.float64]
    rows: NDArray[np.int64]
    cols: NDArray[np.int64]
    row_ids: NDArray[np.int64]
    col_ids: NDArray[np.int64]

    @property
    def total(self) -> float:
        """Summed value of the matched pairs."""
        return float(self.sums[self.rows, self.cols].sum())

    @property
    def id_pairs(self) -> tuple[tuple[int, int], ...]:
        """The matched pairs as (row id, column id)."""
        return tuple(
            (int(self.row_ids[r]), int(self.col_ids[c]))
            for r, c in zip(self.rows.tolist(), self.cols.tolist(), strict=True)
        )

    def partner(self) -> NDArray[np.int64]:
        """Matched column index (R,) of every row index, -1 where unmatched."""
        out = np.full(self.row_ids.size, -1, dtype=np.int64)
        out[self.rows] = self.cols
        return out


def _grow(n: int) -> int:
    size = 8
    while size < n:
        size *= 2
    return size
