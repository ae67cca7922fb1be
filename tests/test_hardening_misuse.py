"""Misuse by a demanding new user: every command on odd but readable input says what it did
(hardening, third round; docs/damaged-files.md)."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError
from laserpeople.scan import PointSet, Scan


def _finer(scan: Scan) -> Scan:
    """``scan`` with twice the beams over the same field of view (a driver reconfigured to
    a finer resolution): each range repeated."""
    return Scan(
        stamp=scan.stamp,
        angle_min=scan.angle_min,
        angle_increment=scan.angle_increment / 2,
        ranges=np.repeat(scan.ranges, 2)[:-1].copy(),
        range_min=scan.range_min,
        range_max=scan.range_max,
        sensor=scan.sensor,
        pose=scan.pose,
        index=scan.index,
    )


def test_a_beam_layout_change_mid_recording_is_tracked_and_said(tmp_path: Path) -> None:
    from laserpeople.sim import SimResult
    from laserpeople.sim.scenarios import run_scenario

    result = run_scenario("figure-eight", seconds=6.0, seed=1)
    scans = [s if s.index < 120 else _finer(s) for s in result.scans]
    assert scans[0].n_beams == 361 and scans[-1].n_beams == 721
    path = tmp_path / "finer.npz"
    SimResult(scans, result.truth, result.meta).write(path)
    for tracker in ("leg-mht", "csa"):
        out = tmp_path / f"{tracker}.csv"
        run = CliRunner().invoke(
            app,
            ["track", str(path), "--tracker", tracker, "--background", "histogram", "-o", str(out)],
        )
        assert run.exit_code == 0, run.output
        assert "1 beam layout change(s)" in run.output
        assert "at scan 120: 361 beams from -90.00° every 0.500° before, 721 beams" in run.output
        assert out.read_text().count("\n") > 1


def test_the_beam_histogram_learns_again_after_a_layout_change() -> None:
    from laserpeople.background.beam_histogram import BeamHistogramBackground, BeamHistogramParams
    from laserpeople.frame import Frame

    def frame(k: int, n: int, person: slice = slice(0)) -> Frame:
        ranges = np.full(n, 3.0)
        ranges[person] = 1.5
        scan = Scan(
            stamp=0.1 * k,
            angle_min=-1.0,
            angle_increment=2.0 / (n - 1),
            ranges=ranges,
            range_min=0.05,
            range_max=8.0,
            sensor="laser",
            index=k,
        )
        return Frame(
            index=k,
            stamp=scan.stamp,
            scans=(scan,),
            topic="laser",
            points=PointSet.from_scans([scan], "sensor"),
        )

    params = BeamHistogramParams(learn_seconds=1.0)
    model = BeamHistogramBackground(params)
    for k in range(20):  # 2 s of a wall at 3 m: learnt and frozen
        assert not model.learn_foreground(frame(k, 41)).any()
    assert not model.learning and model.layout_changes == 0
    # the same wall seen by 21 beams, a person on beams 5-7: the 41-beam histograms say
    # nothing about these beams; the model learns again as a new one would
    new = BeamHistogramBackground(params)
    for k in range(20, 40):
        seen = frame(k, 21, slice(5, 8) if k >= 35 else slice(0))
        fg = model.learn_foreground(seen)
        assert np.array_equal(fg, new.learn_foreground(seen))
    assert model.layout_changes == 1 and not model.learning
    assert model.counts("laser").shape == new.counts("laser").shape
    assert np.flatnonzero(fg).tolist() == [5, 6, 7]


@pytest.mark.parametrize(
    ("tracker", "text", "message"),
    [
        (
            "leg-mht",
            "[leg_tracker]\npeople.gate_probability = 1.5\n",
            r"\[leg_tracker\] people.gate_probability = 1.5 must be below 1",
        ),
        (
            "group-mht",
            "[group_tracker]\np_c = 1.2\n",
            r"\[group_tracker\] p_c = 1.2 is a probability: it must be in \[0, 1\]",
        ),
        (
            "leg-mht",
            "[leg_tracker]\np_det_free = -0.1\n",
            r"\[leg_tracker\] p_det_free = -0.1 is a probability",
        ),
        (
            "feet-pf",
            "[feet_pf]\nsupport_radius = -1.0\n",
            r"\[feet_pf\] support_radius = -1.0 is in m: it cannot be negative",
        ),
        (
            "leg-mht",
            "[leg_tracker]\npeople.reid.max_dormant = -5.0\n",
            r"\[leg_tracker\] people.reid.max_dormant = -5.0 is in s: it cannot be negative",
        ),
        ("feet-pf", "[feet_pf]\nseed = -1\n", r"\[feet_pf\] seed = -1 is a count"),
        (
            "leg-mht",
            "[beam_histogram]\nbin_width = 0.0\n",
            r"\[beam_histogram\]: bin_width must be positive",
        ),
    ],
)
def test_config_values_out_of_range_name_the_file_and_key(
    tmp_path: Path, tracker: str, text: str, message: str
) -> None:
    config = tmp_path / "my.toml"
    config.write_text(text)
    out = tmp_path / "t.csv"
    run = CliRunner().invoke(
        app, ["track", "--tracker", tracker, "--config", str(config), "--print-config"]
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert re.search(message, str(run.exception)), str(run.exception)
    assert "my.toml" in str(run.exception) and not out.exists()


def test_config_values_in_range_and_signed_ones_are_kept(tmp_path: Path) -> None:
    from laserpeople.config import load_config
    from laserpeople.tracking.legs import LegTrackerParams

    config = tmp_path / "my.toml"
    config.write_text(
        "[leg_tracker]\nkalman.gate_probability = 0.5\npeople.llr_delete = -2.5\n"
        "people.gate_probability = 0.0\nmax_report_unseen = 0.0\n"
    )
    params = load_config(LegTrackerParams, config)  # a signed setting stays negative
    assert params.kalman.gate_probability == 0.5 and params.people.llr_delete == -2.5
    assert params.people.gate_probability == 0.0 and params.max_report_unseen == 0.0


def test_config_bias_may_be_negative(tmp_path: Path) -> None:
    from laserpeople.config import load_config
    from laserpeople.sim.robot import OdometryParams

    config = tmp_path / "my.toml"
    config.write_text(
        f"[{OdometryParams.config_section}]\nheading_bias = -0.02\nheading_noise = 0.001\n"
    )
    params = load_config(OdometryParams, config)  # a drift the other way, in rad/m
    assert abs(params.heading_bias + 0.02) < 1e-12
    config.write_text(f"[{OdometryParams.config_section}]\nheading_noise = -0.001\n")
    with pytest.raises(ConfigError, match=r"heading_noise = -0\.001 is in rad/sqrt"):
        load_config(OdometryParams, config)


def _scans(n: int) -> list[Scan]:
    """``n`` scans of a wall 2 m away, 41 beams, at 10 Hz from 10 s."""
    return [
        Scan(
            stamp=10.0 + 0.1 * k,
            angle_min=-1.0,
            angle_increment=0.05,
            ranges=np.full(41, 2.0),
            range_min=0.05,
            range_max=8.0,
            sensor="scan",
            index=k,
        )
        for k in range(n)
    ]


def _stamps_back_recordings(tmp_path: Path) -> list[Path]:
    """A bag and a CARMEN log whose scan 5 is stamped before scan 4 (a driver's clock
    stepping back; in the bag, received in order: log times at 10 Hz)."""
    from laserpeople.io.carmen import write_carmen_log
    from laserpeople.io.rosbag_writer import open_bag

    scans = [replace(s, stamp=s.stamp - 0.25) if s.index == 5 else s for s in _scans(12)]
    bag, log = tmp_path / "back.bag", tmp_path / "back.log"
    with open_bag(bag) as sink:
        for scan in scans:
            sink.scan(scan, "/scan", "laser", log_stamp=10.0 + 0.1 * scan.index)
    write_carmen_log(log, scans)
    return [bag, log]


def test_a_stamp_going_back_stops_or_is_skipped_and_counted(tmp_path: Path) -> None:
    from laserpeople.errors import UnsortedStampsError
    from laserpeople.io import open_recording

    for path in _stamps_back_recordings(tmp_path):
        with open_recording(path) as rec, pytest.raises(UnsortedStampsError) as err:
            list(rec.scans())
        assert err.value.scan == 5 and "0.150000 s before the previous scan's" in str(err.value)
        assert "--on-error skip" in str(err.value)
        with open_recording(path, on_error="skip") as rec:
            kept = [s.index for s in rec.scans()]
        assert kept == [0, 1, 2, 3, 4, 6, 7, 8, 9, 10, 11]
        assert rec.damaged.count == 1 and "before the previous scan's" in rec.damaged.summary()
        out = tmp_path / f"{path.suffix[1:]}.csv"
        run = CliRunner().invoke(app, ["track", str(path), "--on-error", "skip", "-o", str(out)])
        assert run.exit_code == 0, run.output
        assert "skipped 1 damaged scan(s)" in run.output and "11 scans tracked" in run.output


def _tracks_csv(path: Path, scans: range) -> Path:
    header = "scan,stamp,track_id,kind,x,y,vx,vy,cov_xx,cov_xy,cov_yy,size,labels,topic,frame\n"
    rows = "".join(
        f"{k},{100 + 0.1 * k:.6f},1,person,{0.1 * k:.3f},1.0,1.0,0,0.01,0,0.01,1,,/scan,sensor\n"
        for k in scans
    )
    path.write_text(header + rows)
    return path


def _truth_csv(path: Path, scans: range, stamp0: float = 100.0) -> Path:
    rows = "".join(f"{k},{stamp0 + 0.1 * k:.6f},7,{0.1 * k:.3f},1.0\n" for k in scans)
    path.write_text("scan,stamp,person_id,x,y\n" + rows)
    return path


def test_evaluate_refuses_truth_and_tracks_that_share_no_scan(tmp_path: Path) -> None:
    """Truth of other scans and another clock is an error, not MOTA 0 (nothing is scored);
    truth of later scans of the tracks' own clock is all missed, with a warning."""
    from laserpeople.errors import EvaluationError

    tracks = _tracks_csv(tmp_path / "t.csv", range(0, 50))
    same = _truth_csv(tmp_path / "same.csv", range(10, 40))
    other = _truth_csv(tmp_path / "other.csv", range(1000, 1030), stamp0=500.0)
    later = _truth_csv(tmp_path / "later.csv", range(1000, 1030))
    run = CliRunner().invoke(app, ["evaluate", str(tracks), "--truth", str(same)])
    assert run.exit_code == 0, run.output
    assert "no scored scan has track rows" not in run.output
    for extra in ([], ["--followed-person", "auto"]):
        run = CliRunner().invoke(app, ["evaluate", str(tracks), "--truth", str(other), *extra])
        assert run.exit_code == 1 and isinstance(run.exception, EvaluationError), run.output
        assert str(run.exception).startswith(
            "truth and tracks share no scan: the truth covers scans 1000-1029 (stamps "
            "600.000-602.900 s), the tracks scans 0-49 (stamps 100.000-104.900 s); nothing "
            "was scored (not all missed)"
        ), run.exception
        run = CliRunner().invoke(app, ["evaluate", str(tracks), "--truth", str(later), *extra])
        assert run.exit_code == 0, run.output
        text = " ".join(run.output.split())
        assert (
            "no scored scan has track rows: the truth covers scans 1000-1029 (stamps "
            "200.000-202.900 s), the tracks scans 0-49 (stamps 100.000-104.900 s)"
        ) in text, text


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--duration", "-1"], "--duration -1.0 must be a finite number of seconds above 0"),
        (["--duration", "nan"], "--duration nan must be a finite number of seconds"),
        (["--tf-wait", "-0.5"], "--tf-wait -0.5 must be a finite number of seconds (0 or more)"),
        (["--order-wait", "inf"], "--order-wait inf must be a finite number of seconds"),
    ],
)
def test_live_refuses_times_that_are_not_seconds(args: list[str], message: str) -> None:
    pytest.importorskip("zenoh")
    run = CliRunner().invoke(app, ["live", *args])
    assert isinstance(run.exception, ConfigError) and message in str(run.exception)


