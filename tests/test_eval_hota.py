"""HOTA (Luiten et al. 2021) on hand-computed cases and against TrackEval (dev extra).

Similarity S = max(0, 1 - d / d0), d0 = 1.5 m (alpha = 0.5 is the 0.75 m gate); 19 alphas
0.05 .. 0.95. Hand values below are exact fractions; floats compare to 1e-9.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.evaluation.hota import Hota, HotaParams, combine_hota, similarity
from laserpeople.evaluation.matching import frame_points
from laserpeople.evaluation.synthetic import synthetic_sequence

TOL = 1e-9


def run(people, tracks, params=None):
    metric = Hota(params)
    for truth, frame in zip(*synthetic_sequence(people, tracks), strict=True):
        metric.accumulate(truth, frame)
    return metric.result()


def line(n, x=0.0, y=0.0):
    """A person standing at (x, y) for n frames."""
    return np.tile([x, y], (n, 1)).astype(float)


def test_similarity_is_linear_in_distance_and_zero_beyond_d0():
    d = np.array([0.0, 0.375, 0.75, 1.5, 3.0])
    assert similarity(d, 1.5) == pytest.approx([1.0, 0.75, 0.5, 0.0, 0.0], abs=TOL)


def test_perfect_tracking_scores_one():
    r = run({1: line(3)}, {7: line(3)})
    assert (r.hota, r.deta, r.assa, r.loca) == pytest.approx((1, 1, 1, 1), abs=TOL)


def test_offset_track_matches_only_for_alphas_up_to_its_similarity():
    # d = 0.27 m: S = 1 - 0.27 / 1.5 = 0.82, a TP for the 16 alphas 0.05..0.80, FN+FP for
    # 0.85, 0.90, 0.95. Per matched alpha DetA = AssA = 1, LocA = 0.82; unmatched: DetA =
    # AssA = 0 and LocA = 1 (no TP, as TrackEval). HOTA = 16/19; LocA = (16 x 0.82 + 3)/19.
    r = run({1: line(4)}, {7: line(4, 0.27)})
    assert r.tp == (4,) * 16 + (0,) * 3
    assert r.hota == pytest.approx(16 / 19, abs=TOL)
    assert r.deta == pytest.approx(16 / 19, abs=TOL)
    assert r.assa == pytest.approx(16 / 19, abs=TOL)
    assert r.loca == pytest.approx((16 * 0.82 + 3) / 19, abs=TOL)
    # a near miss, S = 1 - (d / d0)^2 = 0.9676, would match at 18 alphas
    assert r.hota != pytest.approx(18 / 19, abs=1e-3)


def test_id_switch_halves_association():
    # One person for 4 frames, perfectly placed, tracked by id 1 then id 2: DetA = 1; each
    # pair has TPA = 2, FNA = 2, FPA = 0, so A = 1/2 and AssA = (2 x 1/2 + 2 x 1/2) / 4.
    first = np.array([[0, 0], [0, 0], [np.nan, np.nan], [np.nan, np.nan]], float)
    second = first[::-1].copy()
    r = run({1: line(4)}, {1: first, 2: second})
    assert r.deta == pytest.approx(1.0, abs=TOL)
    assert r.assa == pytest.approx(0.5, abs=TOL)
    assert r.hota == pytest.approx(math.sqrt(0.5), abs=TOL)
    assert r.assa_re == pytest.approx(0.5, abs=TOL)
    assert r.assa_pr == pytest.approx(1.0, abs=TOL)


def test_false_track_halves_detection():
    # A perfect track plus a clutter track 3 m away in both frames: TP = 2, FP = 2.
    r = run({1: line(2)}, {1: line(2), 9: line(2, 3.0)})
    assert r.deta == pytest.approx(0.5, abs=TOL)
    assert r.assa == pytest.approx(1.0, abs=TOL)
    assert r.hota == pytest.approx(math.sqrt(0.5), abs=TOL)
    assert r.deta_pr == pytest.approx(0.5, abs=TOL)
    assert r.deta_re == pytest.approx(1.0, abs=TOL)


def test_no_tracks_gives_zero_hota_and_loca_one():
    r = run({1: line(3)}, {})
    assert r.hota == 0.0 and r.deta == 0.0 and r.loca == 1.0
    assert r.fn == (3,) * 19


def test_zero_distance_is_a_parameter():
    # d = 0.27 with d0 = 0.54: S = 0.5, a TP for the 10 alphas 0.05..0.50
    r = run({1: line(2)}, {7: line(2, 0.27)}, HotaParams(zero_distance=0.54))
    assert r.hota == pytest.approx(10 / 19, abs=TOL)


def test_combining_sequences_sums_counts_and_weights_association_by_tp():
    a = run({1: line(4)}, {1: line(4)})  # TP 4 per alpha, AssA 1
    first = np.array([[0, 0], [0, 0], [np.nan, np.nan], [np.nan, np.nan]], float)
    b = run({1: line(4)}, {1: first, 2: first[::-1].copy()})  # TP 4, AssA 0.5
    both = combine_hota([a, b])
    assert both.tp == (8,) * 19
    assert both.assa == pytest.approx(0.75, abs=TOL)
    assert both.hota == pytest.approx(math.sqrt(0.75), abs=TOL)
    with pytest.raises(ValueError):
        combine_hota([])


def test_pooled_loca_counts_one_at_alphas_without_any_tp():
    # 0.27 m off: S = 0.82, TP at the 16 alphas up to 0.80, none at 0.85, 0.90, 0.95.
    # One recording: LocA = (16 * 0.82 + 3) / 19 = 0.848; pooling it with itself (or
    # alone) must give the same, not (16 * 0.82 + 0) / 19 = 0.691 (TrackEval: 1 there).
    r = run({1: line(4)}, {7: line(4, 0.27)})
    assert r.loca == pytest.approx((16 * 0.82 + 3) / 19, abs=TOL)
    for pooled in (combine_hota([r]), combine_hota([r, r])):
        assert pooled.loca == pytest.approx(r.loca, abs=TOL)
        assert pooled.loca_alpha[-3:] == pytest.approx((1.0, 1.0, 1.0), abs=TOL)


trackeval = pytest.importorskip("trackeval")


def trackeval_hota(truth_frames, track_frames, d0):
    """TrackEval's HOTA on the same frames, ids made dense, with its Euclidean similarity."""
    gt_index: dict[int, int] = {}
    tr_index: dict[int, int] = {}
    data = {"gt_ids": [], "tracker_ids": [], "similarity_scores": []}
    n_gt = n_tr = 0
    for truth, tracks in zip(truth_frames, track_frames, strict=True):
        pts = frame_points(truth, tracks, "person")
        g = np.array([gt_index.setdefault(i, len(gt_index)) for i in pts.truth_ids.tolist()], int)
        t = np.array([tr_index.setdefault(i, len(tr_index)) for i in pts.track_ids.tolist()], int)
        sim = trackeval.datasets._base_dataset._BaseDataset._calculate_euclidean_similarity(
            pts.truth_xy, pts.track_xy, zero_distance=d0
        )
        data["gt_ids"].append(g)
        data["tracker_ids"].append(t)
        data["similarity_scores"].append(sim.reshape(len(g), len(t)))
        n_gt += len(g)
        n_tr += len(t)
    data.update(
        num_gt_dets=n_gt,
        num_tracker_dets=n_tr,
        num_gt_ids=len(gt_index),
        num_tracker_ids=len(tr_index),
        num_timesteps=len(truth_frames),
    )
    return trackeval.metrics.HOTA().eval_sequence(data)


