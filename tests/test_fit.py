"""``laserpeople fit``: event counting on hand-made sequences with hand-computed
probabilities, the group event counter on a scripted split/merge sequence, the TOML round
trip through ``track --config``, the command line and its errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.config import load_config
from laserpeople.fitting import data
from laserpeople.fitting.estimates import (
    UNLEARNED,
    AccelTally,
    Estimate,
    FitError,
    NotEnoughEventsError,
    multinomial,
    quantile,
    rate,
)
from laserpeople.fitting.flow import WORSE_BY, FitResult
from laserpeople.fitting.groups import GroupEventCounts, count_group_events
from laserpeople.fitting.legs import (
    DEL,
    DET,
    OCC,
    LegEventCounts,
    LegFitParams,
    LegMHTFitter,
    associate,
    count_followed,
    count_full,
    count_legs,
    set_dotted,
)
from laserpeople.fitting.output import check, render
from laserpeople.scan import Scan
from laserpeople.tracking.legs import LegTrackerParams
from laserpeople.tracks import Detections
from laserpeople.truth import TruthFrame

# --- estimators ---------------------------------------------------------------------------


def test_multinomial_is_the_jeffreys_estimate() -> None:
    est = multinomial({"a": 3, "b": 1, "c": 0}, "things", min_events=4)
    # (k + 1/2) / (n + 3/2) with n = 4
    assert [e.value for e in est] == pytest.approx([3.5 / 5.5, 1.5 / 5.5, 0.5 / 5.5])
    assert sum(e.value for e in est) == pytest.approx(1.0)
    assert est[0].note == "3 of 4 things" and est[0].events == 4


def test_too_few_events_say_how_many_are_needed() -> None:
    with pytest.raises(NotEnoughEventsError, match=r"4 counted, at least 50 needed"):
        multinomial({"a": 3, "b": 1}, "things", min_events=50)
    with pytest.raises(NotEnoughEventsError, match="p_x"):
        rate("p_x", 3, 10.0, "events", "scans", exposure_events=2, min_events=3)
    with pytest.raises(NotEnoughEventsError):
        quantile("gate", [1.0, math.nan], 0.5, "steps", min_events=2)


def test_too_few_events_name_only_the_parameters_learned() -> None:
    counts = {"people.q_two": 8, "people.q_one": 2, UNLEARNED: 10}
    with pytest.raises(NotEnoughEventsError) as caught:
        multinomial(counts, "clutter-site-scans", min_events=50)
    message = str(caught.value)
    assert "to learn people.q_two, people.q_one: 20 counted" in message
    assert UNLEARNED not in message


def test_rate_and_quantile() -> None:
    r = rate("lam", 7, 20.0, "false alarms", "m^2 scans", exposure_events=4, min_events=4)
    assert r.value == pytest.approx(7.5 / 20.0)
    q = quantile("g", [0.0, 1.0, 2.0, 3.0, 4.0], 0.5, "steps", min_events=5)
    assert q.value == pytest.approx(2.0)


def test_accel_psd_of_constant_acceleration_by_hand() -> None:
    # x = a t^2 / 2 sampled every h: mean velocities differ by a h; weight 2 (2h) / 3
    a, h = 2.0, 0.1
    t = np.arange(6) * h
    tally = AccelTally()
    tally.add(np.column_stack([0.5 * a * t**2, np.zeros_like(t)]), t)
    assert tally.triples == 4
    assert tally.estimate("q", "test", 1).value == pytest.approx((a * h) ** 2 / (4 * h / 3))


def test_accel_psd_recovers_a_simulated_white_acceleration_process() -> None:
    # exact discrete-time white-noise acceleration model (Bar-Shalom & Li), independent
    # of the estimator: Q = q [[dt^3/3, dt^2/2], [dt^2/2, dt]] per axis
    rng = np.random.default_rng(3)
    q, dt, n = 2.0, 0.1, 40000
    cov = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    chol = np.linalg.cholesky(cov)
    state = np.zeros((2, 2))  # axis x (pos, vel)
    xs = np.empty((n, 2))
    for k in range(n):
        noise = rng.standard_normal((2, 2)) @ chol.T
        state = np.column_stack([state[:, 0] + dt * state[:, 1], state[:, 1]]) + noise
        xs[k] = state[:, 0]
    tally = AccelTally()
    tally.add(xs, np.arange(n) * dt)
    assert tally.estimate("q", "sim", 10).value == pytest.approx(q, rel=0.03)


def test_accel_tally_refuses_unordered_stamps() -> None:
    with pytest.raises(FitError, match="increase"):
        AccelTally().add(np.zeros((3, 2)), np.array([0.0, 0.2, 0.1]))


# --- leg events ---------------------------------------------------------------------------


def test_associate_is_optimal_within_the_gate() -> None:
    ti, di = associate(
        np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([[0.05, 0.0], [1.5, 0.0], [0.9, 0.0]]), 0.2
    )
    assert sorted(zip(ti.tolist(), di.tolist(), strict=True)) == [(0, 0), (1, 2)]
    ti, di = associate(np.zeros((0, 2)), np.ones((3, 2)), 0.2)
    assert ti.size == di.size == 0


def _hits(scans: dict[int, tuple[float, float]]) -> dict[int, np.ndarray]:
    return {k: np.array(v) for k, v in scans.items()}


def test_count_legs_by_hand() -> None:
    # left leg detected in scans 0 1 3 4, right leg in 1 2 3; 10 scans 0.1 s apart
    stamps = np.arange(10) * 0.1
    detected = {
        (1, 0): _hits({0: (0.0, 0.0), 1: (0.1, 0.0), 3: (0.3, 0.0), 4: (0.4, 0.0)}),
        (1, 1): _hits({1: (0.0, 0.2), 2: (0.1, 0.2), 3: (0.2, 0.2)}),
    }
    c = LegEventCounts()
    count_legs(stamps, detected, max_gap=1.0, counts=c)
    # left: scan 1 det (right not live at 0: free), 2 occ (approved), 3 det, 4 det
    # (approved), deleted after 4 (right not live at 4: free)
    # right: 2 det, 3 det (approved), deleted after 3 (left live at 3: approved)
    assert c.free.tolist() == [1, 0, 1]
    assert c.approved.tolist() == [4, 1, 1]
    assert c.new == 2
    assert sorted(c.leg_steps) == pytest.approx([0.1, 0.1, 0.1, 0.1, 0.2])


def test_a_long_gap_ends_the_ideal_track() -> None:
    stamps = np.arange(30) * 0.1
    c = LegEventCounts()
    count_legs(stamps, {(0, 0): _hits({0: (0, 0), 15: (0, 0)})}, max_gap=1.0, counts=c)
    assert c.new == 2
    assert c.free[DEL] == 2 and c.free[DET] == 0 and c.free[OCC] == 0
    # the track that ends in the last scan is not deleted (the recording ends)
    c = LegEventCounts()
    count_legs(stamps[:16], {(0, 0): _hits({0: (0, 0), 15: (0, 0)})}, 1.0, c)
    assert c.free[DEL] == 1


def _scan(k: int) -> Scan:
    # 3 beams of 1 m, 0.5 rad apart: visible area 3 * 1^2 * 0.5 / 2 = 0.75 m^2
    return Scan(stamp=0.1 * k, angle_min=0.0, angle_increment=0.5, ranges=np.ones(3), index=k)


def _dets(k: int, xy: list[tuple[float, float]]) -> Detections:
    m = len(xy)
    return Detections(
        0.1 * k,
        k,
        np.array(xy, dtype=float).reshape(m, 2),
        np.tile(np.eye(2) * 0.01, (m, 1, 1)),
        np.ones(m),
    )


def _legs_truth(k: int) -> TruthFrame:
    return TruthFrame(
        stamp=0.1 * k,
        scan_index=k,
        person_ids=np.array([7]),
        positions=np.array([[2.0, 0.15]]),
        velocities=np.zeros((1, 2)),
        group_ids=np.array([-1]),
        leg_positions=np.array([[[2.0, 0.0], [2.0, 0.3]]]),
        hues=np.zeros(1),
    )


def test_count_full_by_hand() -> None:
    detections = {
        0: [(2.05, 0.0), (2.0, 0.3), (5.0, 5.0)],  # both legs, one false alarm
        1: [(2.0, 0.31)],  # right leg only
        2: [],  # nothing
    }
    rec = data.build(
        "hand",
        [_scan(k) for k in range(3)],
        [_legs_truth(k) for k in range(3)],
        lambda s: _dets(s.index, detections[s.index]),
        followed=False,
    )
    assert rec.areas.tolist() == pytest.approx([0.75, 0.75, 0.75])
    c = count_full(rec, LegFitParams())
    assert (c.false, c.matched, c.scans) == (1, 3, 3)
    assert c.area == pytest.approx(2.25)
    # the person's candidate lives from scan 0 (two legs) to scan 1 (its last leg): one
    # scan counted, with one leg
    assert c.persons.tolist() == [0, 1, 0]
    assert c.pair_distances == pytest.approx([math.hypot(0.05, 0.3)])
    # left: born at 0, deleted at 1 (right live at 0: approved)
    # right: born at 0, detected at 1 (left live at 0: approved), deleted at 2 (left not
    # live at 1: free)
    assert c.approved.tolist() == [1, 0, 1]
    assert c.free.tolist() == [0, 0, 1]
    assert c.new == 2


def test_probabilities_of_the_hand_sequence() -> None:
    from laserpeople.fitting.legs import estimate

    c = LegEventCounts(
        free=np.array([0, 0, 1]),
        approved=np.array([1, 0, 1]),
        new=2,
        false=1,
        scans=3,
        area=2.25,
        persons=np.array([0, 1, 0]),
        clutter=np.array([2, 0, 1]),
        leg_steps=[0.1],
        pair_distances=[0.3],
    )
    c.leg_accel.add(np.array([[0.0, 0.0], [0.1, 0.0], [0.3, 0.0]]), np.array([0.0, 0.1, 0.2]))
    c.person_accel.add(np.array([[0.0, 0.0], [0.1, 0.0], [0.3, 0.0]]), np.array([0.0, 0.1, 0.2]))
    got = {e.key: e.value for e in estimate(c, LegFitParams(min_events=1), full=True)[0]}
    assert got["p_det_approved"] == pytest.approx(1.5 / 3.5)
    assert got["p_occ_approved"] == pytest.approx(0.5 / 3.5)
    assert got["p_del_free"] == pytest.approx(1.5 / 2.5)
    assert got["lambda_fal"] == pytest.approx(1.5 / 2.25)
    assert got["lambda_new"] == pytest.approx(2.5 / 2.25)
    assert got["people.p_one"] == pytest.approx(1.5 / 2.5)
    assert got["people.q_two"] == pytest.approx(2.5 / 4.5)
    # velocities 1 then 2 m/s over 0.1 s steps: d = 1, weight 2 (0.2) / 3
    assert got["kalman.accel_psd"] == pytest.approx(1.0 / (0.4 / 3))
    assert got["people.pair_distance"] == pytest.approx(0.3)


def test_learned_values_the_tracker_refuses_are_a_fit_error() -> None:
    from laserpeople.fitting.legs import with_learned

    # people who never move give a process noise of 0, which the Kalman filter refuses
    still = [Estimate("kalman.accel_psd", 0.0, "fit to 12 triples", 12)]
    with pytest.raises(FitError, match=r"not valid parameters.*accel_psd"):
        with_learned(LegTrackerParams(), still)
    ok = with_learned(LegTrackerParams(), [Estimate("kalman.accel_psd", 3.0, "fit", 12)])
    assert ok.kalman.accel_psd == 3.0


def test_count_followed_by_hand() -> None:
    # the followed person labelled in scans 0-3 of 5; detections within 0.5 m are its legs
    detections = {
        0: [(1.1, 0.0), (0.9, 0.1), (3.0, 0.0)],  # two legs + someone else
        1: [(1.2, 0.0)],
        2: [(2.0, 0.0)],  # 1 m away: not its leg
        3: [(1.0, 0.1), (1.0, -0.1), (1.05, 0.0)],  # three near: two legs counted
        4: [],
    }
    truth = [
        TruthFrame.from_positions(0.1 * k, k, np.array([0]), np.array([[1.0, 0.0]]))
        for k in range(4)
    ]
    rec = data.build(
        "followed",
        [_scan(k) for k in range(5)],
        truth,
        lambda s: _dets(s.index, detections[s.index]),
        followed=True,
    )
    c = count_followed(rec, LegFitParams())
    # candidate from scan 0 to 3: scan 1 one leg, 2 none, 3 two
    assert c.persons.tolist() == [1, 1, 1]
    # approved legs over scans 1-3 (after the first): 1 + 0 + 2 detected of 6, deleted
    # both after scan 3 (the recording goes on)
    assert c.approved[DET] == 3 and c.approved[OCC] == 3 and c.approved[DEL] == 2
    assert c.free.tolist() == [0, 0, 0] and c.false == 0


def test_followed_truth_learns_approved_and_people_only() -> None:
    rng = np.random.default_rng(0)
    n = 120
    truth = [
        TruthFrame.from_positions(0.1 * k, k, np.array([3]), np.array([[1.0 + 0.1 * k, 0.0]]))
        for k in range(n)
    ]
    dets = {
        k: [(1.0 + 0.1 * k + 0.1, 0.1), (1.0 + 0.1 * k - 0.1, -0.1)][: int(rng.integers(0, 3))]
        for k in range(n)
    }
    rec = data.build(
        "f",
        [_scan(k) for k in range(n)],
        truth,
        lambda s: _dets(s.index, dets[s.index]),
        followed=True,
    )
    fitter = LegMHTFitter(settings=LegFitParams(min_events=10)).fit([rec])
    keys = {e.key for e in fitter.estimates_}
    assert {"p_det_approved", "people.pair_distance", "people.accel_psd"} <= keys
    assert not keys & {"p_det_free", "lambda_fal", "people.p_two", "people.q_two"}
    assert dict(fitter.kept_)["lambda_fal"].startswith("followed-person truth")
    seen = sum(len(dets[k]) for k in range(1, n))  # legs after the first labelled scan
    p_det = next(e for e in fitter.estimates_ if e.key == "p_det_approved")
    # 2 (n - 1) approved leg-scans, nobody deleted (labelled up to the last scan)
    assert p_det.value == pytest.approx((seen + 0.5) / (2 * (n - 1) + 1.5))
    assert fitter.params_.p_det_free == LegTrackerParams().p_det_free


def test_set_dotted_replaces_nested_values() -> None:
    p = set_dotted(LegTrackerParams(), {"lambda_new": 0.01, "kalman.accel_psd": 5.0})
    assert p.lambda_new == 0.01 and p.kalman.accel_psd == 5.0
    assert p.kalman.gate_probability == LegTrackerParams().kalman.gate_probability


def test_truth_that_cannot_be_paired_is_refused() -> None:
    truth = [
        TruthFrame.from_positions(0.0, 500 + k, np.array([0]), np.zeros((1, 2))) for k in range(3)
    ]
    with pytest.raises(FitError, match="cannot be paired"):
        data.build(
            "x", [_scan(k) for k in range(3)], truth, lambda s: _dets(s.index, []), followed=True
        )


def test_split_by_recording_and_by_time() -> None:
    recs = [
        data.build(
            f"r{i}",
            [_scan(k) for k in range(10)],
            [_legs_truth(k) for k in range(10)],
            lambda s: _dets(s.index, []),
            followed=False,
        )
        for i in range(4)
    ]
    train, val = data.split(recs, 0.3)
    assert [r.name for r in train] == ["r0", "r1", "r2"] and [r.name for r in val] == ["r3"]
    train, val = data.split(recs[:1], 0.4)
    assert [s.index for s in train[0].scans] == list(range(6))
    assert sorted(val[0].truth) == [6, 7, 8, 9]
    assert data.split(recs, 0.0) == (recs, [])
    with pytest.raises(FitError):
        data.split(recs, 1.0)


# --- group events -------------------------------------------------------------------------


def test_group_events_on_a_scripted_split_and_merge() -> None:
    g, p = (lambda i: ("g", i)), (lambda i: ("p", i))
    seq = [
        {1: g(0), 2: g(0), 3: p(3)},  # group 0 of people 1, 2; person 3 alone
        {1: g(0), 2: g(0), 3: p(3)},
        {1: g(1), 2: g(2), 3: p(3)},  # group 0 splits
        {1: g(1), 2: g(2)},  # person 3 occluded
        {1: g(1), 2: g(2), 3: p(3)},  # ... and seen again
        {1: g(1), 2: g(3), 3: g(3)},  # group 2 and person 3 merge
        {2: g(3), 3: g(3)},  # group 1 gone for good
        {2: g(3), 3: g(3), 4: p(4)},  # a new person
    ]
    c = count_group_events(seq, [0.1 * k for k in range(len(seq))], max_gap=1.0)
    # model events per live track and transition: 2, 1 + split, 3, 3, 1 + merge, 2, 1
    assert (c.continued, c.split, c.merged) == (13, 1, 1)
    # matched 2 + 1 + 2 + 3 + 1 + 1 + 1; person 3 occluded once; group 1 terminated
    assert (c.matched, c.occluded, c.terminated) == (11, 1, 1)
    assert (c.new, c.transitions) == (3, 7)


def test_group_occlusion_longer_than_the_gap_is_a_termination() -> None:
    seq = [{1: ("p", 1)}] + [{} for _ in range(15)] + [{1: ("p", 1)}]
    c = count_group_events(seq, [0.1 * k for k in range(len(seq))], max_gap=1.0)
    assert c.terminated == 1 and c.occluded == 0 and c.new == 2


def test_group_counts_merge() -> None:
    a = GroupEventCounts(1, 2, 3, 4, 5, 6, 7, 8, ["a"])
    b = a.merge(a)
    assert (b.continued, b.transitions, b.sources) == (2, 16, ["a", "a"])


# --- output -------------------------------------------------------------------------------


def test_check_refuses_non_finite_and_out_of_range() -> None:
    with pytest.raises(FitError, match="not finite"):
        check([Estimate("kalman.accel_psd", math.nan, "x", 10)])
    with pytest.raises(FitError, match="outside"):
        check([Estimate("people.p_two", 1.5, "x", 10)])
    check([Estimate("p_det_free", 0.3, "x", 10)])


def test_render_puts_nested_keys_in_their_tables() -> None:
    text = render(
        LegTrackerParams(),
        [Estimate("lambda_new", 0.01, "5 new", 9), Estimate("kalman.accel_psd", 4.0, "fit", 9)],
        [("p_det_free", "why")],
        ["head"],
    )
    assert text.index("[leg_tracker]") < text.index("lambda_new = 0.01  # 5 new")
    assert text.index("[leg_tracker.kalman]") < text.index("accel_psd = 4.0")
    assert "#   p_det_free: why" in text


# --- command line -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sims(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    out = tmp_path_factory.mktemp("fit")
    paths = []
    for seed in (0, 1):
        path = out / f"r{seed}.npz"
        result = CliRunner().invoke(
            app,
            [
                "--quiet",
                "simulate",
                "randomised",
                "--seed",
                str(seed),
                "--seconds",
                "12",
                "-o",
                str(path),
            ],
        )
        assert result.exit_code == 0, result.output
        paths.append(path)
    return paths


def test_fit_help() -> None:
    result = CliRunner().invoke(app, ["fit", "--help"])
    assert result.exit_code == 0
    assert "--truth" in result.output and "--validation" in result.output


@pytest.mark.slow
def test_fit_writes_toml_that_track_reads(sims: list[Path], tmp_path: Path) -> None:
    from laserpeople.fitting.flow import learn

    out = tmp_path / "params.toml"
    result = CliRunner().invoke(
        app, ["--quiet", "fit", *map(str, sims), "-o", str(out), "--min-events", "20"]
    )
    assert result.exit_code == 0, result.output
    assert "validation: default vs learned" in result.output
    text = out.read_text()
    assert "[leg_tracker.kalman]" in text and "# training data: r0.npz" in text
    loaded = load_config(LegTrackerParams, out)
    again = learn(sims, min_events=20)
    assert loaded == again.params
    assert loaded.lambda_fal == pytest.approx(
        next(e.value for e in again.estimates if e.key == "lambda_fal")
    )
    tracks = tmp_path / "tracks.csv"
    run = CliRunner().invoke(
        app, ["--quiet", "track", str(sims[1]), "--config", str(out), "-o", str(tracks)]
    )
    assert run.exit_code == 0, run.output
    assert tracks.read_text().startswith("scan,")


def test_fit_refuses_too_few_events(sims: list[Path], tmp_path: Path) -> None:
    result = CliRunner().invoke(
        app,
        [
            "fit",
            str(sims[0]),
            "-o",
            str(tmp_path / "p.toml"),
            "--validation",
            "0",
            "--min-events",
            "100000",
        ],
    )
    assert isinstance(result.exception, NotEnoughEventsError)
    assert "at least 100000 needed" in str(result.exception)
    assert not (tmp_path / "p.toml").exists()


def test_fit_errors(sims: list[Path], tmp_path: Path) -> None:
    out = str(tmp_path / "p.toml")
    result = CliRunner().invoke(app, ["fit", str(sims[0]), "-o", out, "--tracker", "csa"])
    assert isinstance(result.exception, FitError) and "leg-mht" in str(result.exception)
    result = CliRunner().invoke(app, ["fit", *map(str, sims), "-o", out, "--truth", "a.csv"])
    assert isinstance(result.exception, FitError) and "1 --truth for 2" in str(result.exception)
    csv = tmp_path / "far.csv"
    csv.write_text(
        "scan,stamp,person_id,x,y\n" + "".join(f"{9000 + k},0,0,1,1\n" for k in range(5))
    )
    result = CliRunner().invoke(app, ["fit", str(sims[0]), "-o", out, "--truth", str(csv)])
    assert isinstance(result.exception, FitError) and "cannot be paired" in str(result.exception)
    result = CliRunner().invoke(app, ["fit", str(sims[0]), "-o", str(sims[0])])
    assert result.exception is not None and "write over" in str(result.exception)


def test_fit_group_tracker(tmp_path: Path) -> None:
    from laserpeople.tracking.groups.params import GroupTrackerParams

    npz = tmp_path / "hall.npz"
    res = CliRunner().invoke(
        app, ["--quiet", "simulate", "entrance-hall", "--seconds", "8", "-o", str(npz)]
    )
    assert res.exit_code == 0, res.output
    out = tmp_path / "groups.toml"
    settings = tmp_path / "settings.toml"
    settings.write_text("[fit_groups]\nmax_gap = 1.0\n")
    res = CliRunner().invoke(
        app,
        [
            "--quiet",
            "fit",
            str(npz),
            "--tracker",
            "group-mht",
            "-o",
            str(out),
            "--validation",
            "0.25",
            "--min-events",
            "5",
            "--config",
            str(settings),
        ],
    )
    assert res.exit_code == 0, res.output
    params = load_config(GroupTrackerParams, out)
    assert params.p_c + params.p_s + params.p_g == pytest.approx(1.0)
    assert params.p_m + params.p_o + params.p_t == pytest.approx(1.0)
    assert params.p_f == GroupTrackerParams().p_f
    assert "clustering error" in res.output
    assert "p_f: the labels' foreground" in out.read_text()
    # only the data-association probabilities
    only = tmp_path / "association.toml"
    args = ["--quiet", "fit", str(npz), "--tracker", "group-mht", "--validation", "0.25"]
    args += ["--min-events", "5", "--config", str(settings), "-o", str(only)]
    res = CliRunner().invoke(app, [*args, "--learn", "p_[mot]", "--learn", "p_n"])
    assert res.exit_code == 0, res.output
    chosen = load_config(GroupTrackerParams, only)
    assert (chosen.p_m, chosen.p_n) == (params.p_m, params.p_n)
    assert chosen.p_c == GroupTrackerParams().p_c
    assert "p_c: not chosen by --learn" in only.read_text()
    res = CliRunner().invoke(app, [*args, "--learn", "p_m"])  # p_m + p_o + p_t != 1
    assert isinstance(res.exception, FitError) and "not valid parameters" in str(res.exception)
    res = CliRunner().invoke(app, [*args, "--learn", "kalman.*"])
    assert isinstance(res.exception, FitError) and "no learned value" in str(res.exception)


def test_clutter_evidence_by_hand() -> None:
    from laserpeople.fitting.legs import clutter_evidence

    false_at = [
        (0, np.array([[0.0, 0.0], [0.3, 0.0]])),  # site A born
        (1, np.array([[0.0, 0.0]])),  # one
        (2, np.zeros((0, 2))),  # none
        (3, np.array([[0.1, 0.0], [0.0, 0.1]])),  # two
        (4, np.array([[5.0, 5.0]])),  # site B fires in one scan only: not a site
        (20, np.array([[0.0, 0.0]])),  # site A again after 1.7 s: a new candidate
        (21, np.array([[0.0, 0.0]])),  # one
    ]
    stamps = np.arange(25) * 0.1
    assert clutter_evidence(false_at, stamps, 0.5, 2, 1.0).tolist() == [1, 2, 1]
    assert clutter_evidence([], stamps, 0.5, 1, 1.0).tolist() == [0, 0, 0]


def test_clutter_tracks_are_born_and_not_false_alarms() -> None:
    from laserpeople.fitting.legs import count_clutter_tracks

    stamps = np.arange(20) * 0.1
    false_at = [
        (0, np.array([[1.0, 0.0], [3.0, 0.0]])),
        (1, np.array([[1.05, 0.0]])),  # continues the track at (1, 0)
        (2, np.array([[5.0, 5.0]])),  # once only: a false alarm
        (3, np.array([[1.0, 0.02], [3.3, 0.0]])),  # (1, 0) again; 0.3 m from (3, 0): new
        (15, np.array([[3.0, 0.0]])),  # 1.5 s after (3, 0) at scan 0: not the same track
    ]
    c = LegEventCounts(false=7)
    count_clutter_tracks(false_at, stamps, LegFitParams(), c)
    # one clutter track, scans 0 1 3: born, detected at 1, occluded at 2, detected at 3,
    # deleted after 3 (free: no other leg); the other four stay false alarms
    assert (c.new, c.clutter_tracks, c.false) == (1, 1, 4)
    assert c.free.tolist() == [2, 1, 1]
    assert c.approved.tolist() == [0, 0, 0]


def test_fit_with_followed_person_truth_csv(tmp_path: Path) -> None:
    from laserpeople.io import open_recording
    from laserpeople.io.truth_csv import write_truth_csv

    npz = tmp_path / "demo.npz"
    res = CliRunner().invoke(
        app, ["--quiet", "simulate", "demo", "--seconds", "12", "-o", str(npz)]
    )
    assert res.exit_code == 0, res.output
    rec = open_recording(npz)
    pose = next(iter(rec.scans())).pose
    frames = list(rec.truth())
    rec.close()
    assert pose is not None
    followed = int(frames[0].person_ids[0])
    # one person labelled, in the laser frame, as a person-following benchmark writes it
    labels = [
        TruthFrame.from_positions(
            f.stamp,
            f.scan_index,
            np.array([followed]),
            pose.inverse_transform_points(f.positions[f.person_ids == followed]),
        )
        for f in frames
        if followed in f.person_ids
    ]
    csv = tmp_path / "followed.csv"
    write_truth_csv(csv, labels)
    out = tmp_path / "p.toml"
    res = CliRunner().invoke(
        app,
        ["--quiet", "fit", str(npz), "--truth", str(csv), "-o", str(out), "--min-events", "10"],
    )
    assert res.exit_code == 0, res.output
    assert "identity recall" in res.output
    params = load_config(LegTrackerParams, out)
    text = out.read_text()
    assert "p_det_approved" in text and "lambda_fal =" not in text
    assert "#   lambda_fal: followed-person truth" in text
    assert params.lambda_fal == LegTrackerParams().lambda_fal
    assert 0.0 < params.p_det_approved < 1.0


def test_validation_counts_are_shown_whole() -> None:
    from laserpeople.cli.fit import _score_text

    assert _score_text("ids", 2.0) == "2" and _score_text("ID switches", 14.0) == "14"
    assert _score_text("recall", 1.0) == "1.000" and _score_text("MOTA", -0.1234) == "-0.123"


def _fit_result(rows: list[tuple[str, str, dict[str, float]]]) -> FitResult:
    from laserpeople.fitting.validate import ValidationRow

    return FitResult(
        "leg-mht",
        LegTrackerParams(),
        (),
        (),
        "",
        ("a",),
        tuple(dict.fromkeys(r[0] for r in rows)),
        tuple(ValidationRow(*r) for r in rows),
    )


def test_learned_parameters_that_score_below_the_defaults_are_said() -> None:
    """A learned set that stops the tracker (MOTA 0.797 -> 0) is said per validation
    recording, in the CLI and in the TOML header; a loss within WORSE_BY, a gain, and the
    other scores of a row (IDF1 lost, MOTA not) are not; for an error (groups' clustering
    error) higher is worse, for identity recall lower."""
    result = _fit_result(
        [
            ("d3", "default", {"MOTA": 0.797, "IDF1": 0.9}),
            ("d3", "learned", {"MOTA": 0.0, "IDF1": 0.0}),
            ("d4", "default", {"MOTA": 0.80, "IDF1": 0.9}),
            ("d4", "learned", {"MOTA": 0.80 - WORSE_BY / 2, "IDF1": 0.1}),
            ("d5", "default", {"MOTA": 0.5}),
            ("d5", "learned", {"MOTA": 0.7}),
            ("f", "default", {"identity recall": 0.98, "recall": 0.9}),
            ("f", "learned", {"identity recall": 0.60, "recall": 0.99}),
            ("g", "default", {"clustering error": 0.25, "size error": 0.26}),
            ("g", "learned", {"clustering error": 0.51, "size error": 0.18}),
            ("h", "default", {"clustering error": 0.25}),
            ("h", "learned", {"clustering error": 0.20}),
        ]
    )
    lines = result.worse_than_default()
    assert [line.split()[1] for line in lines] == ["d3", "f", "g"]
    assert "MOTA 0.797 -> 0.000" in lines[0]
    assert "identity recall 0.980 -> 0.600" in lines[1]
    assert "clustering error 0.250 -> 0.510" in lines[2]
    assert [h for h in result.header() if h.startswith("WARNING: ")] == [
        f"WARNING: {line}" for line in lines
    ]


def test_fit_warns_when_the_learned_parameters_lose(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The command prints the warning after writing the file (it is still written: the
    user may keep some of its keys)."""
    from laserpeople.fitting import flow

    losing = _fit_result([("v", "default", {"MOTA": 0.8}), ("v", "learned", {"MOTA": 0.1})])
    monkeypatch.setattr(flow, "learn", lambda *a, **k: losing)
    rec = tmp_path / "a.npz"
    rec.write_bytes(b"")
    out = tmp_path / "p.toml"
    res = CliRunner().invoke(app, ["fit", str(rec), "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.is_file()
    assert "warning: on v the learned parameters score below the defaults (MOTA" in res.output