def test_live_refuses_negative_counts() -> None:
    for args in (["--max-scans", "-1"], ["--domain", "-5"], ["--domain", "233"]):
        run = CliRunner().invoke(app, ["live", *args, "--duration", "0.3"])
        assert run.exit_code == 2 and "Invalid value for" in run.output, run.output


def test_live_refuses_the_sensor_frame_for_several_lasers() -> None:
    # refused before connecting (it stopped at the first fused frame, mid-run)
    run = CliRunner().invoke(
        app,
        ["live", "--frame", "sensor", "--topic", "/front", "--topic", "/back", "--duration", "0.3"],
    )
    assert isinstance(run.exception, ConfigError), run.output
    assert "--frame sensor with 2 lasers" in str(run.exception)


def test_live_without_a_single_scan_is_an_error_not_an_empty_success() -> None:
    pytest.importorskip("zenoh")
    from laserpeople.errors import LaserPeopleError
    from live_harness import free_port

    # a peer whose endpoint nobody listens on opens without complaint and waits
    run = CliRunner().invoke(
        app, ["live", "--connect", f"tcp/127.0.0.1:{free_port()}", "--duration", "0.5"]
    )
    assert isinstance(run.exception, LaserPeopleError), run.output
    assert "no scan arrived on /scan: nothing was tracked" in str(run.exception)
    assert "/scan: 0 scans received" in run.output


