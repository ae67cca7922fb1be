"""`batch` says which of its options had no effect on which recordings, with the rules
`track` uses (a leg model on a still laser's feet-pf runs, a static world model that the
arras people policy never asks)."""

from __future__ import annotations

from pathlib import Path

import pytest

from laserpeople.batch.options import TrackOptions
from laserpeople.batch.task import UNKNOWN, TopicRow
from laserpeople.batch.unused import unused_warnings
from laserpeople.pipeline.unused_options import fleet_warning, never_used


def test_an_option_is_unused_on_a_recording_when_none_of_its_known_runs_used_it() -> None:
    runs: list[tuple[str, bool | None]] = [
        ("a", True),
        ("a", False),  # a's other laser: a used it (the last run does not decide)
        ("b", False),
        ("b", None),
        ("c", None),  # nothing known of c: not judged (not counted as unused)
        ("d", False),
        ("d", True),  # nor does the first run decide
        ("e", False),
    ]
    names, judged = never_used(runs)
    assert names == ["b", "e"]
    assert judged == 4  # recordings a, b, d, e (not the 7 known runs)
    assert never_used([]) == ([], 0)
    assert never_used([("x", None)]) == ([], 0)


def test_the_warning_names_the_first_recordings_and_counts_the_rest() -> None:
    line = fleet_warning(["--model m.json"], ["r1", "r2", "r3", "r4", "r5"], 7, "why")
    assert line == "--model m.json had no effect on 5 of 7 recordings (r1, r2, r3 and 2 more): why"
    line = fleet_warning(["--detector heuristic", "--model m.json"], ["r1"], 1, "why")
    assert line == (
        "--detector heuristic and --model m.json had no effect on 1 of 1 recording (r1): why"
    )
    assert fleet_warning(["--model m.json"], [], 3, "why") is None
    assert fleet_warning([], ["r1"], 1, "why") is None


def _row(name: str, detector: int, static: int, scans: int = 10, status: str = "done") -> TopicRow:
    return TopicRow(
        recording=f"/d/{name}.bag",
        name=name,
        topic="/scan",
        scans=scans,
        status=status,
        detector_used=detector,
        static_model_used=static,
    )


def test_failed_empty_and_unknown_rows_are_not_judged() -> None:
    rows = [
        _row("still", 0, 1),
        _row("moving", 1, 1),
        _row("old", UNKNOWN, UNKNOWN, status="skipped"),  # done by a version before the flags
        _row("broken", 0, 0, scans=0, status="failed"),
        _row("empty", 0, 0, scans=0),
        _row("skipped", 0, 1, status="skipped"),  # done before, flags kept: judged
    ]
    said = unused_warnings(rows, TrackOptions(tracker="feet-pf", model=Path("m.json")))
    assert len(said) == 1
    assert said[0].startswith("--model m.json had no effect on 2 of 3 recordings (still, skipped)")
    assert "feet-pf tracks foreground points and these runs detected no legs" in said[0]
    assert unused_warnings(rows, TrackOptions(tracker="feet-pf")) == []  # nothing asked
    arras = TrackOptions(people_policy="arras", background="histogram")
    rows = [_row("a", 1, 0), _row("b", 1, 1), _row("c", 1, 0)]
    assert unused_warnings(rows, arras) == [
        "--background histogram had no effect on 2 of 3 recordings (a, c): leg-mht with the "
        "arras people policy asks no static world model (--people-policy tracks does)"
    ]
    assert unused_warnings(rows, TrackOptions(people_policy="arras", background="none")) == []


@pytest.fixture(scope="module")
def two(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    """A still laser (demo) and a moving one (moving-robot), 2 s each, simulated."""
    from laserpeople.sim import run_scenario

    folder = tmp_path_factory.mktemp("two")
    return [
        run_scenario(name, seconds=2.0, seed=1).write(folder / f"{name}.npz")
        for name in ("demo", "moving-robot")
    ]


@pytest.fixture(scope="module")
def model(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the shipped leg model, as a user's --model file."""
    import shutil

    import laserpeople.detection as detection

    path = tmp_path_factory.mktemp("model") / "mine.json"
    shutil.copy(Path(detection.__file__).parent / "models" / "default.json", path)
    return path


def test_batch_says_which_recordings_an_option_had_no_effect_on(
    two: list[Path], model: Path, tmp_path: Path
) -> None:
    pytest.importorskip("dask.distributed")
    pytest.importorskip("pyarrow")
    from typer.testing import CliRunner

    from laserpeople.cli import app

    def batch(out: Path, *args: str) -> str:
        run = CliRunner().invoke(
            app,
            ["batch", *map(str, two), "-o", str(out), "--no-processes", "--workers", "1", *args],
        )
        assert run.exit_code == 0, run.output
        return " ".join(run.output.split())

    out = tmp_path / "feet"
    args = ("--tracker", "feet-pf", "--model", str(model), "--topics", "all")
    said = batch(out, *args)
    # the still laser's run detected no legs; the moving laser's narrowed its points to legs
    assert f"--model {model} had no effect on 1 of 2 recordings (demo): feet-pf" in said
    import pyarrow.parquet as pq

    summary = pq.read_table(out / "summary.parquet").to_pylist()
    assert [(r["name"], r["detector_used"]) for r in summary] == [("demo", 0), ("moving-robot", 1)]
    # a rerun skips both (done before) and still says it
    said = batch(out, *args)
    assert "2 done before (skipped)" in said
    assert f"--model {model} had no effect on 1 of 2 recordings (demo)" in said
    said = batch(
        tmp_path / "arras", "--people-policy", "arras", "--background", "histogram",
        "--model", str(model), "--topics", "all",
    )  # fmt: skip
    assert "--background histogram had no effect on 2 of 2 recordings (demo, moving-robot)" in said
    assert "--model" not in said  # the leg MHT detects legs everywhere
