"""Counting the distinct track ids a tracker reported, in memory bounded by the live tracks."""

from __future__ import annotations

from collections.abc import Iterable


class SeenIds:
    """The number of distinct ids reported since the start, keeping only live ids.

    Ids are never reused once their track is gone (the trackers count them up), so an id
    that is no longer live cannot be reported again and is forgotten (:meth:`prune`); a
    plain set of every id ever reported grew with the length of the run.
    """

    def __init__(self) -> None:
        self.count = 0
        self._live: set[int] = set()

    def add(self, ids: Iterable[int]) -> None:
        """Count the ids not counted yet."""
        for i in ids:
            if i not in self._live:
                self._live.add(i)
                self.count += 1

    def prune(self, live: Iterable[int]) -> None:
        """Forget every id not in ``live`` (the ids whose tracks still exist)."""
        self._live.intersection_update(live)

    def __len__(self) -> int:
        return self.count
