"""Scores pooled over recordings: CLEAR MOT and IDF1 add their counts, HOTA as TrackEval."""

from __future__ import annotations

import math

import numpy as np
import pytest

from laserpeople.evaluation import EvaluationParams, evaluate
from laserpeople.evaluation.hota import Hota
from laserpeople.evaluation.recordings import RecordingScore, find_truth, pool, score_rows
from laserpeople.evaluation.synthetic import synthetic_sequence

TOL = 1e-9


def score(name, people, tracks):
    truth, frames = synthetic_sequence(people, tracks)
    hota = Hota()
    run = evaluate(truth, frames, EvaluationParams(), also=[hota])
    return RecordingScore(name, "t.csv", "x.npz", run.result(), hota.result())


def stand(n, x=0.0):
    return np.tile([x, 0.0], (n, 1)).astype(float)


def test_pooled_counts_are_summed_not_averaged():
    # A: 2 frames, 1 person, perfect. B: 6 frames, 1 person, missed in all.
    # Pooled MOTA = 1 - 6 misses / 8 person-frames = 0.25 (the mean of 1 and 0 would be
    # 0.5); pooled IDF1 = 2 x 2 / (8 + 2) = 0.4.
    a = score("a", {1: stand(2)}, {5: stand(2)})
    b = score("b", {1: stand(6)}, {})
    p = pool([a, b])
    assert p is not None and p.recordings == 2
    assert p.mota == pytest.approx(0.25, abs=TOL)
    assert p.idf1 == pytest.approx(0.4, abs=TOL)
    assert p.misses == 6 and p.num_truth == 8
    # HOTA: TP 2, FN 6 at every alpha; AssA of A is 1 (B has no TP): DetA 0.25, HOTA 0.5
    assert p.hota.deta == pytest.approx(0.25, abs=TOL)
    assert p.hota.hota == pytest.approx(0.5, abs=TOL)


def test_rows_end_with_pooled_and_keep_errors():
    a = score("a", {1: stand(2)}, {5: stand(2)})
    bad = RecordingScore("bad", "t.csv", "x.npz", error="x.npz: no truth")
    rows = score_rows([a, bad])
    assert [r["recording"] for r in rows] == ["a", "bad", "pooled (1)"]
    assert rows[1]["error"] == "x.npz: no truth" and math.isnan(rows[1]["mota"])
    assert rows[2]["hota"] == pytest.approx(1.0, abs=TOL)
    assert pool([bad]) is None


def test_truth_found_by_name(tmp_path):
    bag = tmp_path / "run_1.bag"
    bag.write_bytes(b"")
    assert find_truth(bag) is None
    (tmp_path / "run_1.people.csv").write_text("scan,stamp,person_id,x,y\n")
    assert find_truth(bag) == str(tmp_path / "run_1.people.csv")
    assert find_truth(tmp_path / "sim.npz") == str(tmp_path / "sim.npz")


def test_the_table_marks_an_error_row_and_leaves_its_text_to_a_line_of_its_own():
    from laserpeople.cli.evaluate import render_many

    a = score("a", {1: stand(2)}, {5: stand(2)})
    bad = RecordingScore("bad", "t.csv", "x.npz", error="x.npz: no truth")
    table = render_many(score_rows([a, bad]), 0.75)
    bad_row = [str(col._cells[1]) for col in table.columns]  # cells: str or rich Text
    assert bad_row[:3] == ["bad", "error", "–"] and set(bad_row[2:]) == {"–"}
    assert "no truth" not in " ".join(bad_row)
    assert [str(col._cells[0]) for col in table.columns][1] == "1.000"  # a's MOTA


def test_a_tracks_csv_without_a_frame_is_in_the_frame_of_its_truth(tmp_path):
    """Bag labels are in the laser frame, so a CSV that states no frame is read as the
    laser frame against them, as every other truth reads it as the world frame; for one
    file (evaluate's CLI) and for several (score_recording) alike."""
    from laserpeople.evaluation.recordings import track_frames, unstated_tracks_frame

    bag = tmp_path / "run.bag"
    bag.write_bytes(b"")
    assert unstated_tracks_frame(f"{bag}:/people") == "sensor"
    assert unstated_tracks_frame(bag) == "sensor"
    assert unstated_tracks_frame(tmp_path / "run.people.csv") == "world"
    assert unstated_tracks_frame(tmp_path / "sim.npz") == "world" == unstated_tracks_frame(None)
    csv = tmp_path / "t.csv"
    csv.write_text("scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels\n"
                   "0,0.0,1,person,1.0,0.0,0,0,1,0,1,1,\n")  # fmt: skip
    assert [t.frame for t in track_frames(csv, "person", truth=bag)] == ["sensor"]
    assert [t.frame for t in track_frames(csv, "person")] == ["world"]
