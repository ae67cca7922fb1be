"""Comparing a tracker's output with a recorded reference so that the comparison holds on
every CPU and still catches a real change.

Why not bit for bit: numpy picks its SIMD loops at run time (SSE4.2, AVX2, AVX-512) and
OpenBLAS its kernels by the CPU, so sums and matrix products are rounded in another order
on another machine. The recorded trackers' floats then differ by about 1e-13, and where two
hypotheses are tied to the last bit such a difference flips a discrete choice: which child
of a split keeps which id, which of two clutter legs a track takes. A golden is therefore
compared in two parts:

* floats row by row with a stated absolute tolerance, far above the rounding noise
  (1e-13) and far below what any change of a parameter or an equation makes (1e-4 and
  more, see each test);
* discrete outcomes through summaries that a tie flip leaves alone: a row of the run is
  matched to a reference row of the same frame and kind whose floats all agree within the
  tolerance; ids are compared up to a consistent renaming (the ids per person); point
  groups as partitions (up to renaming); and the share of matched rows must stay above a
  floor that a changed tracker falls far below.
"""

from __future__ import annotations

import itertools
from collections import defaultdict
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Agreement:
    """How far two runs' rows agree.

    ``matched`` rows of the run have a reference row of the same key whose floats agree
    within the tolerance (``expected`` reference rows, ``got`` rows of the run); ``pairs``
    are the matched (run row, reference row) indices; ``id_conflicts`` counts the run's
    ids paired with more than one reference id plus the reference ids paired with more than
    one of the run's (0: the ids agree up to renaming)."""

    matched: int
    expected: int
    got: int
    pairs: NDArray[np.int64]
    id_conflicts: int

    @property
    def share(self) -> float:
        """Matched rows over the larger of the two row counts (1.0 when both are empty)."""
        n = max(self.expected, self.got)
        return 1.0 if n == 0 else self.matched / n

    def describe(self) -> str:
        return (
            f"{self.matched} rows matched of {self.expected} expected and {self.got} got "
            f"(share {self.share:.4f}), {self.id_conflicts} id conflicts"
        )


def match_rows(
    got_keys: NDArray,  # type: ignore[type-arg]
    got_values: FloatArray,
    expected_keys: NDArray,  # type: ignore[type-arg]
    expected_values: FloatArray,
    atol: float | FloatArray,
    got_ids: NDArray | None = None,  # type: ignore[type-arg]
    expected_ids: NDArray | None = None,  # type: ignore[type-arg]
) -> Agreement:
    """Match rows (N, V) of ``got_values`` to rows (M, V) of ``expected_values`` with an
    equal key row (frame, kind, ...; ``*_keys`` (N, K) and (M, K)) whose values all agree
    within ``atol`` (a number or one per column, in the columns' units). Each reference row
    is matched at most once, to the first free row that agrees; with ids given, the
    agreement also counts the ids that are not a consistent renaming of the reference's."""
    got_keys = np.asarray(got_keys).reshape(len(got_values), -1)
    expected_keys = np.asarray(expected_keys).reshape(len(expected_values), -1)
    tol = np.broadcast_to(np.asarray(atol, dtype=np.float64), (got_values.shape[1],))
    by_key: dict[tuple[object, ...], list[int]] = defaultdict(list)
    for i, key in enumerate(map(tuple, got_keys.tolist())):
        by_key[key].append(i)
    pairs: list[tuple[int, int]] = []
    for j, key in enumerate(map(tuple, expected_keys.tolist())):
        candidates = by_key.get(key)
        if not candidates:
            continue
        close = np.all(np.abs(got_values[candidates] - expected_values[j]) <= tol, axis=1)
        hits = np.flatnonzero(close)
        if hits.size:
            pairs.append((candidates.pop(int(hits[0])), j))
    pair_array = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    conflicts = 0
    if got_ids is not None and expected_ids is not None and len(pair_array):
        conflicts = id_conflicts(
            np.asarray(got_ids)[pair_array[:, 0]], np.asarray(expected_ids)[pair_array[:, 1]]
        )
    return Agreement(len(pairs), len(expected_values), len(got_values), pair_array, conflicts)


def id_conflicts(got_ids: NDArray, expected_ids: NDArray) -> int:  # type: ignore[type-arg]
    """Ids of matched rows that are not a one-to-one renaming: the run's ids paired with
    more than one reference id, plus the reference ids paired with more than one of the
    run's (0 when each reference track is one track of the run, as before)."""
    pairs = set(zip(np.asarray(got_ids).tolist(), np.asarray(expected_ids).tolist(), strict=True))
    partners: dict[object, int] = defaultdict(int)
    back: dict[object, int] = defaultdict(int)
    for g, e in pairs:
        partners[g] += 1
        back[e] += 1
    return sum(n - 1 for n in partners.values()) + sum(n - 1 for n in back.values())


def same_partition_share(
    got: NDArray,  # type: ignore[type-arg]
    expected: NDArray,  # type: ignore[type-arg]
    offsets: NDArray[np.int64],
    expected_offsets: NDArray[np.int64],
) -> float:
    """Share of frames (``offsets`` (F + 1,) into the flat per-point labels ``got``,
    ``expected_offsets`` into ``expected``) whose points fall into the same groups in both
    runs, whatever the groups are called. A frame with another number of points in the
    two runs (a point at a threshold on one CPU) counts as one that disagrees."""
    frames = len(offsets) - 1
    if frames != len(expected_offsets) - 1:
        return 0.0
    if frames <= 0:
        return 1.0
    same = 0
    spans = zip(
        itertools.pairwise(offsets.tolist()),
        itertools.pairwise(expected_offsets.tolist()),
        strict=True,
    )
    for (a, b), (c, d) in spans:
        if b - a != d - c:
            continue
        g, e = got[a:b], expected[c:d]
        n_pairs = len(set(zip(g.tolist(), e.tolist(), strict=True)))
        same += n_pairs == len(set(g.tolist())) == len(set(e.tolist()))
    return same / frames
