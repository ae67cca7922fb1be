"""Truth CSV, scan pairing and `laserpeople evaluate` end to end."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import EvaluationError, RecordingError
from laserpeople.evaluation import SUMMARY_KEYS, evaluate
from laserpeople.evaluation.synthetic import synthetic_sequence
from laserpeople.io import write_recording
from laserpeople.io.tracks_csv import TracksCsvWriter, iter_tracks_csv
from laserpeople.io.truth_csv import read_truth_csv, write_truth_csv
from laserpeople.scan import Scan
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame


def scene():
    """Two people, 6 scans; the tracker follows both, loses person 2 in scan 4 and reports
    nothing at all in scan 5."""
    a = np.column_stack([0.2 * np.arange(6), np.zeros(6)])
    b = a + np.array([0.0, 2.0])
    tb = b + np.array([0.1, 0.0])
    tb[4] = np.nan
    ta = a.copy()
    ta[5] = tb[5] = np.nan
    return synthetic_sequence({1: a, 2: b}, {10: ta, 11: tb})


def write_tracks(path, track_frames):
    with TracksCsvWriter(path, frame="world") as out:
        for tracks in track_frames:
            out.write(tracks)


def test_truth_csv_round_trip_sparse_and_empty_scans(tmp_path):
    truth, _ = scene()
    empty = TruthFrame.from_positions(9.0, 90, np.array([]), np.empty((0, 2)))
    path = tmp_path / "truth.csv"
    assert write_truth_csv(path, [truth[3], truth[0], empty]) == 5
    back = read_truth_csv(path)
    assert [f.scan_index for f in back] == [0, 3, 90]
    assert back[1].person_ids.tolist() == [1, 2]
    np.testing.assert_allclose(back[1].positions, truth[3].positions, atol=1e-4)
    assert len(back[2]) == 0 and back[2].stamp == 9.0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("scan,stamp,x,y\n0,0.0,1,2\n", "missing column"),
        ("scan,stamp,person_id,x,y\n0,0.0,1,abc,2\n", "line 2"),
        ("scan,stamp,person_id,x,y\n0,0.0,1,1,2\n0,0.0,1,3,4\n", "person 1 appears twice"),
        ("scan,stamp,person_id,x,y\n0,0.0,1,1,2\n0,0.5,2,3,4\n", "stamp 0.5 differs"),
        ("scan,stamp,person_id,x,y\n", "no rows"),
        ("scan,stamp,person_id,x,y\n-1,0.0,1,1,2\n", "negative"),
    ],
)
def test_truth_csv_errors_name_the_problem(tmp_path, text, message):
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(RecordingError, match=message) as info:
        read_truth_csv(path)
    assert str(path) in str(info.value)
    with pytest.raises(RecordingError, match="not found"):
        read_truth_csv(tmp_path / "missing.csv")


def test_pairing_by_scan_counts_unscored_and_trackless_scans():
    truth, tracks = scene()
    sparse = [truth[1], truth[4], truth[5]]
    reported = [t for t in tracks if len(t)]  # scan 5 has no rows, as in a CSV
    run = evaluate(sparse, reported)
    report = run.result()
    assert report.pairing is not None
    assert report.pairing.frames_scored == 3
    assert report.pairing.frames_without_tracks == 1
    assert report.pairing.track_scans_unscored == 3  # scans 0, 2, 3
    c = report.clear_mot
    assert (c.matches, c.misses, c.false_positives) == (3, 3, 0)
    assert run.frames().column("scan").tolist() == [1, 4, 5]


def test_pairing_rejects_out_of_order_scans():
    truth, tracks = scene()
    with pytest.raises(EvaluationError, match="comes after"):
        evaluate([truth[2], truth[1]], tracks)
    with pytest.raises(EvaluationError, match="come after"):
        evaluate(truth, [tracks[2], tracks[1]])
    with pytest.raises(EvaluationError, match="no ground-truth frame"):
        evaluate([], tracks)


def test_cli_json_has_exactly_the_summary_keys(tmp_path):
    truth, tracks = scene()
    write_tracks(tmp_path / "tracks.csv", tracks)
    write_truth_csv(tmp_path / "truth.csv", truth)
    per_frame = tmp_path / "frames.csv"
    result = CliRunner().invoke(
        app,
        [
            "--quiet",
            "evaluate",
            str(tmp_path / "tracks.csv"),
            "--truth",
            str(tmp_path / "truth.csv"),
            "--json",
            "--per-frame",
            str(per_frame),
        ],
    )
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert set(data) == {*SUMMARY_KEYS, "detail"}
    # 12 person-frames; 9 matched; misses: person 2 in scan 4, both in scan 5.
    assert (data["misses"], data["false_positives"], data["id_switches"]) == (3, 0, 0)
    assert data["mota"] == pytest.approx(1 - 3 / 12)
    assert data["motp_m"] == pytest.approx((5 * 0.0 + 4 * 0.1) / 9)
    assert data["motp_schenk"] == pytest.approx(9 / 12)
    assert data["idf1"] == pytest.approx(2 * 9 / (12 + 9))
    assert data["recall"] == pytest.approx(9 / 12) and data["precision"] == 1.0
    lines = per_frame.read_text().splitlines()
    assert lines[0].startswith("scan,stamp,num_truth,num_tracks,matches,misses")
    assert len(lines) == 7


def test_cli_reads_npz_truth_and_prints_a_table(tmp_path):
    truth, tracks = scene()
    scans = [
        Scan(stamp=f.stamp, angle_min=-1.0, angle_increment=0.5, ranges=np.ones(5), index=k)
        for k, f in enumerate(truth)
    ]
    write_recording(tmp_path / "rec.npz", scans, truth)
    write_tracks(tmp_path / "tracks.csv", tracks)
    result = CliRunner().invoke(
        app, ["evaluate", str(tmp_path / "tracks.csv"), "--truth", str(tmp_path / "rec.npz")]
    )
    assert result.exit_code == 0, result.output
    assert "MOTA" in result.stdout and "0.750" in result.stdout


@pytest.mark.parametrize(
    ("damage", "reason"),
    [
        (lambda a: a["truth_xy"].__setitem__((0, 0), np.nan), "a position is not finite"),
        (lambda a: a["truth_scan_index"].__setitem__(1, 0), "does not come after scan 0"),
        (lambda a: a["truth_person_id"].__setitem__(1, a["truth_person_id"][0]), "id repeats"),
    ],
)
def test_cli_npz_truth_damaged_frame_stops_or_is_skipped(tmp_path, damage, reason):
    truth, tracks = scene()
    scans = [
        Scan(stamp=f.stamp, angle_min=-1.0, angle_increment=0.5, ranges=np.ones(5), index=k)
        for k, f in enumerate(truth)
    ]
    write_recording(tmp_path / "rec.npz", scans, truth)
    with np.load(tmp_path / "rec.npz") as z:
        arrays = {k: z[k] for k in z.files}
    damage(arrays)
    np.savez(tmp_path / "rec.npz", **arrays)
    write_tracks(tmp_path / "tracks.csv", tracks)
    args = ["evaluate", str(tmp_path / "tracks.csv"), "--truth", str(tmp_path / "rec.npz")]
    stop = CliRunner().invoke(app, [*args, "--json"])
    assert isinstance(stop.exception, RecordingError)
    assert reason in str(stop.exception) and "--on-error skip" in str(stop.exception)
    skip = CliRunner().invoke(app, ["--quiet", *args, "--json", "--on-error", "skip"])
    assert skip.exit_code == 0, skip.output
    data = json.loads(skip.stdout)
    # frame 0 or 1 is left out: two matched person-frames fewer, the three misses remain
    assert data["misses"] == 3 and data["recall"] == pytest.approx(7 / 10)
    assert "skipped 1 damaged scan(s) (truth scan" in skip.stderr + skip.output


def test_cli_errors_without_truth(tmp_path):
    _, tracks = scene()
    scans = [
        Scan(stamp=0.1 * k, angle_min=0.0, angle_increment=0.5, ranges=np.ones(3), index=k)
        for k in range(3)
    ]
    write_recording(tmp_path / "rec.npz", scans)
    write_tracks(tmp_path / "tracks.csv", tracks)
    result = CliRunner().invoke(
        app, ["evaluate", str(tmp_path / "tracks.csv"), "--truth", str(tmp_path / "rec.npz")]
    )
    assert result.exit_code != 0
    assert isinstance(result.exception, EvaluationError)
    assert "no ground truth" in str(result.exception)
    bad = CliRunner().invoke(
        app, ["evaluate", str(tmp_path / "tracks.csv"), "--truth", "x.csv", "--kind", "car"]
    )
    assert bad.exit_code != 0 and "kind 'car'" in str(bad.exception)


def test_empty_tracks_object_means_all_missed():
    truth, _ = scene()
    run = evaluate(truth[:1], [Tracks(0.0, 0)])
    assert run.result().clear_mot.misses == 2


def test_frame_table_csv_and_join(tmp_path):
    from laserpeople.evaluation import FrameTable

    a = FrameTable(("scan", "stamp", "x"), ((3, 1700000000.123456, 0.5), (4, 1.0, float("nan"))))
    b = FrameTable(("scan", "stamp", "y"), ((3, 0.0, 1), (4, 0.0, 2)))
    joined = a.join(b)
    assert joined.columns == ("scan", "stamp", "x", "y")
    assert list(joined)[1] == {"scan": 4, "stamp": 1.0, "x": joined.rows[1][2], "y": 2}
    joined.to_csv(tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_text().splitlines() == [
        "scan,stamp,x,y",
        "3,1700000000.123456,0.5,1",
        "4,1.000000,,2",
    ]
    with pytest.raises(ValueError, match="different frames"):
        a.join(FrameTable(("scan", "stamp", "y"), ((5, 0.0, 1), (4, 0.0, 2))))


def test_cli_warns_when_no_track_comes_near_any_label(tmp_path):
    """Truth moved 10 m away (labels in another frame): the scores are all misses, and the
    user is told to check the frames; with the truth in place there is no such warning."""
    truth, tracks = scene()
    write_tracks(tmp_path / "tracks.csv", tracks)
    far = [replace(f, positions=f.positions + 10.0) for f in truth]
    for name, frames in (("near.csv", truth), ("far.csv", far)):
        write_truth_csv(tmp_path / name, frames)

    def run(name):
        args = ["evaluate", str(tmp_path / "tracks.csv"), "--truth", str(tmp_path / name)]
        result = CliRunner().invoke(app, args)
        assert result.exit_code == 0, result.output
        return result.output

    assert "same frame" in run("far.csv") and "--output-frame sensor" in run("far.csv")
    assert "same frame" not in run("near.csv")


def test_nothing_matched_needs_tracks_and_people_and_no_match():
    """The warning's condition: no match while there were tracks and labelled people. A run
    with no track at all (a tracker that reported nobody), or no labelled person, is not
    a frame mix-up; one match anywhere is not either."""
    truth, tracks = scene()
    far = [replace(f, positions=f.positions + 10.0) for f in truth]
    assert evaluate(far, tracks).result().nothing_matched()
    assert not evaluate(truth, tracks).result().nothing_matched()
    no_tracks = [Tracks(t.stamp, t.scan_index) for t in tracks]
    report = evaluate(truth, no_tracks).result()
    assert report.clear_mot.num_tracks == 0 and report.clear_mot.num_truth == 12
    assert not report.nothing_matched()
    nobody = [
        TruthFrame.from_positions(f.stamp, f.scan_index, np.array([]), np.empty((0, 2)))
        for f in truth
    ]
    assert not evaluate(nobody, tracks).result().nothing_matched()
    # only the labels of scan 0 within the gate of a track: matched
    one = [
        replace(f, positions=f.positions + (0.0 if k == 0 else 10.0)) for k, f in enumerate(truth)
    ]
    assert not evaluate(one, tracks).result().nothing_matched()


def test_the_frames_of_tracks_and_truth_are_compared_and_said(tmp_path):
    """A tracks CSV's frame column and a truth CSV's frame column are read; the scorer
    refuses sensor-frame tracks without poses against world truth, says the frame it
    compared in when the truth states none, and says nothing when both state the same."""
    truth, tracks = scene()
    write_tracks(tmp_path / "plain.csv", tracks)
    head, *rows = (tmp_path / "plain.csv").read_text().splitlines()
    for frame in ("world", "sensor"):  # the frame column `track` writes
        lines = [f"{head},frame", *(f"{row},{frame}" for row in rows)]
        (tmp_path / f"{frame}.csv").write_text("\n".join(lines) + "\n")
    assert {t.frame for t in iter_tracks_csv(tmp_path / "sensor.csv", frame="world")} == {
        "sensor"
    }  # the file's own column, not the default
    stated = [replace(f, frame="world") for f in truth]
    write_truth_csv(tmp_path / "stated.csv", stated)
    write_truth_csv(tmp_path / "unstated.csv", truth)
    assert {f.frame for f in read_truth_csv(tmp_path / "stated.csv")} == {"world"}
    assert {f.frame for f in read_truth_csv(tmp_path / "unstated.csv")} == {None}

    def run(tracks_name, truth_name, code=0):
        args = ["evaluate", str(tmp_path / tracks_name), "--truth", str(tmp_path / truth_name)]
        result = CliRunner().invoke(app, args)
        assert result.exit_code == code, result.output
        return " ".join((result.output + str(result.exception or "")).split())

    refused = run("sensor.csv", "stated.csv", code=1)
    assert "in the sensor frame with no sensor pose, the truth in the world frame" in refused
    assert "--output-frame world" in refused
    assert "state its frame" not in run("world.csv", "stated.csv")
    assert "scored in the world frame of the tracks" in run("world.csv", "unstated.csv")
    assert "scored in the sensor frame of the tracks" in run("sensor.csv", "unstated.csv")


@pytest.mark.parametrize(
    ("reader", "text", "message"),
    [
        ("tracks", "scan,stamp,track_id,kind,x,y,frame\n0,0.0,1,person,1,2,odom\n", "odom"),
        ("truth", "scan,stamp,person_id,x,y,frame\n0,0.0,1,1,2,map\n", "'map' is neither"),
        (
            "truth",
            "scan,stamp,person_id,x,y,frame\n0,0.0,1,1,2,world\n1,0.1,1,1,2,sensor\n",
            "line 3: frame 'sensor' differs from 'world'",
        ),
    ],
)
def test_a_frame_column_holds_sensor_or_world(tmp_path, reader, text, message):
    path = tmp_path / "x.csv"
    path.write_text(text)
    with pytest.raises(RecordingError, match=message) as info:
        if reader == "tracks":
            list(iter_tracks_csv(path))
        else:
            read_truth_csv(path)
    assert str(path) in str(info.value)


def test_cli_moves_world_tracks_into_the_laser_frame_the_truth_states(tmp_path):
    """World-frame tracks written with each scan's sensor pose are scored against labels in
    the laser frame (moved with the pose, and said); without the poses they are refused."""
    from laserpeople.scan import Pose2D

    truth, tracks = scene()
    poses = [Pose2D(5.0 + k, -3.0, 0.4 * k) for k in range(len(truth))]
    laser = [
        replace(f, positions=p.inverse_transform_points(f.positions), frame="sensor")
        for f, p in zip(truth, poses, strict=True)
    ]
    write_truth_csv(tmp_path / "labels.csv", laser)
    with_poses = {t.scan_index: replace(t, sensor_pose=poses[t.scan_index]) for t in tracks}
    for name, frames in (("posed.csv", list(with_poses.values())), ("bare.csv", tracks)):
        with TracksCsvWriter(tmp_path / name, frame="world", topic="/scan") as out:
            for t in frames:
                out.write(t)

    def run(name, *more):
        args = ["evaluate", str(tmp_path / name), "--truth", str(tmp_path / "labels.csv")]
        return CliRunner().invoke(app, [*args, *more])

    moved = CliRunner().invoke(
        app,
        [
            "--quiet",
            "evaluate",
            str(tmp_path / "posed.csv"),
            "--truth",
            str(tmp_path / "labels.csv"),
            "--json",
        ],
    )
    assert moved.exit_code == 0, moved.output
    data = json.loads(moved.stdout)
    # the scores of the same tracks and truth in the world frame (test above): 9 of 12,
    # the track of person 2 0.1 m off in 4 scans
    assert (data["misses"], data["false_positives"], data["id_switches"]) == (3, 0, 0)
    assert data["motp_m"] == pytest.approx((5 * 0.0 + 4 * 0.1) / 9, abs=1e-4)
    assert "moved into the sensor frame of the truth" in run("posed.csv").output
    refused = run("bare.csv")
    assert refused.exit_code != 0 and "no sensor pose" in str(refused.exception)


@pytest.mark.parametrize(
    ("kind", "truths"), [("person", "people"), ("leg", "legs"), ("group", "groups")]
)
def test_table_names_what_the_truth_of_the_kind_counts(kind, truths):
    from rich.console import Console

    from laserpeople.cli.evaluate import render
    from laserpeople.evaluation.params import EvaluationParams

    truth, tracks = scene()
    report = evaluate(truth, tracks, EvaluationParams(kind=kind)).result()
    console = Console(record=True, width=200)
    console.print(render(report))
    text = console.export_text()
    assert f"of 12 {kind}-frames matched" in text
    assert f"unmatched {kind}-frames" in text
    assert f"ID switches) / {truths}" in text
    others = {"person", "leg", "group"} - {kind}
    assert not any(f"{other}-frames" in text for other in others)


@pytest.mark.parametrize("kind", ["person", "group"])
def test_followed_table_counts_the_ids_of_the_kind_scored(kind):
    from rich.console import Console

    from laserpeople.cli.evaluate import render_followed
    from laserpeople.evaluation.followed import evaluate_followed
    from laserpeople.io.tracks_csv import TrackIdNames

    truth, tracks = scene()
    metric, _ = evaluate_followed(truth, tracks, 2)
    console = Console(record=True, width=200)
    console.print(render_followed(metric.result(), TrackIdNames(), kind))
    text = console.export_text()
    other = "group" if kind == "person" else "person"
    assert f"{kind} ids" in text and f"{other} ids" not in text
    assert "frames per id: 11: 4" in text  # person 2 matched by track 11 in scans 0-3
