"""Followed-person scoring, text track ids in tracks CSVs, and `evaluate` on bag truth."""

from __future__ import annotations

import json
import math
import uuid
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import EvaluationError
from laserpeople.evaluation import EvaluationParams, evaluate
from laserpeople.evaluation.followed import FollowedPerson, evaluate_followed
from laserpeople.evaluation.synthetic import synthetic_sequence
from laserpeople.io.tracks_csv import STRING_ID_BASE, TrackIdNames, iter_tracks_csv
from laserpeople.io.truth_csv import write_truth_csv
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame


def _tracks(k: int, rows: list[tuple[int, float, float]]) -> Tracks:
    return Tracks(
        float(k),
        k,
        tuple(Track(t, "person", np.array([x, y]), np.zeros(2), np.eye(2)) for t, x, y in rows),
    )


def _truth(k: int, people: list[tuple[int, float, float]]) -> TruthFrame:
    ids = np.array([p for p, _, _ in people], dtype=np.int64)
    xy = np.array([(x, y) for _, x, y in people]).reshape(-1, 2)
    return TruthFrame.from_positions(float(k), k, ids, xy)


def hand_case() -> tuple[list[TruthFrame], list[Tracks]]:
    """Person 2 at x = k along y = 0 in scans 0-6 except scan 3 (not labelled); person 9
    (someone else) labelled in scan 0 only. Tracks: 10 covers 2 in scans 0-1; in scan 2
    track 11 is nearer but 10 is still within 0.75 m (kept); scan 4 only 11 (switch);
    scan 5 nothing within the gate (miss); scan 6 track 10 again, 11 beyond the gate
    (switch). Track 99 is
    elsewhere the whole time (another person: no false positive)."""
    truth = [_truth(0, [(2, 0.0, 0.0), (9, 0.0, 5.0)])]
    truth += [_truth(k, [(2, float(k), 0.0)]) for k in (1, 2, 4, 5, 6)]
    tracks = [
        _tracks(0, [(10, 0.1, 0.0), (99, 0.0, 3.0)]),
        _tracks(1, [(10, 1.2, 0.0), (99, 0.0, 3.0)]),
        _tracks(2, [(10, 2.5, 0.0), (11, 2.05, 0.0), (99, 0.0, 3.0)]),
        _tracks(3, [(11, 3.0, 0.0)]),
        _tracks(4, [(11, 4.3, 0.0), (99, 0.0, 3.0)]),
        _tracks(5, [(11, 6.0, 0.0)]),
        _tracks(6, [(10, 6.0, 0.2), (11, 6.0, 0.9)]),
    ]
    return truth, tracks


def test_followed_person_hand_values() -> None:
    truth, tracks = hand_case()
    r = evaluate_followed(truth, tracks, 2)[0].result()
    # person 2 is labelled in scans 0, 1, 2, 4, 5, 6: six frames
    assert r.frames == 6
    # matched: 0 (10), 1 (10), 2 (10 kept), 4 (11), 6 (10); scan 5: 11 is 1 m away -> miss
    assert r.matched == 5
    assert r.recall == pytest.approx(5 / 6)
    assert r.id_switches == 2 and r.ids == 2
    assert r.track_frames == ((10, 4), (11, 1))
    # within the gate per id: 10 in scans 0, 1, 2, 6 (4); 11 in scans 2, 4 (2)
    assert r.identity_recall == pytest.approx(4 / 6) and r.best_track == 10
    assert r.mota == pytest.approx(1 - (1 + 2) / 6)
    assert r.motp == pytest.approx((0.1 + 0.2 + 0.5 + 0.3 + 0.2) / 5)
    # at 0.25 m scan 2 switches to 11 (0.05 m; 10 is 0.5 m away) and scan 4 (0.3 m) is missed
    tight = evaluate_followed(truth, tracks, 2, EvaluationParams(gate=0.25))[0].result()
    assert tight.matched == 4 and tight.recall == pytest.approx(4 / 6)
    assert tight.id_switches == 2 and tight.track_frames == ((10, 3), (11, 1))


