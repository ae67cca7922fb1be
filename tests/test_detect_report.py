"""The report tables of leg classifiers (000 Tables 2-8 and the per-distance breakdown)."""

from __future__ import annotations

import numpy as np

from laserpeople.detection.features import N_FEATURES
from laserpeople.detection.report import Confusion, error_table, errors_by_distance
from laserpeople.detection.training import LabelledSegments


def _segments(labels: list[int], distance: list[float]) -> LabelledSegments:
    n = len(labels)
    return LabelledSegments(
        np.zeros((n, N_FEATURES)),
        np.zeros(n),
        np.asarray(distance, dtype=np.float64),
        np.asarray(labels, dtype=np.int64),
        np.zeros(n, dtype=np.int64),
        np.arange(n, dtype=np.int64),
        ("rec",),
    )


def test_confusion_rates_by_hand() -> None:
    c = Confusion.of(np.array([1, 1, -1, -1, 1]), np.array([1, -1, 1, -1, -1]))
    assert (c.tp, c.fn, c.fp, c.tn) == (1, 1, 2, 1)
    assert c.fn_rate == 50.0 and np.isclose(c.fp_rate, 200 / 3) and c.overall_error == 60.0
    assert c.detection_rate == 50.0
    text = error_table({"A": c}, "t")
    assert "50.00" in text and "66.67" in text and "60.00" in text


def test_errors_by_distance_by_hand() -> None:
    # band 0-1 m: 2 legs (one missed), 2 non-legs (one false alarm);
    # band 1-2 m: empty (not printed); band >= 2 m: one non-leg, correctly rejected
    data = _segments([1, 1, -1, -1, -1], [0.5, 0.9, 0.2, 0.99, 7.0])
    decisions = np.array([1, -1, 1, -1, -1])
    text = errors_by_distance({"AdaBoost": decisions}, data, edges=(0.0, 1.0, 2.0), title="T")
    lines = text.splitlines()
    assert lines[0] == "T"
    rows = {line.split()[0]: line.split() for line in lines[3:]}
    assert set(rows) == {"0-1", ">="}
    assert rows["0-1"][1:] == ["2", "2", "50.0", "/", "50.0"]
    assert rows[">="][1:] == ["2", "0", "1", "-", "/", "0.0"]


def test_segments_summary_counts_recordings_and_their_lasers():
    """Three lasers of one bag are one recording with three lasers; one laser per file
    says no more (the 'from 3 recordings' of negative_2.bag was one file)."""

    def table(groups: tuple[str, ...], rows: list[int]) -> LabelledSegments:
        n = len(rows)
        return LabelledSegments(
            np.zeros((n, N_FEATURES)),
            np.zeros(n),
            np.ones(n),
            np.array([1] + [-1] * (n - 1)),
            np.array(rows),
            np.arange(n),
            groups,
        )

    room = table(
        ("negative_2.bag:/left_scan", "negative_2.bag:/right_scan", "negative_2.bag:/rear_scan"),
        [0, 1, 2, 2],
    )
    assert room.summary() == "4 segments (1 legs, 3 non-legs) from 1 recording (3 lasers)"
    legs = table(("positive_1.bag:/training_scan", "positive_2.bag:/training_scan"), [0, 1])
    assert legs.summary() == "2 segments (1 legs, 1 non-legs) from 2 recordings"
    unused = table(("a.bag:/s", "b.bag:/s"), [1, 1])  # only groups with segments count
    assert unused.summary().endswith("from 1 recording")
    # train --augment: one bag of three lasers in two scanner variants is one recording
    # of three lasers (not "from 2 recordings (6 lasers)")
    names = [
        f"negative_2.bag@{v}:{laser}"
        for v in ("0.25deg x0.7", "0.50deg x1.4")
        for laser in ("/left_scan", "/right_scan", "/rear_scan")
    ]
    varied = table(tuple(names), [0, 1, 2, 3, 4, 5])
    assert varied.summary().endswith("from 1 recording (3 lasers) in 2 scanner variants")
    one = table(("positive_1.bag@0.35deg x2:/training_scan", "a@b.bag:/s"), [0, 1])
    assert one.summary().endswith("from 2 recordings in 1 scanner variant")


def test_error_table_shows_a_dash_for_a_rate_of_no_segments() -> None:
    # A test set of legs only (positive bags, no --test-negatives): FN 1 of 4 = 25.00 %,
    # overall 25.00 %, and no false-positive rate at all, printed "-", not "nan".
    c = Confusion.of(np.array([1, 1, 1, -1]), np.array([1, 1, 1, 1]))
    rows = error_table({"A": c}, "t").splitlines()
    cells = {row.split("  ")[0]: row.split()[-1] for row in rows if "(%)" in row}
    assert cells == {
        "False Negatives (%)": "25.00",
        "False Positives (%)": "-",
        "Overall Error (%)": "25.00",
    }


def test_train_report_prints_the_distance_header_with_its_unit(tmp_path) -> None:
    """The tables go out as plain text: rich markup would eat "[m]" of "distance [m]"."""
    from typer.testing import CliRunner

    from laserpeople.cli import app
    from laserpeople.sim import run_scenario

    rec = tmp_path / "office.npz"
    run_scenario("office", seconds=2, seed=3).write(rec)
    args = [
        "--quiet",
        "train",
        str(rec),
        "--rounds",
        "3",
        "--report",
        "-o",
        str(tmp_path / "m.json"),
    ]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "distance [m]  legs  non-legs" in result.stdout
