"""The compiled segment features and AdaBoost margins (``detection/_cfeatures.c``) against
their Python references (``features._compute``, ``adaboost._StumpTables.evaluate``), and
the rules of loading the extension.

Both paths are run on the same blocks of scans: random segments of every size round
numpy's pairwise-sum block sizes (1-3, 7-9, 127-130, 300 points), degenerate ones (two or
three points, collinear, repeated and identical points, evenly spaced points), several
scans per block with and without a previous scan, full circles and negative angle
increments, and simulated scans. The compiled path does the same IEEE operations in the
same order, but another CPU's C library or numpy loops may differ in the last bit, so the
features are compared within 1e-12 (relative, and absolute on metres and radians; NaN
where the reference has NaN, the circle centre of a straight segment) and the legs found
as the user sees them.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from laserpeople import extensions
from laserpeople.detection import adaboost, compiled, features
from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceSegmenter, SegmentTable, covers_full_circle

TOL = 1e-12
NAME = compiled.NAME


def _both(
    ext: ModuleType,
    tables: list[SegmentTable],
    scans: list[Scan],
    previous: list[Scan | None],
    circle: list[bool],
) -> tuple[features.SegmentFeatures, features.SegmentFeatures]:
    params = features.DEFAULT_FEATURE_PARAMS
    with np.errstate(divide="ignore", invalid="ignore"):
        want = features._compute(tables, scans, previous, params, circle)
    got = features._compute_compiled(ext, tables, scans, previous, params, circle)[0]
    return want, got


def _assert_same(want: features.SegmentFeatures, got: features.SegmentFeatures) -> None:
    for name in ("values", "max_beam_motion", "centres", "circle_centres"):
        np.testing.assert_allclose(
            getattr(got, name), getattr(want, name), rtol=TOL, atol=TOL, err_msg=name
        )


SIZES = (1, 2, 3, 4, 7, 8, 9, 15, 16, 17, 127, 128, 129, 130, 300)


def _random_points(rng: np.random.Generator, n: int, kind: str) -> np.ndarray:
    """``n`` points of one kind of segment, about 1-5 m from the sensor."""
    origin = rng.uniform(-5.0, 5.0, 2)
    if kind == "noise":
        return origin + rng.normal(0.0, 0.05, (n, 2))
    if kind == "arc":
        t = np.sort(rng.uniform(0.0, 2.5, n))
        return origin + 0.07 * np.c_[np.cos(t), np.sin(t)] + rng.normal(0.0, 1e-3, (n, 2))
    if kind == "collinear":
        return origin + np.outer(np.linspace(0.0, 1.0, n), rng.normal(size=2))
    if kind == "repeated":
        pts = origin + rng.normal(0.0, 0.05, (n, 2))
        pts[rng.integers(0, n, n // 2 + 1)] = pts[0]
        return pts
    if kind == "identical":
        return np.repeat(origin[None, :], n, axis=0)
    assert kind == "even"
    return origin + np.outer(np.arange(n) * 0.01, [1.0, 0.0])


KINDS = ("noise", "arc", "collinear", "repeated", "identical", "even")


def _block(
    rng: np.random.Generator, n_scans: int
) -> tuple[list[SegmentTable], list[Scan], list[Scan | None], list[bool]]:
    """A block of scans of random segments (their beams in order, so that feature 14 reads
    the scans' ranges), some with a previous scan, some full circles, some sweeping
    clockwise."""
    tables, scans, previous, circle = [], [], [], []
    for q in range(n_scans):
        sizes = rng.choice(SIZES, size=int(rng.integers(1, 6)))
        pts = np.concatenate([_random_points(rng, int(n), rng.choice(KINDS)) for n in sizes])
        k = pts.shape[0]
        offsets = np.zeros(sizes.size + 1, dtype=np.int64)
        np.cumsum(sizes, out=offsets[1:])
        n_beams = k + 5
        tables.append(SegmentTable(np.arange(k), pts, offsets, n_beams))
        step = 2 * np.pi / n_beams if q % 3 == 1 else 0.01
        increment = -step if q % 2 else step
        ranges = rng.uniform(0.5, 5.0, n_beams)
        scans.append(Scan(float(q + 1), 0.0, increment, ranges, index=q))
        if q % 4 == 3:
            previous.append(None)
        else:
            before = ranges + rng.normal(0.0, 0.02, n_beams)
            before[rng.random(n_beams) < 0.2] = np.nan
            previous.append(Scan(q + 0.9, 0.0, increment, before, index=q))
        circle.append(covers_full_circle(scans[-1]))
    return tables, scans, previous, circle


@pytest.mark.parametrize("seed", range(6))
def test_random_and_degenerate_segments_give_the_reference_features(
    cfeatures: ModuleType, seed: int
) -> None:
    rng = np.random.default_rng(seed)
    for n_scans in (1, 2, 5):
        tables, scans, previous, circle = _block(rng, n_scans)
        _assert_same(*_both(cfeatures, tables, scans, previous, circle))


def test_the_same_legs_on_simulated_scans(cfeatures: ModuleType) -> None:
    """What the user sees: the shipped model finds the same legs with either path in the
    scans of a simulated scene (the features within the tolerance; a last-bit difference
    on another CPU may flip a segment whose score lies in the rounding noise, so up to one
    segment in 500 may differ), and the legs both find score within 1e-9."""
    from laserpeople.detection.detector import DEFAULT_LEG_DETECTOR_PARAMS, default_model
    from laserpeople.sim import run_scenario

    scans = run_scenario("crossing-3", seconds=3.0, seed=2).scans
    tables = JumpDistanceSegmenter().many(scans)
    last: dict[str, Scan] = {}
    previous: list[Scan | None] = []
    for scan in scans:
        previous.append(last.get(scan.sensor))
        last[scan.sensor] = scan
    want, got = _both(cfeatures, tables, scans, previous, [covers_full_circle(s) for s in scans])
    _assert_same(want, got)
    model = default_model()
    columns = list(model.columns)
    scores_want = model.classifier.decision_function(want.values[:, columns])
    scores_got = model.classifier.decision_function(got.values[:, columns])
    threshold = DEFAULT_LEG_DETECTOR_PARAMS.score_threshold
    legs_want, legs_got = scores_want > threshold, scores_got > threshold
    assert legs_want.sum() > 100
    assert np.count_nonzero(legs_want != legs_got) <= len(want) // 500
    both = legs_want & legs_got
    np.testing.assert_allclose(scores_got[both], scores_want[both], rtol=1e-9, atol=1e-9)


def test_no_previous_scan_and_a_single_segment(cfeatures: ModuleType) -> None:
    rng = np.random.default_rng(5)
    for n in (1, 2, 3, 4):
        pts = _random_points(rng, n, "noise")
        table = SegmentTable(np.arange(n), pts, np.array([0, n]), n)
        scan = Scan(0.0, 0.0, 0.01, np.ones(n))
        want, got = _both(cfeatures, [table], [scan], [None], [False])
        _assert_same(want, got)
        assert got.values[0, 3] == got.values[0, 4] == 100.0  # (no neighbour)
        assert got.values[0, 13] == 0.0 and got.max_beam_motion[0] == 0.0


def test_simulated_scans_give_the_reference_features(cfeatures: ModuleType) -> None:
    from laserpeople.sim import run_scenario

    scans = run_scenario("crossing-3", seconds=3.0, seed=4).scans
    segmenter = JumpDistanceSegmenter()
    tables = segmenter.many(scans)
    last: dict[str, Scan] = {}
    previous: list[Scan | None] = []
    for scan in scans:  # (two lasers)
        previous.append(last.get(scan.sensor))
        last[scan.sensor] = scan
    want, got = _both(cfeatures, tables, scans, previous, [covers_full_circle(s) for s in scans])
    assert len(got) > 1000
    _assert_same(want, got)


def test_the_tolerance_tells_a_wrong_feature(cfeatures: ModuleType) -> None:
    """The comparison is not vacuous: a feature off by a part in 1e10 fails the stated
    tolerance."""
    rng = np.random.default_rng(3)
    pts = _random_points(rng, 300, "noise")
    table = SegmentTable(np.arange(300), pts, np.array([0, 300]), 300)
    scan = Scan(0.0, 0.0, 0.01, np.ones(300))
    want, got = _both(cfeatures, [table], [scan], [None], [False])
    _assert_same(want, got)
    wrong = features.SegmentFeatures(
        got.values * (1 + 1e-10), got.max_beam_motion, got.centres, got.circle_centres
    )
    with pytest.raises(AssertionError):
        _assert_same(want, wrong)


def test_compute_features_many_runs_the_extension_and_python_alike(
    cfeatures: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(8)
    tables, scans, previous, circle = _block(rng, 3)
    monkeypatch.setattr(features, "_extension", cfeatures)
    compiled = features.compute_features_many(tables, scans, previous, full_circle=circle)
    monkeypatch.setattr(features, "_extension", None)
    python = features.compute_features_many(tables, scans, previous, full_circle=circle)
    for a, b in zip(compiled, python, strict=True):
        _assert_same(b, a)


def _stump_tables() -> adaboost._StumpTables:
    from laserpeople.detection.detector import default_model

    tables = default_model().classifier._tables
    assert isinstance(tables, adaboost._StumpTables)
    return tables


def test_stump_sums_give_the_reference_margins(
    cfeatures: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The shipped model's margins of random rows, rows of its thresholds themselves (a
    tie counts -1 for one polarity and +1 for the other: left and right ranks), their
    neighbouring floats and a single row, the same floats both ways."""
    tables = _stump_tables()
    rng = np.random.default_rng(9)
    width = int(tables.columns.max()) + 1
    rows = [rng.normal(0.0, 1.0, (200, width)) * rng.choice([1e-3, 0.1, 1.0, 100.0], width)]
    picks = rng.choice(tables.grid, (300, width))
    rows += [picks, np.nextafter(picks, np.inf), np.nextafter(picks, -np.inf), picks[:1]]
    for X in rows:
        monkeypatch.setattr(adaboost, "_extension", None)
        want = tables.evaluate(X)
        monkeypatch.setattr(adaboost, "_extension", cfeatures)
        got = tables.evaluate(X)
        np.testing.assert_allclose(got, want, rtol=TOL, atol=TOL)
        np.testing.assert_array_equal(got > 0, want > 0)  # (the same legs)
    ties = tables.evaluate(picks)
    assert not np.array_equal(ties, tables.evaluate(np.nextafter(picks, np.inf)))


def test_the_pure_python_switch(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(extensions.PURE_PYTHON, "1")
    assert extensions.load_extension(NAME, compiled.SOURCE, "segment features") == (
        None,
        "pure Python (LASERPEOPLE_PURE_PYTHON is set)",
    )


def test_extension_not_built_runs_python(monkeypatch: pytest.MonkeyPatch) -> None:
    from laserpeople import detection

    monkeypatch.delenv(extensions.PURE_PYTHON, raising=False)
    monkeypatch.delattr(detection, "_cfeatures", raising=False)
    monkeypatch.setitem(sys.modules, NAME, None)  # (ImportError)
    assert extensions.load_extension(NAME, compiled.SOURCE, "segment features") == (
        None,
        "pure Python (the C extension is not built)",
    )


def test_a_stale_extension_is_not_used(
    cfeatures: ModuleType, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.delenv(extensions.PURE_PYTHON, raising=False)
    edited = tmp_path / "_cfeatures.c"
    edited.write_bytes(compiled.SOURCE.read_bytes() + b"\n")
    with pytest.warns(extensions.StaleExtensionWarning, match=r"segment features.*pip install"):
        module, which = extensions.load_extension(NAME, edited, "segment features")
    assert module is None and "stale" in which
    edited.write_bytes(compiled.SOURCE.read_bytes())
    assert extensions.load_extension(NAME, edited, "segment features") == (
        cfeatures,
        "compiled (C extension)",
    )


def test_without_the_extension_detection_runs_in_python(tmp_path: Path) -> None:
    """A fresh process where the extension cannot be imported (no C compiler at install)
    detects the legs with the Python features."""
    script = textwrap.dedent(
        f"""
        import sys
        sys.modules[{NAME!r}] = None
        import numpy as np
        from laserpeople.detection import features
        from laserpeople.detection.detector import AdaBoostLegDetector
        from laserpeople.scan import Scan
        from laserpeople.detection import adaboost, compiled
        assert features._extension is None and adaboost._extension is None
        assert compiled.EXTENSION is None, compiled.IMPLEMENTATION
        ranges = np.r_[np.full(20, 3.0), np.full(8, 1.5), np.full(20, 3.0)]
        det = AdaBoostLegDetector.default().detect(Scan(0.0, -0.4, 0.017, ranges))
        print(compiled.IMPLEMENTATION, len(det.positions))
        """
    )
    env = {k: v for k, v in os.environ.items() if k != extensions.PURE_PYTHON}
    done = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        check=False,
        timeout=120,
        env=env,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("pure Python (the C extension is not built)")