def test_followed_agrees_with_clear_mot_and_idf1_on_single_person_truth() -> None:
    """With only that person in the truth, recall, switches and identity recall equal the
    general CLEAR MOT recall/switches and IDF1's IDR (which also count false positives,
    which followed mode ignores)."""
    rng = np.random.default_rng(4)
    n = 300
    walk = np.cumsum(rng.normal(0.0, 0.1, (n, 2)), axis=0)
    tracks_xy = {}
    for tid in range(6):
        xy = walk + rng.normal(0.0, 0.4, (n, 2))
        xy[rng.random(n) < 0.5] = np.nan
        tracks_xy[100 + tid] = xy
    truth, tracks = synthetic_sequence({3: walk}, tracks_xy)
    followed = evaluate_followed(truth, tracks, 3)[0].result()
    general = evaluate(truth, tracks).result()
    assert followed.frames == n
    assert followed.recall == pytest.approx(general.clear_mot.recall)
    assert followed.id_switches == general.clear_mot.id_switches
    assert followed.identity_recall == pytest.approx(general.identity.idr)
    assert general.clear_mot.false_positives > 0  # followed mode ignores these


def test_unlabelled_person_is_an_error() -> None:
    truth, tracks = hand_case()
    with pytest.raises(EvaluationError, match=r"person 4 is not labelled.*2, 9"):
        evaluate_followed(truth, tracks, 4)
    metric = FollowedPerson(2, keep_frames=False)
    with pytest.raises(EvaluationError):
        metric.frames()


def test_track_id_names_keep_integers_and_number_text() -> None:
    names = TrackIdNames()
    assert names.to_int("12") == 12 and names.to_int("-3") == -3
    a, b = str(uuid.UUID(int=1)), str(uuid.UUID(int=2))
    assert names.to_int(a) == STRING_ID_BASE
    assert names.to_int(b) == STRING_ID_BASE + 1
    assert names.to_int(a) == STRING_ID_BASE
    assert names.name(STRING_ID_BASE + 1) == b and names.name(12) == "12"
    with pytest.raises(ValueError, match="empty"):
        names.to_int(" ")


def _write_csv(path: Path, tracks: list[Tracks], rename: dict[int, str]) -> None:
    lines = ["scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels"]
    for fr in tracks:
        for t in fr.tracks:
            tid = rename.get(t.track_id, str(t.track_id))
            x, y = t.position
            lines.append(f"{fr.scan_index},{fr.stamp},{tid},person,{x},{y},0,0,1,0,1,1,")
    path.write_text("\n".join(lines) + "\n")


def test_uuid_track_ids_score_like_integer_ids(tmp_path: Path) -> None:
    truth, tracks = hand_case()
    rename = {10: str(uuid.UUID(int=10)), 11: str(uuid.UUID(int=11)), 99: "walker-b"}
    _write_csv(tmp_path / "int.csv", tracks, {})
    _write_csv(tmp_path / "uuid.csv", tracks, rename)
    names = TrackIdNames()
    by_int = evaluate(truth, iter_tracks_csv(tmp_path / "int.csv")).result()
    by_text = evaluate(truth, iter_tracks_csv(tmp_path / "uuid.csv", ids=names)).result()
    assert by_int.summary() == by_text.summary()
    assert {names.name(t) for t, _ in by_text.identity.matched} <= set(rename.values())
    write_truth_csv(tmp_path / "truth.csv", truth)
    runner = CliRunner()
    res = runner.invoke(
        app,
        [
            "evaluate",
            str(tmp_path / "uuid.csv"),
            "--truth",
            str(tmp_path / "truth.csv"),
            "--followed-person",
            "auto",
            "--match-distance",
            "0.75",
            "--json",
        ],
    )
    assert res.exit_code == 0, res.output
    out = json.loads(res.output.strip().splitlines()[-1])
    # auto picks person 2 (six labelled frames against one for person 9)
    assert out["person_id"] == 2 and out["ids"] == 2 and out["id_switches"] == 2
    assert out["recall"] == pytest.approx(5 / 6)
    assert out["best_track"] == rename[10]
    assert out["track_frames"] == [[rename[10], 4], [rename[11], 1]]
    general = runner.invoke(
        app, ["evaluate", str(tmp_path / "uuid.csv"), "--truth", str(tmp_path / "truth.csv")]
    )
    assert general.exit_code == 0 and "MOTA" in general.output
    js = runner.invoke(
        app,
        ["evaluate", str(tmp_path / "uuid.csv"), "--truth", str(tmp_path / "truth.csv"), "--json"],
    )
    matching = json.loads(js.output.strip().splitlines()[-1])["detail"]["identity_matching"]
    assert [rename[10], 2] in matching