@pytest.mark.parametrize("seed", range(15))
def test_matches_trackeval_on_random_sequences(seed):
    from test_eval_oracle import random_scene

    rng = np.random.default_rng(seed)
    people, tracks = random_scene(rng)
    truth_frames, track_frames = synthetic_sequence(people, tracks)
    ours = Hota()
    for truth, frame in zip(truth_frames, track_frames, strict=True):
        ours.accumulate(truth, frame)
    r = ours.result()
    ref = trackeval_hota(truth_frames, track_frames, 1.5)
    np.testing.assert_allclose(r.hota_alpha, ref["HOTA"], atol=1e-9)
    np.testing.assert_allclose(r.deta_alpha, ref["DetA"], atol=1e-9)
    np.testing.assert_allclose(r.assa_alpha, ref["AssA"], atol=1e-9)
    np.testing.assert_allclose(r.loca_alpha, ref["LocA"], atol=1e-9)
    np.testing.assert_allclose(r.tp, ref["HOTA_TP"])
    np.testing.assert_allclose(r.fp, ref["HOTA_FP"])


def test_pooled_matches_trackeval_combination():
    metric = trackeval.metrics.HOTA()
    from test_eval_oracle import random_scene

    ours, refs = [], {}
    for seed in range(4):
        people, tracks = random_scene(np.random.default_rng(100 + seed))
        truth_frames, track_frames = synthetic_sequence(people, tracks)
        h = Hota()
        for truth, frame in zip(truth_frames, track_frames, strict=True):
            h.accumulate(truth, frame)
        ours.append(h.result())
        refs[seed] = trackeval_hota(truth_frames, track_frames, 1.5)
    pooled = combine_hota(ours)
    ref = metric.combine_sequences(refs)
    np.testing.assert_allclose(pooled.hota_alpha, ref["HOTA"], atol=1e-9)
    np.testing.assert_allclose(pooled.assa_alpha, ref["AssA"], atol=1e-9)
    np.testing.assert_allclose(pooled.loca_alpha, ref["LocA"], atol=1e-9)
