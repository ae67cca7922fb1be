"""The distinct ids of a whole run, in memory that grows with the gaps between them."""

from __future__ import annotations

from bisect import bisect_right


class DistinctIds:
    """The set of ids reported over a whole run, stored as sorted runs of consecutive ids.

    The trackers count their ids up, so the ids of a run form few runs (one, when every id
    was reported); memory grows with the number of gaps, not of ids, as a plain set of every
    id did over a long run (about 1.7 MB per 100,000 scans of a crowded hall). An id may come
    back after its track ended (re-identification), so no id is ever forgotten.
    """

    def __init__(self) -> None:
        self._starts: list[int] = []
        self._ends: list[int] = []  # exclusive: run k holds starts[k] .. ends[k] - 1
        self._count = 0

    def add(self, i: int) -> None:
        """Add one id (no change when it is in already)."""
        starts, ends = self._starts, self._ends
        k = bisect_right(starts, i) - 1
        if k >= 0 and i < ends[k]:
            return
        self._count += 1
        joins_left = k >= 0 and ends[k] == i
        joins_right = k + 1 < len(starts) and starts[k + 1] == i + 1
        if joins_left and joins_right:
            ends[k] = ends[k + 1]
            del starts[k + 1], ends[k + 1]
        elif joins_left:
            ends[k] = i + 1
        elif joins_right:
            starts[k + 1] = i
        else:
            starts.insert(k + 1, i)
            ends.insert(k + 1, i + 1)

    def __contains__(self, i: object) -> bool:
        if not isinstance(i, int):
            return False
        k = bisect_right(self._starts, i) - 1
        return k >= 0 and i < self._ends[k]

    def __len__(self) -> int:
        return self._count

    @property
    def runs(self) -> int:
        """Runs of consecutive ids held (what the memory grows with)."""
        return len(self._starts)
