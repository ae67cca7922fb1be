"""The per-beam histogram background of 004 Sec. 2."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from laserpeople.background.beam_histogram import (
    BackgroundModelError,
    BeamHistogramBackground,
    BeamHistogramParams,
)
from laserpeople.errors import LaserPeopleError
from laserpeople.frame import Frame
from laserpeople.scan import PointSet, Pose2D, Scan


def _scan(ranges: np.ndarray, stamp: float, sensor: str = "a", index: int = 0) -> Scan:
    return Scan(
        stamp,
        -math.pi / 2,
        math.pi / 180,
        ranges,
        0.05,
        30.0,
        sensor=sensor,
        pose=Pose2D(1.0, 2.0, 0.3),
        index=index,
    )


def _walls(n: int = 181) -> np.ndarray:
    return np.linspace(4.0, 6.0, n)


def _frame(scans: list[Scan]) -> Frame:
    return Frame(
        scans[0].index,
        scans[0].stamp,
        tuple(scans),
        "fused",
        "world",
        points=PointSet.from_scans(scans, "world"),
    )


def test_walls_are_background_and_a_person_is_foreground() -> None:
    rng = np.random.default_rng(0)
    learn = [_scan(_walls() + rng.normal(0, 0.01, 181), 0.1 * k) for k in range(20)]
    model = BeamHistogramBackground().learn_scans(learn)
    test = _walls() + rng.normal(0, 0.01, 181)
    test[90:96] = 2.0  # a person 2 m in front of the laser
    test[10] = np.nan  # no return
    fg = model.foreground_of(_scan(test, 5.0))
    assert np.flatnonzero(fg).tolist() == list(range(90, 96))


def test_tolerance_and_minimum_fraction() -> None:
    p = BeamHistogramParams(bin_width=0.05, tolerance=0.10, min_fraction=0.2)
    walls = _walls()
    learn = [_scan(walls, float(k)) for k in range(10)]
    # beam 5 saw something at 1 m in 1 of 10 scans: below min_fraction, not static
    learn[3] = _scan(np.where(np.arange(181) == 5, 1.0, walls), 3.0)
    model = BeamHistogramBackground(p).learn_scans(learn)
    probe = walls.copy()
    probe[0] += 0.07  # within the 0.10 m tolerance of its wall bin
    probe[1] += 0.25  # beyond it
    probe[5] = 1.0
    fg = model.foreground_of(_scan(probe, 11.0))
    assert not fg[0] and fg[1] and fg[5]
    assert fg.sum() == 2


def test_learns_from_the_first_seconds_of_frames_then_stops() -> None:
    model = BeamHistogramBackground(BeamHistogramParams(learn_seconds=1.0))
    walls = _walls()
    for k in range(11):  # 0.0 .. 1.0 s
        out = model(_frame([_scan(walls, 0.1 * k, index=k)]))
        assert out.foreground is not None
    assert not model.learning
    probe = walls.copy()
    probe[40:44] = 1.5
    out = model(_frame([_scan(probe, 2.0, index=20)]))
    assert out.foreground is not None and out.points is not None
    assert out.foreground.sum() == 4
    assert set(out.points.beams[out.foreground].tolist()) == {40, 41, 42, 43}
    # frozen: the person is not learned into the background
    assert model.counts("a")[40].sum() == 11


def test_save_load_round_trip_without_pickle(tmp_path: Path) -> None:
    rng = np.random.default_rng(1)
    model = BeamHistogramBackground().learn_scans(
        [_scan(_walls() + rng.normal(0, 0.01, 181), k * 0.1, s) for k in range(5) for s in "ab"]
    )
    path = model.save(tmp_path / "bg.npz")
    with np.load(path, allow_pickle=False) as data:
        assert data["meta"].dtype.kind == "U"
    again = BeamHistogramBackground.load(path)
    assert again.sensors == ("a", "b")
    for s in "ab":
        assert np.array_equal(again.counts(s), model.counts(s))
    probe = _scan(np.where(np.arange(181) < 20, 1.0, _walls()), 9.0, "b")
    assert np.array_equal(again.foreground_of(probe), model.foreground_of(probe))


def test_bad_files_and_unknown_lasers(tmp_path: Path) -> None:
    bad = tmp_path / "x.npz"
    np.savez(bad, meta=np.array('{"format": "other"}'))
    with pytest.raises(BackgroundModelError, match="not a laserpeople background"):
        BeamHistogramBackground.load(bad)
    with pytest.raises(BackgroundModelError, match="cannot read"):
        BeamHistogramBackground.load(tmp_path / "missing.npz")
    model = BeamHistogramBackground().learn_scans([_scan(_walls(), 0.0)])
    with pytest.raises(BackgroundModelError, match="no laser 'zz'"):
        model.counts("zz")
    with pytest.raises(BackgroundModelError, match=r"saved as \.npz"):
        model.save(tmp_path / "bg.json")


def test_static_time_marks_walls_only() -> None:
    walls = _walls()
    model = BeamHistogramBackground()
    for k in range(25):
        model(_frame([_scan(walls, 0.1 * k, index=k)]))
    scan = _scan(walls, 3.0, index=30)
    model(_frame([scan]))
    wall_pts = scan.points("world")[[20, 100]]
    free = scan.pose.transform_points(np.array([[1.0, 0.0]]))  # type: ignore[union-attr]
    t = model.static_time(np.vstack([wall_pts, free]))
    assert t[0] > 1.9 and t[1] > 1.9
    assert t[2] == 0.0


def test_a_person_standing_while_learning_does_not_stay_background() -> None:
    """Beams 40-43 see a person at 2 m during the whole learning period; the wall behind
    is never learned. Once the person leaves, the wall there is foreground for
    ``relearn_seconds``, then background; the person coming back is foreground."""
    p = BeamHistogramParams(learn_seconds=1.0, relearn_seconds=0.5)
    model = BeamHistogramBackground(p)
    walls = _walls()
    person = walls.copy()
    person[40:44] = 2.0
    k = 0
    for k in range(11):  # learning 0.0 .. 1.0 s with the person standing
        model(_frame([_scan(person, 0.1 * k, index=k)]))
    assert not model.learning
    fg_at = []
    for j in range(1, 11):  # the person has gone: the wall is seen, 1.1 .. 2.0 s
        out = model(_frame([_scan(walls, 1.0 + 0.1 * j, index=k + j)]))
        assert out.foreground is not None
        fg_at.append(int(out.foreground.sum()))
    # foreground until the candidate held 0.5 s (1.1 .. 1.6 s), then background
    assert fg_at[:5] == [4] * 5 and fg_at[6:] == [0] * 4
    assert model.relearned("a") == 4
    back = model(_frame([_scan(person, 2.5, index=30)]))
    assert back.foreground is not None and int(back.foreground.sum()) == 4


def test_a_person_standing_after_learning_stays_foreground() -> None:
    """Relearning goes only towards farther returns: someone who stops in front of the
    wall after learning is never learned into the background, and a short flicker beyond
    the wall does not relearn."""
    p = BeamHistogramParams(learn_seconds=1.0, relearn_seconds=0.5)
    model = BeamHistogramBackground(p)
    walls = _walls()
    for k in range(11):
        model(_frame([_scan(walls, 0.1 * k, index=k)]))
    person = walls.copy()
    person[40:44] = 2.0
    flicker = walls.copy()
    flicker[100] += 1.0  # beyond the wall in single scans only
    for j in range(1, 41):  # ends on a scan with the person
        ranges = flicker if j % 3 == 0 else person
        out = model(_frame([_scan(ranges, 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None
    assert int(out.foreground.sum()) == 4
    assert model.relearned("a") == 0


def test_relearned_model_survives_save_and_load(tmp_path: Path) -> None:
    model = BeamHistogramBackground(BeamHistogramParams(learn_seconds=0.5, relearn_seconds=0.3))
    walls = _walls()
    person = walls.copy()
    person[10:12] = 1.0
    for k in range(6):
        model(_frame([_scan(person, 0.1 * k, index=k)]))
    for j in range(1, 6):
        model(_frame([_scan(walls, 0.5 + 0.1 * j, index=5 + j)]))
    assert model.relearned("a") == 2
    again = BeamHistogramBackground.load(model.save(tmp_path / "bg.npz"))
    assert again.params.relearn_seconds == 0.3
    assert not again.foreground_of(_scan(walls, 9.0)).any()
    assert again.foreground_of(_scan(person, 9.0)).sum() == 2


def test_the_farthest_frequent_range_is_the_background() -> None:
    """Learning 20 scans: beams 40-43 see a person standing at 2.0 m for the first 8 scans
    (40 %), then the wall at 4.44-4.47 m; beams 60-61 see only a near object at 1.5 m.
    With ``farthest`` the person's beams take the wall as background and the person is
    foreground, the near-only beams keep 1.5 m; 004's rule (every bin seen in at least
    10 % of the scans) keeps the person as background too."""
    walls = _walls()
    walls[60:62] = 1.5
    person = walls.copy()
    person[40:44] = 2.0
    learn = [_scan(person if k < 8 else walls, 0.1 * k) for k in range(20)]
    new = BeamHistogramBackground(BeamHistogramParams(relearn_seconds=0.0)).learn_scans(learn)
    old = BeamHistogramBackground(BeamHistogramParams(farthest=False)).learn_scans(learn)
    assert np.flatnonzero(new.foreground_of(_scan(person, 5.0))).tolist() == [40, 41, 42, 43]
    assert not new.foreground_of(_scan(walls, 5.0)).any()  # wall and the 1.5 m object
    assert not old.foreground_of(_scan(person, 5.0)).any()
    # a return 0.2 m (more than twice the tolerance) in front of the 1.5 m object
    nearer = walls.copy()
    nearer[60] = 1.3
    assert np.flatnonzero(new.foreground_of(_scan(nearer, 5.0))).tolist() == [60]
    static = new._table("a").static
    assert static is not None
    assert static[41, int(walls[41] / 0.05)] and not static[41, int(2.0 / 0.05)]


def test_the_paper_preset_keeps_every_frequent_bin() -> None:
    from laserpeople.config import load_config
    from laserpeople.pipeline.background import load_static_world

    assert load_config(BeamHistogramParams, None, "paper").farthest is False
    assert BeamHistogramParams().farthest is True
    # `track --preset paper` reads the static world with the preset
    assert load_static_world(None, "paper").beam_histogram.farthest is False
    assert load_static_world(None).beam_histogram.farthest is True


def test_a_frames_foreground_is_per_point_of_each_laser() -> None:
    """Two lasers learned on their walls; then laser a has no return on beams 10-19 and
    sees a person on beams 90-95, laser b a person on beams 30-33. The frame's foreground
    holds one entry per point (beams without a return have none): True on exactly the
    points of a's beams 90-95 and b's beams 30-33; a frame of laser a alone, True on
    exactly its points of beams 90-95."""
    rng = np.random.default_rng(4)
    learn = [
        _scan(_walls() + rng.normal(0, 0.01, 181), 0.1 * k, sensor=s, index=k)
        for k in range(20)
        for s in ("a", "b")
    ]
    model = BeamHistogramBackground().learn_scans(learn)
    ra = _walls() + rng.normal(0, 0.01, 181)
    ra[10:20] = np.nan
    ra[90:96] = 2.0
    rb = _walls() + rng.normal(0, 0.01, 181)
    rb[30:34] = 1.5
    a, b = _scan(ra, 5.0, "a", 50), _scan(rb, 5.0, "b", 50)
    out = model(_frame([a, b]))
    pts = out.points
    assert out.foreground is not None and pts is not None
    assert len(out.foreground) == len(pts) == 171 + 181
    names = np.asarray(pts.sensors)[pts.sensor_ids]
    want = ((names == "a") & (pts.beams >= 90) & (pts.beams < 96)) | (
        (names == "b") & (pts.beams >= 30) & (pts.beams < 34)
    )
    assert np.array_equal(out.foreground, want)
    alone = model(_frame([_scan(ra, 5.1, "a", 51)]))
    assert alone.foreground is not None and alone.points is not None
    assert len(alone.foreground) == 171
    assert sorted(alone.points.beams[alone.foreground].tolist()) == list(range(90, 96))


def _learn_with_person(
    person_beams: slice,
    marked_share: float,
    p: BeamHistogramParams | None = None,
    legs_share: float = 0.0,
) -> tuple[BeamHistogramBackground, list[int]]:
    """Learn 11 frames (0.0 .. 1.0 s) with a person at 2.0 m on ``person_beams``, marked as
    people in the first ``marked_share`` of the frames and as near a leg detection (maybe
    people) in the first ``legs_share``; returns the model and the number of foreground
    points of each learning frame."""
    model = BeamHistogramBackground(p or BeamHistogramParams(learn_seconds=1.0))
    person = _walls()
    person[person_beams] = 2.0
    fg = []
    for k in range(11):
        frame = _frame([_scan(person, 0.1 * k, index=k)])
        assert frame.points is not None
        there = np.isin(frame.points.beams, np.arange(181)[person_beams])
        on = there & (k < round(11 * marked_share))
        legs = there & (k < round(11 * legs_share))
        fg.append(int(model.learn_foreground(frame, on, legs).sum()))
    assert not model.learning
    return model, fg


def test_people_marked_while_learning_are_foreground_and_the_wall_behind_is_guessed() -> None:
    """Beams 40-43 see a person at 2 m through the learning, marked as people: the person
    is foreground from the first scan (without marks, 004: background), and once they
    leave the wall there is background at once, guessed between beams 39 and 44."""
    model, fg = _learn_with_person(slice(40, 44), 1.0)
    assert fg == [4] * 11
    table = model._tables["a"]
    assert table.nearest is not None
    # by hand: the farthest static returns beside the person, bin centres of beams 39
    # (4.425 m at -51 deg) and 44 (4.475 m at -46 deg); their straight line crosses beam
    # 40 at 4.432 m (bin 88), 41 at 4.441 m (88), 42 at 4.451 m (89), 43 at 4.462 m (89)
    # (the person's bin 40, or the ranges interpolated by beam index, 4.435 .. 4.465 m,
    # bins 88 88 89 89 too, but a guess from the far walls at 4.0 / 6.0 m is not)
    assert table.nearest[40:44].tolist() == [88, 88, 89, 89]
    gone = model(_frame([_scan(_walls(), 1.1, index=11)]))
    assert gone.foreground is not None and int(gone.foreground.sum()) == 0
    unmarked, fg0 = _learn_with_person(slice(40, 44), 0.0)
    assert fg0 == [0] * 11
    assert int(unmarked.foreground_of(_scan(_walls(), 1.1)).sum()) == 4  # until relearned


def test_legs_not_confirmed_as_people_stay_static_and_the_wall_behind_is_guessed() -> None:
    """Beams 40-43 near a leg detection in every learning scan but never on a person (a
    bin the detector fires on, or a person the leg tracker did not confirm): static as
    without marks (background from the first scan, and as long as it stays), but the wall
    behind is guessed as for people, so when something there leaves, the wall is
    background at once (without the guess: foreground until relearned); relearning then
    drops the near bin as before."""
    p = BeamHistogramParams(learn_seconds=1.0, relearn_seconds=0.5)
    model, fg = _learn_with_person(slice(40, 44), 0.0, p, legs_share=1.0)
    assert fg == [0] * 11
    table = model._tables["a"]
    assert table.nearest is not None and table.static is not None
    assert table.nearest[40:44].tolist() == [40] * 4  # the near bin stays the nearest
    assert table.static[40:44, 88:90].any(axis=1).all()  # the guessed wall (by hand above)
    assert model.people_beams() == (0, 0)  # nothing is watched for settling
    person = _walls()
    person[40:44] = 2.0
    for j in range(1, 61):  # 6 s: never settled, never foreground
        out = model(_frame([_scan(person, 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None and int(out.foreground.sum()) == 0
    counts = []
    for j in range(61, 71):
        out = model(_frame([_scan(_walls(), 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None
        counts.append(int(out.foreground.sum()))
    assert counts == [0] * 10
    assert model.relearned("a") == 4
    assert int(model.foreground_of(_scan(person, 9.0)).sum()) == 4  # the near bin dropped
    plain, _ = _learn_with_person(slice(40, 44), 0.0, p)
    assert int(plain.foreground_of(_scan(_walls(), 1.1)).sum()) == 4  # until relearned
    _, fg1 = _learn_with_person(slice(40, 44), 1.0, p, legs_share=1.0)
    assert fg1 == [4] * 11  # people among the legs: foreground as before


def test_the_wall_is_guessed_behind_legs_whose_returns_straddle_two_bins() -> None:
    """Returns near a leg detection alternating between 2.00 and 2.06 m (bins 40 and 41,
    both frequent, both static): the wall behind is still guessed (the farther of the two
    bins is no wall), so once they leave the wall is background at once."""
    model = BeamHistogramBackground(BeamHistogramParams(learn_seconds=1.0))
    for k in range(11):
        ranges = _walls()
        ranges[40:44] = 2.0 if k % 2 else 2.06
        frame = _frame([_scan(ranges, 0.1 * k, index=k)])
        assert frame.points is not None
        legs = np.isin(frame.points.beams, [40, 41, 42, 43])
        model.learn_foreground(frame, np.zeros(len(legs), dtype=bool), legs)
    assert not model.learning
    assert int(model.foreground_of(_scan(_walls(), 1.1)).sum()) == 0


def test_a_person_who_stood_while_learning_and_stands_farther_stays_foreground() -> None:
    """With the wall behind guessed, relearning on those beams waits for returns beyond
    the guess: the person of the learning walking on to 3 m along the same beams and
    standing there is not learned as static (without the guess it would be after 0.5 s)."""
    model, _ = _learn_with_person(slice(40, 44), 1.0, BeamHistogramParams(learn_seconds=1.0))
    farther = _walls()
    farther[40:44] = 3.0
    for j in range(1, 21):
        out = model(_frame([_scan(farther, 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None and int(out.foreground.sum()) == 4
    assert model.relearned("a") == 0


def test_without_a_wall_beside_the_people_the_beam_relearns() -> None:
    """A person on the first beams (0-3) has no beam without people on one side: no guess;
    the wall behind is foreground until it held ``relearn_seconds``, then background."""
    p = BeamHistogramParams(learn_seconds=1.0, relearn_seconds=0.5)
    model, fg = _learn_with_person(slice(0, 4), 1.0, p)
    assert fg == [4] * 11
    counts = []
    for j in range(1, 11):
        out = model(_frame([_scan(_walls(), 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None
        counts.append(int(out.foreground.sum()))
    assert counts[:5] == [4] * 5 and counts[6:] == [0] * 4
    assert model.relearned("a") == 4


def test_people_share_decides_which_bins_stay_static() -> None:
    """Marked in 2 of 11 learning scans (0.18 < 0.2): static as before; in 3 of 11
    (0.27): not static."""
    few, _ = _learn_with_person(slice(40, 44), 2 / 11)
    more, _ = _learn_with_person(slice(40, 44), 3 / 11)
    person = _walls()
    person[40:44] = 2.0
    assert int(few.foreground_of(_scan(person, 2.0)).sum()) == 0
    assert int(more.foreground_of(_scan(person, 2.0)).sum()) == 4
    with pytest.raises(LaserPeopleError):
        BeamHistogramParams(people_share=0.0)


def test_people_counts_survive_save_and_load(tmp_path: Path) -> None:
    model, _ = _learn_with_person(slice(40, 44), 1.0)
    again = BeamHistogramBackground.load(model.save(tmp_path / "bg.npz"))
    person = _walls()
    person[40:44] = 2.0
    assert int(again.foreground_of(_scan(person, 9.0)).sum()) == 4
    assert int(again.foreground_of(_scan(_walls(), 9.0)).sum()) == 0
    legs, _ = _learn_with_person(slice(40, 44), 0.0, legs_share=1.0)
    loaded = BeamHistogramBackground.load(legs.save(tmp_path / "legs.npz"))
    assert int(loaded.foreground_of(_scan(person, 9.0)).sum()) == 0
    assert int(loaded.foreground_of(_scan(_walls(), 9.0)).sum()) == 0  # the guess kept


def test_people_flags_must_fit_the_points() -> None:
    model = BeamHistogramBackground()
    frame = _frame([_scan(_walls(), 0.0)])
    with pytest.raises(BackgroundModelError, match="people flags"):
        model.learn_foreground(frame, np.zeros(3, dtype=bool))


def test_people_of_the_learning_who_never_leave_settle_into_the_background() -> None:
    """A leg detection on furniture while learning: beams 40-43 keep returning 2.0 m after
    learning (every third scan someone passes in front at 1.0 m, which does not count
    against it). Foreground until it held ``people_settle_seconds`` (2 s here, from the
    last learning scan at 1.0 s; the passing scans at 2.1, 2.4, ... s do not restart it),
    background after 3.0 s. Once the wall was seen there (the people left), the beam
    is no longer watched: someone standing on the same place later stays foreground."""
    p = BeamHistogramParams(learn_seconds=1.0, people_settle_seconds=2.0)
    model, _ = _learn_with_person(slice(40, 44), 1.0, p)
    stays, passing = _walls(), _walls()
    stays[40:44] = 2.0
    passing[40:44] = 1.0
    fg = {}
    for j in range(1, 31):
        out = model(_frame([_scan(passing if j % 3 == 0 else stays, 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None
        fg[round(1.0 + 0.1 * j, 1)] = int(out.foreground.sum())
    # counted from the last learning scan (1.0 s); the scan at 3.0 s completes the 2 s
    # (its own foreground is computed before)
    assert [fg[t] for t in (2.9, 3.0, 3.2, 3.3, 3.5, 3.8)] == [4, 4, 0, 0, 0, 0]
    assert fg[3.1] == fg[4.0] == 4  # the one passing in front is foreground
    assert model.settled("a") == 4
    again, _ = _learn_with_person(slice(40, 44), 1.0, p)
    for j in range(1, 51):
        ranges = _walls() if j == 15 else stays  # at 2.5 s the wall is seen: gone for a scan
        out = again(_frame([_scan(ranges, 1.0 + 0.1 * j, index=10 + j)]))
    # 6.0 s: someone stood there 3.5 s since, longer than people_settle_seconds
    assert out.foreground is not None and int(out.foreground.sum()) == 4
    assert again.settled("a") == 0


def test_a_chair_a_person_passed_in_front_of_while_learning_settles_after_all() -> None:
    """Beams 40-43 see a chair at 2.0 m, taken for a person through the learning (11 scans,
    0.0 .. 1.0 s), and in the first 3 and the last a person in front at 1.0 m, marked as
    well: both ranges are on people, the beams are watched at the nearer from 1.0 s. The
    person stands in front until 1.5 s, then the chair is seen again: a farther return on a
    range of the people, watched from 1.6 s on; it holds ``people_settle_seconds`` (2 s) at
    3.6 s and is background from the next scan (a clock kept from 1.0 s: from 3.1 s; the
    chair taken for the people leaving: foreground for good). A person at 1.0 m is
    foreground after."""
    p = BeamHistogramParams(learn_seconds=1.0, people_settle_seconds=2.0)
    model = BeamHistogramBackground(p)
    chair, passing = _walls(), _walls()
    chair[40:44] = 2.0
    passing[40:44] = 1.0
    for k in range(11):
        frame = _frame([_scan(passing if k < 3 or k == 10 else chair, 0.1 * k, index=k)])
        assert frame.points is not None
        model.learn_foreground(frame, np.isin(frame.points.beams, np.arange(40, 44)))
    assert not model.learning
    fg = {}
    for j in range(1, 41):
        ranges = passing if j <= 5 else chair
        out = model(_frame([_scan(ranges, 1.0 + 0.1 * j, index=10 + j)]))
        assert out.foreground is not None
        fg[round(1.0 + 0.1 * j, 1)] = int(out.foreground.sum())
    assert [fg[t] for t in (1.5, 1.6, 3.1, 3.5, 3.6, 3.7, 4.0, 5.0)] == [4, 4, 4, 4, 4, 0, 0, 0]
    assert model.settled("a") == 4
    assert int(model.foreground_of(_scan(passing, 5.1)).sum()) == 4


def test_a_wall_seen_between_the_legs_and_taken_for_a_leg_is_the_wall() -> None:
    """Through the learning beams 40-47 see a person at 2 m, and beam 43 sees the wall
    through the gap between the legs; the detector takes that wall segment for a leg too
    (marked). It lies on the line guessed from beams 39 and 48, so it is static: the wall
    seen there later is background, the person foreground."""
    model = BeamHistogramBackground(BeamHistogramParams(learn_seconds=1.0))
    ranges = _walls()
    ranges[40:48] = 2.0
    ranges[43] = _walls()[43]
    for k in range(11):
        frame = _frame([_scan(ranges, 0.1 * k, index=k)])
        assert frame.points is not None
        model.learn_foreground(frame, np.isin(frame.points.beams, np.arange(40, 48)))
    assert int(model.foreground_of(_scan(ranges, 1.1)).sum()) == 7  # the person, not beam 43
    assert int(model.foreground_of(_scan(_walls(), 1.2)).sum()) == 0


def test_no_wall_is_guessed_in_front_of_people_standing_in_a_recess() -> None:
    """Through the learning beams 40-43 see a person at 5.0 m (bin 100), marked, in a
    recess behind the walls beside them: the straight line between the farthest static
    returns of beams 39 and 44 crosses those beams at 4.43-4.46 m (bins 88-89), nearer
    than the person less the tolerance (4.9 m), so no wall is guessed there (the nearest
    static bin stays the person's, 100). Someone later passing at 4.46 m on those beams is
    foreground (a guess there would hide them), as the person's range is."""
    model = BeamHistogramBackground(BeamHistogramParams(learn_seconds=1.0))
    ranges = _walls()
    ranges[40:44] = 5.0
    for k in range(11):
        frame = _frame([_scan(ranges, 0.1 * k, index=k)])
        assert frame.points is not None
        model.learn_foreground(frame, np.isin(frame.points.beams, np.arange(40, 44)))
    table = model._tables["a"]
    assert table.nearest is not None
    assert table.nearest[40:44].tolist() == [100] * 4
    passing = _walls()
    passing[40:44] = 4.46
    assert int(model.foreground_of(_scan(passing, 1.1)).sum()) == 4
    assert int(model.foreground_of(_scan(ranges, 1.1)).sum()) == 4
