"""The compiled listing (the C extension ``_clisting``) gives the Python listing's children,
on random clusters and on the calls a tracker makes; the switch to the Python listing and
the stale-extension guard."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from laserpeople.tracking.mht import compiled, listing
from laserpeople.tracking.mht.probability import (
    DETECTED,
    FALSE_ALARM,
    MATCHED,
)
from laserpeople.tracking.synthetic import walkers_scene

# the costs are sums of the same floats in the same order (no multiplication), so they are
# the same bits on any CPU; compared within this absolute tolerance all the same
COST_TOL = 1e-12

INF = math.inf


def _load_extension() -> ModuleType:
    """The built extension, set up as the listing sets it up; skips when it is not built or
    stale (the Python listing then runs: nothing to compare)."""
    try:
        from laserpeople.tracking.mht import _clisting
    except ImportError:
        pytest.skip("the C extension is not built (`pip install -e .` with a C compiler)")
    if compiled.source_hash(compiled.SOURCE) != _clisting.SOURCE_HASH:
        pytest.skip("the C extension is stale (`pip install -e .` rebuilds it)")
    listing.set_up(_clisting)
    return _clisting


@pytest.fixture(scope="module")
def clisting() -> ModuleType:
    return _load_extension()


def _comparable(out: Any) -> Any:
    """A listing's result with its costs taken out: (children, costs)."""
    if out is None:
        return None, []
    children = [
        (pi, list(d.track_label), tuple(d.track_measurement), list(d.measurement_label))
        for pi, d, _ in out
    ]
    return children, [(d.cost, total) for _, d, total in out]


def _assert_same(c_out: Any, py_out: Any) -> None:
    c_children, c_costs = _comparable(c_out)
    py_children, py_costs = _comparable(py_out)
    assert c_children == py_children
    for (a, ta), (b, tb) in zip(c_costs, py_costs, strict=True):
        assert a == pytest.approx(b, rel=0.0, abs=COST_TOL) or a == b  # (b infinite)
        assert ta == pytest.approx(tb, rel=0.0, abs=COST_TOL) or ta == tb


def _python_takes(args: tuple[Any, ...]) -> bool:
    """Whether the compiled listing leaves the call to the Python one (NotImplemented)."""
    priors, rows, _, _, _, c_new, _, k, _, _, shortcut, _ = args
    single = shortcut and len(c_new) <= 1 and all(len(r) <= 1 for r in rows)
    return single or k < 1 or any(math.isnan(p) for p in priors)


def _compare(clisting: ModuleType, args: tuple[Any, ...]) -> Any:
    """Both listings on ``args`` (list_children's twelve); the Python result."""
    want = listing.list_children_python(*args)
    got = clisting.list_children(*args)
    if got is NotImplemented:
        assert _python_takes(args)
        return want
    assert not _python_takes(args) or want is None
    _assert_same(got, want)
    return want


COSTS = [-1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 3.25, INF]  # few values: many ties and equal sums


@st.composite
def clusters(draw: st.DrawFn) -> tuple[Any, ...]:
    """list_children's arguments: a random cluster, its costs from few values (ties) or
    any floats, infinite labels, parents and gaps, small listing limits and budgets."""
    n = draw(st.integers(0, 6))
    m = draw(st.integers(0, 7) | st.just(11))
    tied = draw(st.booleans())
    cost = st.sampled_from(COSTS) if tied else (st.floats(-3.0, 20.0) | st.just(INF))
    tm = [[draw(cost) for _ in range(m)] for _ in range(n)]
    c_occ = [draw(cost) for _ in range(n)]
    c_del = [draw(cost) for _ in range(n)]
    c_new = [draw(cost) for _ in range(m)]
    c_fal = [draw(cost) for _ in range(m)]
    n_parents = draw(st.integers(1, 5))
    rows = [
        draw(st.lists(st.integers(0, n - 1), unique=True, max_size=n)) if n else []
        for _ in range(n_parents)
    ]
    priors = [draw(st.sampled_from([0.0, 0.5, 1.0, 1.25, INF]) | st.floats(0.0, 5.0))]
    priors += [draw(st.sampled_from([0.0, 0.5, 1.0, 1.25, INF])) for _ in rows[1:]]
    k = draw(st.integers(1, 12))
    max_gap = draw(st.sampled_from([0.0, 0.5, 2.0, 9.0, INF]))
    limit = draw(st.sampled_from([listing.LISTING_LIMIT, 0, 3, 50, 10**12, -1]))
    shortcut = draw(st.booleans())
    budget = draw(st.sampled_from([listing.LISTING_BUDGET, 0, 1, 2, 5, 30]))
    return (priors, rows, tm, c_occ, c_del, c_new, c_fal, k, max_gap, limit, shortcut, budget)