def test_view_refuses_negative_scan_indices(tmp_path: Path) -> None:
    for option in ("--scan", "--start", "--stop"):
        run = CliRunner().invoke(
            app, ["view", "any.bag", option, "-5", "-o", str(tmp_path / "v.png")]
        )
        assert run.exit_code == 2 and f"Invalid value for '{option}'" in run.output, run.output


def test_small_outputs_go_into_missing_folders_like_the_others(tmp_path: Path) -> None:
    """train, align and fit create the folder of -o as track, detect and view do (train's
    model was lost to a traceback after the training), and an unwritable path is an error
    naming it."""
    from laserpeople.alignment import Mount, write_mounts
    from laserpeople.detection.detector import default_model
    from laserpeople.errors import LaserPeopleError, ModelFileError
    from laserpeople.fitting.output import write
    from laserpeople.scan import Pose2D
    from laserpeople.tracking.nearest import NearestNeighbourParams

    model = tmp_path / "a" / "b" / "model.json"
    default_model().save(model)
    assert model.read_text().startswith("{")
    mounts = tmp_path / "c" / "mounts.toml"
    write_mounts(mounts, [Mount("front", "base_link", Pose2D(0.4, 0.0, 0.0), None)])
    assert '[mounts."front"]' in mounts.read_text()
    fitted = tmp_path / "d" / "nn.toml"
    write(fitted, NearestNeighbourParams(), [], [], ["fitted by hand"])
    assert fitted.read_text() == "# fitted by hand\n"
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(ModelFileError, match=r"cannot write the model: .*-o"):
        default_model().save(blocker / "model.json")
    with pytest.raises(LaserPeopleError, match="cannot write the mounts"):
        write_mounts(blocker / "m.toml", [])
    with pytest.raises(LaserPeopleError, match="cannot write the parameters"):
        write(blocker / "nn.toml", NearestNeighbourParams(), [], [], [])
    assert sorted(p.name for p in tmp_path.rglob(".*partial*")) == []


