"""The global-nearest-neighbour baseline tracker."""

from __future__ import annotations

import numpy as np

from laserpeople.tracking import synthetic as syn
from laserpeople.tracking.nearest import NearestNeighbourParams, NearestNeighbourTracker
from laserpeople.tracks import Detections


def dets(k: int, pts: list[list[float]]) -> Detections:
    p = np.array(pts, float).reshape(-1, 2)
    return Detections(0.1 * k, k, p, np.tile(np.eye(2) * 1e-3, (len(p), 1, 1)), np.ones(len(p)))


def test_tracks_confirm_coast_and_delete() -> None:
    tr = NearestNeighbourTracker(NearestNeighbourParams(max_misses=2, min_hits=2))
    assert len(tr.update(dets(0, [[1, 0], [3, 0]]))) == 0  # not confirmed yet
    out = tr.update(dets(1, [[1.05, 0], [3, 0.05]]))
    ids = sorted(t.track_id for t in out.of_kind("leg"))
    assert ids == [0, 1]
    # target 1 missed twice: coasts; a third miss deletes it
    for k in (2, 3):
        out = tr.update(dets(k, [[1.0 + 0.05 * k, 0]]))
        assert sorted(t.track_id for t in out.of_kind("leg")) == [0, 1]
    out = tr.update(dets(4, [[1.2, 0]]))
    assert sorted(t.track_id for t in out.of_kind("leg")) == [0]
    np.testing.assert_allclose(out.of_kind("leg")[0].position, [1.2, 0], atol=0.02)


def test_nearest_neighbour_pairs_by_global_cost() -> None:
    tr = NearestNeighbourTracker(NearestNeighbourParams(min_hits=1))
    tr.update(dets(0, [[0, 0], [0.4, 0]]))
    out = tr.update(dets(1, [[0.38, 0], [0.02, 0]]))
    by_id = {t.track_id: t.position for t in out.of_kind("leg")}
    np.testing.assert_allclose(by_id[0], [0.02, 0], atol=0.02)
    np.testing.assert_allclose(by_id[1], [0.38, 0], atol=0.02)


def test_walkers_become_people() -> None:
    scene = syn.make_scene([syn.line_path((2.0, -2.0), (0.05, 0.8))], 8.0, seed=4)
    tr = NearestNeighbourTracker()
    outs = [tr.update(d) for d in scene.detections]
    assert sum(len(o.of_kind("person")) for o in outs) > 20
