"""`laserpeople train` refuses to fit AdaBoost on a handful of legs or non-legs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.cli.train import MIN_EXAMPLES
from laserpeople.detection.training import LabelledSegments, too_few_examples


def _segments(legs: int, others: int, groups: tuple[str, ...] = ("rec.npz",)) -> LabelledSegments:
    """``legs`` legs and ``others`` non-legs in each of ``groups``."""
    per = np.r_[np.ones(legs, dtype=np.int64), -np.ones(others, dtype=np.int64)]
    n = per.size * len(groups)
    return LabelledSegments(
        features=np.zeros((n, 14)),
        max_beam_motion=np.zeros(n),
        distance=np.ones(n),
        labels=np.tile(per, len(groups)),
        group=np.repeat(np.arange(len(groups)), per.size),
        scan=np.zeros(n, dtype=np.int64),
        groups=groups,
    )


@pytest.mark.parametrize(
    ("legs", "others", "lacking"),
    [
        (20, 20, None),
        (19, 20, "19 legs"),
        (20, 19, "19 non-legs"),
        (3, 0, "3 legs and 0 non-legs"),
        (21, 500, None),
    ],
)
def test_too_few_examples_at_the_minimum(legs: int, others: int, lacking: str | None) -> None:
    assert too_few_examples(_segments(legs, others), 20) == lacking


def test_augmented_examples_count_once_per_recorded_segment() -> None:
    """``--augment`` shows each recorded segment to 20 scanner variants: 12 legs seen by two
    variants are 12 legs, not 24 (and two lasers of one variant do add up)."""
    variants = ("rec.npz@0.25deg x0.7:/scan", "rec.npz@0.50deg x1.4:/scan")
    data = _segments(12, 30, variants)
    assert data.recorded_counts() == (12, 30)
    assert too_few_examples(data, 20) == "12 legs"
    lasers = _segments(12, 30, ("rec.npz@0.25deg x0.7:/front", "rec.npz@0.25deg x0.7:/rear"))
    assert lasers.recorded_counts() == (24, 60)
    assert too_few_examples(lasers, 20) is None
    plain = _segments(12, 30, ("a.npz", "b.npz"))
    assert plain.recorded_counts() == (24, 60)


@pytest.fixture(scope="module")
def short_walk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path_factory.mktemp("train") / "walk.npz"
    run_scenario("figure-eight", seconds=0.3, seed=2).write(rec)
    return rec


def test_train_refuses_a_handful_of_legs_and_writes_nothing(
    tmp_path: Path, short_walk: Path
) -> None:
    model = tmp_path / "m.json"
    run = CliRunner().invoke(app, ["train", str(short_walk), "-o", str(model)])
    assert run.exit_code == 1
    text = str(run.exception)
    assert "too few examples to train on:" in text and f"at least {MIN_EXAMPLES} of each" in text
    assert "--min-examples" in text and not model.exists()


def test_train_below_the_minimum_on_request_warns_and_records_the_counts(
    tmp_path: Path, short_walk: Path
) -> None:
    model = tmp_path / "m.json"
    run = CliRunner().invoke(
        app, ["train", str(short_walk), "-o", str(model), "--min-examples", "1"]
    )
    assert run.exit_code == 0, run.output
    doc = json.loads(model.read_text())["training"]
    assert 0 < doc["legs"] < MIN_EXAMPLES
    assert f"warning: training on only {doc['legs']} legs" in run.output
    assert "(--min-examples 1)" in run.output