def test_train_writes_its_model_into_a_missing_folder(tmp_path: Path, shared_data: Path) -> None:
    out = tmp_path / "new" / "model.json"
    neko = shared_data / "neko7055"
    run = CliRunner().invoke(
        app,
        ["train", "--neko", str(neko), "--neko-frames", "0-19", "--rounds", "1", "-o", str(out)],
    )
    assert run.exit_code == 0, run.output
    assert out.is_file()


def test_intensities_of_another_length_are_left_out_and_said(tmp_path: Path) -> None:
    """A driver writing intensities of another length than the ranges: the ranges are
    read, the intensities left out and counted (the whole recording was refused)."""
    from laserpeople.io import open_recording
    from laserpeople.io.rosbag_writer import write_laserscan_bag

    scans = [
        Scan(
            stamp=10.0 + 0.1 * k,
            angle_min=-1.0,
            angle_increment=0.05,
            ranges=np.full(41, 2.0 + 0.01 * k),
            range_min=0.05,
            range_max=8.0,
            intensities=np.ones(41),
            sensor="scan",
            index=k,
        )
        for k in range(6)
    ]
    path = tmp_path / "i.mcap"
    write_laserscan_bag(path, scans)
    good = open_recording(path)
    assert all(s.intensities is not None for s in good.scans())
    assert good.damaged.summary() == ""
    # the same bag with 30 intensities per scan
    write_laserscan_bag(
        path, [replace(s, intensities=None) for s in scans[:2]] + [_short(s) for s in scans[2:]]
    )
    with open_recording(path) as rec:
        read = list(rec.scans())
        assert [s.ranges[0] for s in read] == pytest.approx([2.0 + 0.01 * k for k in range(6)])
        assert all(s.intensities is None for s in read)
        assert rec.damaged.intensities_dropped == 4
        assert (
            "4 scan(s) read without their intensities, which do not match their ranges in "
            "number (first /scan scan 2: 30 intensities for 41 ranges); the ranges are kept"
        ) in rec.damaged.summary()
    out = tmp_path / "t.csv"
    run = CliRunner().invoke(app, ["track", str(path), "-o", str(out)])
    assert run.exit_code == 0, run.output
    assert "4 scan(s) read without their intensities" in run.output
    assert "6 scans tracked" in run.output


