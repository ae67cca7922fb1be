"""The KD-trees kept for their next use (``clustering.trees``): the same tree for the same
points, a new one for other points, none shared between threads, and answers the same as a
tree built afresh."""

from __future__ import annotations

import threading

import numpy as np

from laserpeople.clustering import trees
from laserpeople.lazy_scipy import cKDTree


def test_same_points_same_tree_other_points_other_tree() -> None:
    trees.clear()
    rng = np.random.default_rng(7)
    pts = rng.uniform(-2.0, 2.0, (50, 2))
    first = trees.kdtree(pts)
    assert trees.kdtree(pts.copy()) is first  # the same values, another array
    other = pts.copy()
    other[3, 0] = np.nextafter(other[3, 0], 9.0)  # one value a float away
    assert trees.kdtree(other) is not first
    assert trees.kdtree(pts[:49]) is not first


def test_a_changed_array_does_not_reach_its_tree() -> None:
    trees.clear()
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    tree = trees.kdtree(pts)
    pts[:] = 10.0
    d, j = tree.query([[0.9, 0.0]], k=1)
    np.testing.assert_allclose(d, [0.1], atol=1e-15)
    assert j.tolist() == [1]
    assert trees.kdtree(pts) is not tree


def test_the_oldest_is_forgotten() -> None:
    trees.clear()
    sets = [np.full((3, 2), float(k)) for k in range(trees.KEPT + 1)]
    kept = [trees.kdtree(s) for s in sets]
    assert trees.kdtree(sets[-1]) is kept[-1]
    assert trees.kdtree(sets[0]) is not kept[0]


def test_answers_as_a_fresh_tree() -> None:
    rng = np.random.default_rng(8)
    pts = rng.uniform(-2.0, 2.0, (200, 2))
    queries = rng.uniform(-2.0, 2.0, (40, 2))
    for _ in range(2):  # built, then kept
        got = trees.kdtree(pts).query(queries, k=1)
        want = cKDTree(pts).query(queries, k=1)
        np.testing.assert_array_equal(got[1], want[1])
        np.testing.assert_allclose(got[0], want[0], rtol=1e-15, atol=0.0)


def test_threads_keep_their_own() -> None:
    pts = np.zeros((4, 2))
    here = trees.kdtree(pts)
    there: list[object] = []
    worker = threading.Thread(target=lambda: there.append(trees.kdtree(pts)))
    worker.start()
    worker.join()
    assert there[0] is not here
    assert trees.kdtree(pts) is here
