"""KD-trees of point sets kept for their next use: a particle-filter tracker asks for a
tree of the same points several times per scan (the step detector, the filters' support,
the points near their feet, the blobs) and of the previous scan's points once more (the
step detector's overlap), and building one costs more than looking it up.

:func:`kdtree` returns a :class:`scipy.spatial.cKDTree` of a copy of the points, the same
tree for the same points (the same float64 values, bit for bit, in the same order) while it
is among the :data:`KEPT` last ones asked for in this thread (each thread keeps its own, so
that trackers in threads do not share a cache).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.lazy_scipy import cKDTree

KEPT = 4
"""Trees kept per thread: this scan's point sets and the previous scan's."""

_local = threading.local()


def kdtree(points: NDArray[np.floating]) -> Any:
    """A ``cKDTree`` (default leaf size) of ``points`` (N, 2) [m], built on a copy of them
    (a later change of ``points`` does not reach it), kept for the next call with the same
    points (see the module doc)."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    key = (pts.shape, pts.tobytes())
    cache: OrderedDict[tuple[tuple[int, ...], bytes], Any] | None = getattr(_local, "trees", None)
    if cache is None:
        cache = _local.trees = OrderedDict()
    tree = cache.get(key)
    if tree is not None:
        cache.move_to_end(key)
        return tree
    tree = cKDTree(pts.copy())
    cache[key] = tree
    if len(cache) > KEPT:
        cache.popitem(last=False)
    return tree


def clear() -> None:
    """Forget the trees this thread keeps."""
    getattr(_local, "trees", OrderedDict()).clear()


__all__ = ["KEPT", "clear", "kdtree"]