def test_evaluate_reads_truth_from_a_bag_topic(tmp_path: Path) -> None:
    """The same hand case with the labels in a bag written after each scan."""
    from laserpeople.io.rosbag_writer import open_bag
    from laserpeople.io.truth_bag import LEG_TRACKER_PERSON, register_people_types
    from test_io_truth_bag import _person, _scan

    truth, tracks = hand_case()
    by_scan = {f.scan_index: f for f in truth}
    bag = tmp_path / "run.bag"
    with open_bag(bag) as sink:
        register_people_types(sink.typestore)
        for k in range(7):
            sink.scan(_scan(k, float(k)), "/scan", "laser")
            frame = by_scan.get(k)
            for pid, (x, y) in zip(
                [] if frame is None else frame.person_ids.tolist(),
                [] if frame is None else frame.positions.tolist(),
                strict=True,
            ):
                person = _person(sink.typestore.types, pid, x, y)
                sink.write("/gt", LEG_TRACKER_PERSON, person, k + 0.05)
    _write_csv(tmp_path / "t.csv", tracks, {})
    res = CliRunner().invoke(
        app,
        ["evaluate", str(tmp_path / "t.csv"), "--truth", f"{bag}:/gt", "--followed-person", "2"],
    )
    assert res.exit_code == 0, res.output
    assert "7 labels of 2 people on 6 scans of /scan" in res.output
    assert "5 of 6 labelled frames" in res.output
    assert "states no frame (no frame column): taken as sensor" in res.output
    # the labels are in the laser frame: tracks that say they are in the world frame, with
    # no sensor pose to move them, are refused (they scored as garbage before)
    lines = (tmp_path / "t.csv").read_text().splitlines()
    for frame in ("world", "sensor"):
        (tmp_path / f"{frame}.csv").write_text(
            "\n".join([lines[0] + ",topic,frame"] + [f"{ln},/scan,{frame}" for ln in lines[1:]])
            + "\n"
        )
    world = CliRunner().invoke(
        app, ["evaluate", str(tmp_path / "world.csv"), "--truth", f"{bag}:/gt"]
    )
    assert world.exit_code != 0
    assert "truth in the sensor frame" in str(world.exception or world.output)
    sensor = CliRunner().invoke(
        app, ["evaluate", str(tmp_path / "sensor.csv"), "--truth", f"{bag}:/gt", "--json"]
    )
    assert sensor.exit_code == 0, sensor.output
    assert "states no frame" not in sensor.output
    bad = CliRunner().invoke(
        app, ["evaluate", str(tmp_path / "t.csv"), "--truth", str(bag), "--followed-person", "x"]
    )
    assert bad.exit_code != 0
    assert math.isfinite(evaluate_followed(truth, tracks, 2)[0].result().motp)


@pytest.mark.parametrize("truth_frame", [None, "sensor", "world"])
def test_fit_scores_tracks_without_pose_in_the_frame_the_truth_states(truth_frame) -> None:
    """``fit``'s validation compares tracks of a recording without poses as they are,
    whichever frame the labels state (a bag's labels: the laser frame; a CSV: none)."""
    from dataclasses import replace

    from laserpeople.fitting.data import LabelledRecording
    from laserpeople.fitting.validate import score_legs

    truth, tracks = hand_case()
    truth = [replace(f, frame=truth_frame) for f in truth]
    tracks = [replace(t, frame="sensor", sensor_pose=None) for t in tracks]
    rec = LabelledRecording("x", (), (), {f.scan_index: f for f in truth}, True, np.empty(0))
    scores = score_legs(rec, tracks)
    assert scores["recall"] == pytest.approx(5 / 6) and scores["ids"] == 2
