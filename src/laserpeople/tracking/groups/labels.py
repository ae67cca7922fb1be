"""Group label sets L (000 Sec. 4.2.3): the history of splits and merges.

A new group gets a number (``"0"``); a split appends ``-0`` and ``-1`` to every label of
the set (``{"0"}`` -> ``{"0-0"}`` and ``{"0-1"}``); a merge takes the union
(``{"0-0"} | {"2"}``). With the optional pruning of 000, a set holding both halves of a
split (``"X-0"`` and ``"X-1"``) is relabelled ``"X"`` again.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections.abc import Iterable
from functools import lru_cache

NATURAL_MEMO = 4096
"""Labels whose natural sort keys are remembered (least recently used first out). A long
run meets new labels all the time (every born group, split and merge, in every hypothesis:
about 1,500 per 1,000 scans on the 20-people hall); a few hundred are alive at once. A memo
of 65,536 would hold about 20 MB when full, reached after some 45,000 scans."""


@lru_cache(maxsize=NATURAL_MEMO)
def _natural(label: str) -> tuple[int, ...]:
    """The natural sort key of ``label``: its dash-separated numbers (-1 for a non-number)."""
    return tuple(int(p) if p.isdigit() else -1 for p in label.split("-"))


def sort_labels(labels: Iterable[str]) -> tuple[str, ...]:
    """Labels in natural order (``"2" < "10"``, ``"1" < "1-0" < "1-1"``), no duplicates."""
    return tuple(sorted(set(labels), key=_natural))


def split_labels(labels: Iterable[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The label sets of the two groups a group with ``labels`` splits into."""
    labels = sort_labels(labels)
    return tuple(f"{x}-0" for x in labels), tuple(f"{x}-1" for x in labels)


def prune_labels(labels: Iterable[str]) -> tuple[str, ...]:
    """Replace every pair ``X-0``, ``X-1`` by ``X``, repeatedly (000's optional pruning),
    always the first pair in natural order first. After a replacement the search goes on
    from ``X`` or its sibling, whichever comes first: the labels before them had no
    sibling before and still have none."""
    out = set(labels)
    order = sorted(out, key=_natural)
    keys = [_natural(x) for x in order]
    i = 0
    while i < len(order):
        stem, sep, last = order[i].rpartition("-")
        zero, one = f"{stem}-0", f"{stem}-1"
        if not (sep and last in ("0", "1") and zero in out and one in out):
            i += 1
            continue
        for gone in (zero, one):
            out.discard(gone)
            at = bisect_left(keys, _natural(gone))
            while order[at] != gone:
                at += 1
            del order[at], keys[at]
        i = _insert(order, keys, stem) if stem not in out else bisect_left(keys, _natural(stem))
        out.add(stem)
        head, dash, tail = stem.rpartition("-")
        if dash and tail in ("0", "1"):
            sibling = f"{head}-{1 - int(tail)}"
            if sibling in out:
                i = min(i, bisect_left(keys, _natural(sibling)))
    return sort_labels(out)


def _insert(order: list[str], keys: list[tuple[int, ...]], label: str) -> int:
    """Insert ``label`` into the naturally sorted ``order`` (``keys`` its keys); its index."""
    key = _natural(label)
    at = bisect_right(keys, key)
    order.insert(at, label)
    keys.insert(at, key)
    return bisect_left(keys, key)


def merge_labels(a: Iterable[str], b: Iterable[str], prune: bool = True) -> tuple[str, ...]:
    """The label set of two merging groups: the union (pruned when ``prune``)."""
    union = set(a) | set(b)
    return prune_labels(union) if prune else sort_labels(union)


def format_labels(labels: Iterable[str]) -> str:
    """One string such as ``"0-1|2"``."""
    return "|".join(sort_labels(labels))