@settings(max_examples=1500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(args=clusters())
def test_compiled_listing_gives_the_python_listings_children(args: tuple[Any, ...]) -> None:
    """Random clusters (ties, infinite labels and parents, more measurements than are
    listed, listing limits and budgets that run out): the same children (parents, labels,
    order), None where the Python listing gives None, and the same costs."""
    _compare(_load_extension(), args)


def test_compiled_listing_by_hand(clisting: ModuleType) -> None:
    """A cluster whose children are worked out by hand: parent 1 (prior 0.5, track 1) and
    parent 0 (prior 0, tracks 0 and 1), three measurements. Its best child is parent 1's
    track detected with measurement 0 (0.5), the other two false alarms (1.0 + 0.9): 2.9;
    then parent 0's tracks with measurements 1 and 0 (2.0 + 0.5) and the third a false
    alarm: 3.4."""
    args = (
        [0.0, 0.5],
        [[0, 1], [1]],
        [[1.0, 2.0, INF], [0.5, INF, 3.0]],
        [2.0, 2.5],
        [4.0, 3.0],
        [1.5, 1.6, 1.7],
        [2.1, 1.0, 0.9],
        2,
        8.0,
        listing.LISTING_LIMIT,
        True,
        listing.LISTING_BUDGET,
    )
    out = clisting.list_children(*args)
    assert [(pi, d.track_label, d.track_measurement, d.measurement_label) for pi, d, _ in out] == [
        (1, [DETECTED], (0,), [MATCHED, FALSE_ALARM, FALSE_ALARM]),
        (0, [DETECTED, DETECTED], (1, 0), [MATCHED, MATCHED, FALSE_ALARM]),
    ]
    assert [t for _, _, t in out] == pytest.approx([2.9, 3.4], rel=0.0, abs=COST_TOL)
    _compare(clisting, args)
    # one step of budget beyond a listing limit of 0: none (Murty's method takes it)
    assert clisting.list_children(*args[:9], 0, True, 1) is None
    assert listing.list_children_python(*args[:9], 0, True, 1) is None
    # a lone track and measurement: the Python shortcut's
    lone = ([0.0], [[0]], [[1.0]], [2.0], [3.0], [1.5], [2.5], 3, 9.0, 10, True, 10)
    assert clisting.list_children(*lone) is NotImplemented
    assert _comparable(listing.list_children(*lone)) == _comparable(
        listing.list_children_python(*lone)
    )


def test_compiled_listing_on_a_trackers_calls(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every call the leg MHT makes on a scene of six walkers with clutter: the same
    children from both listings."""
    import laserpeople.tracking.mht.core as core
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    calls: list[tuple[Any, ...]] = []

    def recorded(*args: Any, **kwargs: Any) -> Any:
        full = (
            *args,
            kwargs.get("limit", listing.LISTING_LIMIT),
            kwargs.get("shortcut", True),
            kwargs.get("budget", listing.LISTING_BUDGET),
        )
        calls.append(full)
        return listing.list_children_python(*full)

    monkeypatch.setattr(core, "list_children", recorded)
    monkeypatch.setattr(listing, "COMPILED_K_BEST", None)  # (every cluster calls the listing)
    tracker = LegMHTTracker(LegTrackerParams())
    for d in walkers_scene(21, 1.5).detections:
        tracker.update(d)
    assert len(calls) > 200
    listed = sum(len(_compare(clisting, call) or []) for call in calls)
    assert listed > 500
    assert max(len(call[5]) for call in calls) >= 3  # clusters of several measurements


@pytest.mark.parametrize("parts", [("listing",), ("k_best",), ("listing", "k_best")])
def test_tracker_with_the_compiled_listing_holds_the_same_hypotheses(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch, parts: tuple[str, ...]
) -> None:
    """Two leg MHTs stepped side by side, one with compiled ``parts`` (the listing alone,
    the k best children of a cluster from the scan's tables alone, both) and one with the
    Python listing: the same hypotheses after every scan (tracks exactly, weights within
    the tolerance) and the same reported tracks; the compiled k best took most clusters of
    the general path."""
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    fast, slow = LegMHTTracker(LegTrackerParams()), LegMHTTracker(LegTrackerParams())
    taken = {"compiled": 0, "python": 0}

    def k_best(*args: Any) -> Any:
        out = clisting.k_best_plain(*args)
        taken["python" if out is NotImplemented else "compiled"] += 1
        return out

    def state(tracker: LegMHTTracker) -> tuple[list[Any], list[float]]:
        hyps = [h for c in tracker.mht.clusters for h in c.hypotheses]
        return [[t.node_id for t in h.tracks] for h in hyps], [h.log_weight for h in hyps]

    for d in walkers_scene(21, 1.5).detections:
        monkeypatch.setattr(
            listing, "COMPILED", clisting.list_children if "listing" in parts else None
        )
        monkeypatch.setattr(listing, "COMPILED_K_BEST", k_best if "k_best" in parts else None)
        out_fast = fast.update(d)
        monkeypatch.setattr(listing, "COMPILED", None)
        monkeypatch.setattr(listing, "COMPILED_K_BEST", None)
        out_slow = slow.update(d)
        (ids_f, w_f), (ids_s, w_s) = state(fast), state(slow)
        assert ids_f == ids_s, d.scan_index
        assert w_f == pytest.approx(w_s, rel=0.0, abs=COST_TOL), d.scan_index
        assert [(t.track_id, t.position.tobytes()) for t in out_fast] == [
            (t.track_id, t.position.tobytes()) for t in out_slow
        ]
    if "k_best" in parts:
        assert taken["compiled"] > 200 and taken["compiled"] > 10 * taken["python"]


def test_compiled_k_best_takes_each_clusters_own_costs(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Rates that differ per measurement and clusters whose measurements do not start the
    scan's list (three targets, two close, misses and clutter): the MHT whose clusters'
    k best children the compiled code lists from the scan's tables holds the hypotheses of
    the one whose Python path takes them from the same tables."""
    from laserpeople.tracking.kalman import KalmanParams
    from laserpeople.tracking.mht.core import MHT, MHTParams
    from laserpeople.tracking.point_model import KalmanPointModel
    from test_track_mht_core import PlaceLabels, meas

    taken = 0

    def k_best(*args: Any) -> Any:
        nonlocal taken
        out = clisting.k_best_plain(*args)
        taken += out is not NotImplemented and args[4][:1] != [0]
        return out

    def make() -> Any:
        return MHT(MHTParams(), KalmanPointModel(KalmanParams()), PlaceLabels())

    fast, slow = make(), make()
    rng = np.random.default_rng(3)
    for step in range(60):
        t = 0.1 * step
        pts = np.array([[1 + 0.5 * t, 0.0], [1 + 0.5 * t, 0.3], [4.0, -2 + 0.3 * t]])
        pts = pts[rng.random(3) > 0.15]
        if rng.random() < 0.3:
            pts = np.vstack([rng.uniform(0, 5, (1, 2)), pts])
        monkeypatch.setattr(listing, "COMPILED_K_BEST", k_best)
        fast.step(meas(pts), t)
        monkeypatch.setattr(listing, "COMPILED_K_BEST", None)
        slow.step(meas(pts), t)
        got = [(h.log_weight, h.key()) for c in fast.clusters for h in c.hypotheses]
        want = [(h.log_weight, h.key()) for c in slow.clusters for h in c.hypotheses]
        assert [key for _, key in got] == [key for _, key in want], step
        assert [w for w, _ in got] == pytest.approx([w for w, _ in want], rel=0.0, abs=COST_TOL)
    assert taken >= 4  # clusters of measurements after the scan's first, listed compiled


def test_compiled_k_best_leaves_other_tables_to_python(clisting: ModuleType) -> None:
    """A table of detection costs that is not float64 in C order, a node not scored this
    scan, a cluster over the size limit, and the shortcut's cluster: NotImplemented (the
    Python path takes them); otherwise the children of the listing on the same costs."""
    from types import SimpleNamespace

    table = np.array([[1.0, 2.0, INF], [0.5, INF, 3.0], [9.0, 9.0, 9.0]])
    a, b = SimpleNamespace(node_id=7), SimpleNamespace(node_id=3)
    plain = ([2.0, 2.5, 0.0], [4.0, 3.0, 0.0], [1.5, 1.6, 1.7], [2.1, 1.0, 0.9])

    def k_best(cost: Any, tracks_of: Any, row_of: Any, meas: Any, size: int = 200) -> Any:
        return clisting.k_best_plain(
            tracks_of, [0.0, 0.5], row_of, cost, meas, *plain, 5, 8.0, True, size
        )

    rows = {7: 0, 3: 1}
    out, size = k_best(table, [(a, b), (b,)], rows, [0, 1, 2])
    assert size == 5
    want = listing.list_children_python(  # (the nodes at rows 0 and 1 of the tables)
        [0.0, 0.5], [[0, 1], [1]], table[:2].tolist(), plain[0][:2], plain[1][:2], *plain[2:],
        5, 8.0,
    )  # fmt: skip
    assert want
    _assert_same(out, want)
    assert k_best(np.asfortranarray(table), [(a, b), (b,)], rows, [0, 1, 2]) is NotImplemented
    assert k_best(table.astype(np.float32), [(a, b), (b,)], rows, [0, 1, 2]) is NotImplemented
    assert k_best(table, [(a, b), (b,)], {7: 0}, [0, 1, 2]) is NotImplemented
    assert k_best(table, [(a, b), (b,)], rows, [0, 1, 2], size=4) is NotImplemented
    assert k_best(table, [(a,), (b,)], rows, [2]) is NotImplemented


def _components_cases(rng: np.random.Generator, n: int) -> list[tuple[Any, ...]]:
    """``n`` random inputs of :func:`core.components`: up to 30 families (small ids and
    ids up to 2^40, whose sets' tables collide), up to 25 measurements, gates of 0-3 of
    them, up to 8 links."""
    cases = []
    for _ in range(n):
        nf, m = int(rng.integers(0, 31)), int(rng.integers(0, 26))
        top = int(rng.choice([40, 100, 10**6, 2**40]))
        fams = [int(f) for f in rng.choice(top, size=min(nf, top), replace=False)]
        gates = {f: {int(j) for j in rng.choice(m, size=int(rng.integers(0, 4)))} if m else set()
                 for f in fams}  # fmt: skip
        links = {}
        for _ in range(int(rng.integers(0, 9)) if len(fams) >= 2 else 0):
            a, b = sorted(int(f) for f in rng.choice(fams, size=2, replace=False))
            links[(a, b)] = 1
        cases.append((gates, links, m))
    return cases


def test_compiled_components_are_the_python_ones(clisting: ModuleType) -> None:
    """The compiled components of random scans are the Python ones: the same components in
    the same order, each one's measurements and its frozenset of families iterated in the
    same order (what the step's loops over a cluster's families see)."""
    from laserpeople.tracking.mht import core

    def seen(out: Any) -> list[tuple[list[int], list[int]]]:
        return [(list(fams), meas) for fams, meas in out]

    singles = 0
    for gates, links, m in _components_cases(np.random.default_rng(21), 4000):
        got = clisting.components(gates, links, m)
        want = core.components_python(gates, links, m)
        assert seen(got) == seen(want), (gates, links, m)
        assert all(type(f) is frozenset and type(j) is list for f, j in got)
        singles += sum(len(f) == 1 for f, _ in got)
    assert singles > 1000
    # a scan by hand: families 7 and 3 share measurement 1, 9 is linked to 3, 5 alone,
    # measurement 2 in no gate
    got = clisting.components({7: {1}, 5: set(), 3: {0, 1}, 9: set()}, {(3, 9): 4}, 3)
    assert [(sorted(f), j) for f, j in got] == [([3, 7, 9], [0, 1]), ([5], []), ([], [2])]


def test_compiled_components_leave_refused_input_to_python(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Input the Python components refuse (a measurement out of range, a link of an unknown
    family, a gate that is not ints) is left to them (NotImplemented), so
    :func:`core.components` raises what they raise; with no extension they run alone."""
    from laserpeople.tracking.mht import core

    for gates, links, m in (({1: {5}}, {}, 3), ({1: set()}, {(1, 2): 0}, 0)):
        assert clisting.components(gates, links, m) is NotImplemented
        with pytest.raises(KeyError):
            core.components(gates, links, m)
    assert clisting.components({1: {"a"}}, {}, 3) is NotImplemented
    monkeypatch.setattr(listing, "COMPILED_COMPONENTS", None)
    assert core.components({4: {0}, 2: {0}}, {}, 2) == [
        (frozenset({2, 4}), [0]),
        (frozenset(), [1]),
    ]


def test_compiled_detection_costs_are_numpys(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The compiled detection costs of a scan are numpy's within 1e-15 relative (one
    addition and a negation per pair; infinities and NaNs where numpy has them): random
    tables of 0-40 nodes and 0-30 measurements with infinities and NaNs among the
    log-likelihoods, and by hand (the detected column, not another, and inf where not
    gated); arrays it does not take raise ValueError and :func:`core._detection_costs`
    gives numpy's for them."""
    from laserpeople.tracking.mht import core

    rng = np.random.default_rng(35)
    for _ in range(800):
        t, m = int(rng.integers(0, 41)), int(rng.integers(0, 31))
        gated = rng.random((t, m)) < 0.4
        loglik = rng.normal(-3.0, 40.0, (t, m))
        loglik[rng.random((t, m)) < 0.05] = -np.inf
        loglik[rng.random((t, m)) < 0.02] = np.nan
        lp = np.log(rng.dirichlet((1.0, 1.0, 1.0), t)).reshape(t, 3)
        out = np.empty((t, m))
        clisting.detection_costs(gated, loglik, lp, out)
        want = core._detection_costs_python(gated, loglik, lp)
        np.testing.assert_allclose(out, want, rtol=1e-15, atol=0.0)
        np.testing.assert_allclose(
            core._detection_costs(gated, loglik, lp), want, rtol=1e-15, atol=0.0
        )
    lp = np.log(np.array([[0.5, 0.25, 0.25], [0.2, 0.7, 0.1]]))
    got = core._detection_costs(np.array([[True, False], [False, True]]), np.ones((2, 2)), lp)
    assert got[0, 0] == -(math.log(0.5) + 1.0) and got[1, 1] == -(math.log(0.2) + 1.0)
    assert got[0, 1] == got[1, 0] == INF
    gated, loglik = np.ones((3, 2), dtype=bool), np.zeros((3, 2))
    for bad in (
        (gated, loglik, np.zeros((3, 2)), np.empty((3, 2))),  # lp not (T, 3)
        (gated, loglik[:2], np.zeros((3, 3)), np.empty((3, 2))),  # rows differ
        (gated.T.copy(), loglik, np.zeros((3, 3)), np.empty((3, 2))),  # gated (M, T)
        (gated, loglik, np.zeros((3, 3)), np.empty((2, 3))),  # out (M, T)
        (gated.astype(np.float64), loglik, np.zeros((3, 3)), np.empty((3, 2))),
    ):
        with pytest.raises(ValueError):
            clisting.detection_costs(*bad)
    strided = np.zeros((3, 4))[:, ::2]  # (not C-contiguous: numpy's path)
    lp = np.log(np.full((3, 3), 1 / 3))
    assert np.array_equal(
        core._detection_costs(gated, strided, lp), core._detection_costs_python(gated, strided, lp)
    )
    monkeypatch.setattr(listing, "COMPILED_DETECTION_COSTS", None)
    assert np.array_equal(
        core._detection_costs(gated, loglik, lp), core._detection_costs_python(gated, loglik, lp)
    )


def test_pure_python_switch(monkeypatch: pytest.MonkeyPatch) -> None:
    """LASERPEOPLE_PURE_PYTHON set (not to 0) runs the Python listing, and says so."""
    monkeypatch.setenv(compiled.PURE_PYTHON, "1")
    module, which = compiled.load()
    assert module is None and which == "pure Python (LASERPEOPLE_PURE_PYTHON is set)"
    monkeypatch.setenv(compiled.PURE_PYTHON, "0")
    module, which = compiled.load()
    assert compiled.PURE_PYTHON not in which
    assert (module is None) == which.startswith("pure Python")


def test_extension_not_built_runs_python(monkeypatch: pytest.MonkeyPatch) -> None:
    import laserpeople.tracking.mht as package

    monkeypatch.delenv(compiled.PURE_PYTHON, raising=False)
    monkeypatch.delattr(package, "_clisting", raising=False)
    monkeypatch.setitem(sys.modules, "laserpeople.tracking.mht._clisting", None)  # (ImportError)
    assert compiled.load() == (None, "pure Python (the C extension is not built)")


def test_stale_extension_runs_python_and_says_how_to_rebuild(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """A source beside the extension other than the one it was built from (one byte
    more): the Python listing runs, with a warning naming the rebuild command; the same
    source: the extension runs."""
    monkeypatch.delenv(compiled.PURE_PYTHON, raising=False)
    edited = tmp_path / "_clisting.c"
    edited.write_bytes(compiled.SOURCE.read_bytes() + b"\n")
    monkeypatch.setattr(compiled, "SOURCE", edited)
    with pytest.warns(compiled.StaleExtensionWarning, match=r"pip install -e \."):
        module, which = compiled.load()
    assert module is None and "stale" in which
    edited.write_bytes(compiled.SOURCE.read_bytes()[:-1])
    assert compiled.load() == (clisting, "compiled (C extension)")