def _short(scan: Scan) -> Scan:
    """``scan`` with 30 intensities, bypassing the check a Scan makes (as a bag can)."""
    out = replace(scan, intensities=None)
    object.__setattr__(out, "intensities", np.ones(30))
    return out


def test_batch_rows_say_what_the_read_left_out(tmp_path: Path) -> None:
    """A batch row carries what `track` would have said about the read (skipped scans),
    in the summary's notes column; a clean recording's notes are empty."""
    pytest.importorskip("pyarrow")
    from laserpeople.batch import TrackOptions, resolve
    from laserpeople.batch.task import RecordingTask, track_recording

    bag = _stamps_back_recordings(tmp_path)[0]
    resolved = resolve(TrackOptions(topics=("all",), on_error="skip"))
    task = RecordingTask(bag, "back", tmp_path / "out", resolved)
    (row,) = track_recording(task)
    assert row.status == "done" and row.scans == 11, row.error
    assert "skipped 1 damaged scan(s) (/scan scan 5: stamp 10.250000 s" in row.notes
    clean = tmp_path / "clean.bag"
    from laserpeople.io.rosbag_writer import write_laserscan_bag

    write_laserscan_bag(clean, _scans(12))
    (row,) = track_recording(RecordingTask(clean, "clean", tmp_path / "out", resolved))
    assert row.status == "done" and row.notes == ""
