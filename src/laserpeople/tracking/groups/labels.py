"""Group label sets L (000 Sec. 4.2.3): the history of splits and merges.

A new group gets a number (``"0"``); a split appends ``-0`` and ``-1`` to every label of
the set (``{"0"}`` -> ``{"0-0"}`` and ``{"0-1"}``); a merge takes the union
(``{"0-0"} | {"2"}``). With the optional pruning of 000, a set holding both halves of a
split (``"X-0"`` and ``"X-1"``) is relabelled ``"X"`` again.
"""

from __future__ import annotations

import re
from collections.abc import Iterable


def _natural(label: str) -> tuple[int, ...]:
    return tuple(int(p) if p.isdigit() else -1 for p in label.split("-"))


def sort_labels(labels: Iterable[str]) -> tuple[str, ...]:
    """Labels in natural order (``"2" < "10"``, ``"1" < "1-0" < "1-1"``), no duplicates."""
    return tuple(sorted(set(labels), key=_natural))


def split_labels(labels: Iterable[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The label sets of the two groups a group with ``labels`` splits into."""
    labels = sort_labels(labels)
    return tuple(f"{x}-0" for x in labels), tuple(f"{x}-1" for x in labels)


_HALF = re.compile(r"^(.*)-([01])$")


def prune_labels(labels: Iterable[str]) -> tuple[str, ...]:
    """Replace every pair ``X-0``, ``X-1`` by ``X``, repeatedly (000's optional pruning)."""
    out = set(labels)
    changed = True
    while changed:
        changed = False
        for label in sorted(out, key=_natural):
            m = _HALF.match(label)
            if m is None:
                continue
            stem = m.group(1)
            if f"{stem}-0" in out and f"{stem}-1" in out:
                out -= {f"{stem}-0", f"{stem}-1"}
                out.add(stem)
                changed = True
                break
    return sort_labels(out)


def merge_labels(a: Iterable[str], b: Iterable[str], prune: bool = True) -> tuple[str, ...]:
    """The label set of two merging groups: the union (pruned when ``prune``)."""
    union = set(a) | set(b)
    return prune_labels(union) if prune else sort_labels(union)


def format_labels(labels: Iterable[str]) -> str:
    """One string such as ``"0-1|2"``."""
    return "|".join(sort_labels(labels))
