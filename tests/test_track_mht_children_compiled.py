"""The plain MHT's bookkeeping around the listing, compiled (the C extension ``_clisting``):
``prune`` gives :func:`~laserpeople.tracking.mht.hypothesis.prune_children`'s hypotheses, in
its order, with its log weights; ``plan_plain`` and ``assemble_plain`` give
``MHT._plan_plain``'s and ``MHT._assemble``'s children; on random children, by hand and on a
tracker's clusters; what they leave to Python.

The pruning computes every weight by the same IEEE operations in the same order as the
Python one, with ``exp`` and ``log`` from the same C library (Python's ``math`` calls it)
and ``math.fsum``'s exact algorithm, so on this machine they agree to the bit; the tests
compare them within ``WEIGHT_TOL`` (another compiler or C library may differ in the last
bits) and what they decide exactly, except the one hand-made case whose last bit tells
``fsum``'s total from a plain sum. The plan and the assembly make no float but ``-total`` and
numpy's ``logaddexp`` (called by both)."""

from __future__ import annotations

import copy
import math
from types import ModuleType
from typing import Any

import numpy as np
import pytest

from laserpeople.tracking.mht import compiled, listing
from laserpeople.tracking.mht.hypothesis import Hypothesis, logsumexp, prune_children
from laserpeople.tracking.synthetic import walkers_scene


@pytest.fixture(scope="module")
def clisting() -> ModuleType:
    """The built extension; skips when it is not built or stale (nothing to compare)."""
    try:
        from laserpeople.tracking.mht import _clisting
    except ImportError:
        pytest.skip("the C extension is not built (`pip install -e .` with a C compiler)")
    if compiled.source_hash(compiled.SOURCE) != _clisting.SOURCE_HASH:
        pytest.skip("the C extension is stale (`pip install -e .` rebuilds it)")
    return _clisting


def _children(rng: np.random.Generator, depth: int, trial: int) -> list[Hypothesis]:
    """Random children: weights spread widely or tied (exact duplicates, -1e-300, 0),
    histories mostly ``depth`` long (some shorter), ancestors ints or, as a joined
    cluster's, tuples; 1 to 24 of them."""
    n = int(rng.integers(1, 25))
    if trial % 3:
        weights = rng.normal(-3.0, 3.0 if trial % 2 else 30.0, size=n).tolist()
    else:
        weights = rng.choice([-1.0, -2.0, -3.5, -1e-300, 0.0], size=n).tolist()
    out = []
    for i, w in enumerate(weights):
        length = depth if rng.random() < 0.9 else int(rng.integers(0, max(depth, 1)))
        joined = trial % 5 == 0
        ancestors = tuple(
            (int(rng.integers(0, 3)), 7) if joined else int(rng.integers(0, 3))
            for _ in range(length)
        )
        out.append(Hypothesis(w, (), ancestors, hypothesis_id=i))
    return out


WEIGHT_TOL = 1e-12
"""Log weights of the compiled and the Python path agree within this (the same operations
in the same order, so on this machine to the bit; another C library may differ in the last
bits): what the user sees, which hypotheses and in which order, is compared exactly."""


def _same(got: list[Hypothesis], want: list[Hypothesis]) -> None:
    assert [h.hypothesis_id for h in got] == [h.hypothesis_id for h in want]
    assert [h.log_weight for h in got] == pytest.approx(
        [h.log_weight for h in want], rel=0.0, abs=WEIGHT_TOL
    )


def _same_tracks(got: Any, want: Any) -> None:
    """Two trackers' reported tracks: the same ids in the same order, positions within
    WEIGHT_TOL [m]."""
    assert [t.track_id for t in got] == [t.track_id for t in want]
    for g, w in zip(got, want, strict=True):
        np.testing.assert_allclose(g.position, w.position, rtol=0.0, atol=WEIGHT_TOL)


def _same_state(fast: tuple[Any, ...], slow: tuple[Any, ...], scan: int) -> None:
    """Two trackers' states (their hypotheses' log weights last): the same structure
    exactly, the weights within :data:`WEIGHT_TOL`."""
    assert fast[:-1] == slow[:-1], scan
    assert fast[-1] == pytest.approx(slow[-1], rel=0.0, abs=WEIGHT_TOL), scan


def test_compiled_prune_is_the_python_one_on_random_children(clisting: ModuleType) -> None:
    """6000 random clusters' children at N-scan depths 0-8 and ratios 0-0.5: the same
    hypotheses in the same order with the same log weights, every case met (one and
    several ancestor groups, short histories, hypotheses dropped by the ratio)."""
    rng = np.random.default_rng(35)
    met: set[str] = set()
    for trial in range(6000):
        depth = int(rng.choice([0, 1, 2, 3, 8]))
        ratio = float(rng.choice([0.0, 1e-3, 1e-2, 0.1, 0.5]))
        hyps = _children(rng, depth, trial)
        want = prune_children(copy.deepcopy(hyps), depth, ratio)
        got = clisting.prune(list(hyps), depth, ratio)
        assert got is not NotImplemented, trial
        _same(got, want)
        if depth and all(len(h.ancestors) >= depth for h in hyps):
            met.add("groups" if len({h.ancestors[-depth] for h in hyps}) > 1 else "one group")
        elif depth:
            met.add("short history")
        if len(want) < len(hyps):
            met.add("dropped")
    assert met == {"groups", "one group", "short history", "dropped"}


def test_compiled_prune_by_hand(clisting: ModuleType) -> None:
    """Hand-made children whose results tell the rules from their near misses: the group
    of most mass wins over the group of the best hypothesis, a tie of masses goes to the
    first group, the ratio floor keeps a hypothesis at exactly ``log ratio`` below the best,
    and the total is ``math.fsum``'s (a plain sum is one ulp off here)."""
    # group a: 0.4 + 0.35 of the mass against b's best 0.25 alone
    a1 = Hypothesis(math.log(0.25), (), (1, "b"), hypothesis_id=1)
    a2 = Hypothesis(math.log(0.4), (), (1, "a"), hypothesis_id=2)
    a3 = Hypothesis(math.log(0.35), (), (2, "a"), hypothesis_id=3)
    got = clisting.prune([a1, a2, a3], 1, 0.0)
    assert [h.hypothesis_id for h in got] == [2, 3]
    assert got[0].log_weight == pytest.approx(math.log(0.4 / 0.75), abs=1e-15)
    # equal masses: the first group met (best first) is kept
    b = [Hypothesis(-1.0, (), ("x",), hypothesis_id=i) for i in range(2)]
    b[1].ancestors = ("y",)
    assert [h.hypothesis_id for h in clisting.prune(b, 1, 0.0)] == [0]
    # the ratio floor: the best minus log(ratio) exactly stays, one ulp below goes
    top = 0.0
    floor = top + math.log(0.01)
    c = [
        Hypothesis(top, (), (), hypothesis_id=0),
        Hypothesis(floor, (), (), hypothesis_id=1),
        Hypothesis(math.nextafter(floor, -math.inf), (), (), hypothesis_id=2),
    ]
    want = prune_children(copy.deepcopy(c), 3, 0.01)
    got = clisting.prune(c, 3, 0.01)
    _same(got, want)
    assert [h.hypothesis_id for h in got] == [0, 1]
    # math.fsum's total: weights whose exps a plain sum rounds differently
    ws = [0.0, math.log(1e-16), math.log(1e-16), math.log(0.5)]
    d = [Hypothesis(w, (), (), hypothesis_id=i) for i, w in enumerate(ws)]
    plain = max(ws) + math.log(sum(math.exp(w - max(ws)) for w in ws))
    assert logsumexp(ws) != plain
    got = clisting.prune(d, 3, 0.0)
    # exact: the one-ulp difference is what tells fsum's total from a plain sum (both
    # sides take exp and log from this machine's C library, as the extension does)
    assert [h.log_weight for h in got] == [w - logsumexp(ws) for w in sorted(ws, reverse=True)]


def test_compiled_prune_leaves_other_children_to_python(clisting: ModuleType) -> None:
    """Weights that are not finite, ancestors that cannot be hashed or are not a tuple:
    NotImplemented, the hypotheses untouched; no children: an empty list."""
    assert clisting.prune([], 3, 1e-3) == []
    for bad in (-math.inf, math.inf, math.nan):
        hyps = [Hypothesis(-1.0, (), (0,)), Hypothesis(bad, (), (0,))]
        assert clisting.prune(hyps, 1, 1e-3) is NotImplemented
        assert hyps[0].log_weight == -1.0
    unhashable = [Hypothesis(-1.0, (), ([0],)), Hypothesis(-2.0, (), ([1],))]
    assert clisting.prune(unhashable, 1, 1e-3) is NotImplemented
    listed = [Hypothesis(-1.0, (), [0]), Hypothesis(-2.0, (), [1])]  # type: ignore[arg-type]
    assert clisting.prune(listed, 1, 1e-3) is NotImplemented
    with pytest.raises(TypeError):
        clisting.prune(tuple(listed), 1, 1e-3)


def _cluster_by_hand() -> tuple[Any, ...]:
    """Two parents (tracks a, b; track a alone) and two measurements (scan indices 3 and
    5), the children the listing could give: detected, occluded and deleted tracks, births
    whose families sort before an old one's, and two children holding the same (no)
    tracks, which are joined. Fresh nodes on every call (occluded children are cached)."""
    from laserpeople.tracking.mht.hypothesis import Hypothesis
    from laserpeople.tracking.mht.matrix import LabelledAssignment
    from laserpeople.tracking.mht.probability import (
        DELETED,
        DETECTED,
        FALSE_ALARM,
        MATCHED,
        NEW,
        OCCLUDED,
    )
    from laserpeople.tracking.mht.tracktree import TrackNode

    def node(node_id: int, family: int) -> TrackNode:
        return TrackNode(node_id, family, -1, np.zeros(4), np.eye(4), 0.0, "new")

    a, b = node(0, 9), node(1, 2)
    a.children = {3: node(10, 9), 5: node(11, 9)}
    b.children = {5: node(12, 2)}
    new_nodes = {3: node(20, 7), 5: node(21, 6)}
    parents = [
        Hypothesis(-0.1, (b, a), (40, 41), hypothesis_id=50),
        Hypothesis(-2.3, (a,), (40, 42), hypothesis_id=51),
    ]
    tracks_of = [p.tracks for p in parents]

    def la(tlabels: list[int], tmeas: tuple[int, ...], mlabels: list[int]) -> Any:
        return LabelledAssignment(tlabels, tmeas, mlabels, 0.0)

    solutions = [
        (0, la([OCCLUDED, DETECTED], (-1, 0), [MATCHED, NEW]), 1.0),
        (0, la([DELETED, DELETED], (-1, -1), [NEW, NEW]), 2.0),
        (1, la([DELETED], (-1,), [FALSE_ALARM, FALSE_ALARM]), 2.5),
        (0, la([DELETED, DELETED], (-1, -1), [FALSE_ALARM, FALSE_ALARM]), 3.0),
        (1, la([DETECTED], (1,), [NEW, MATCHED]), 1.5),
        (0, la([DETECTED, DETECTED], (1, 0), [MATCHED, MATCHED]), 0.5),
    ]
    return solutions, parents, tracks_of, [3, 5], new_nodes


def _occluded(node: Any, stamp: float) -> Any:
    """A stand-in for MHT._occluded_child: a node made and cached on its parent."""
    from laserpeople.tracking.mht.tracktree import TrackNode

    child = TrackNode(100 + node.node_id, node.family, node.node_id, node.mean, node.cov, stamp,
                      "occluded")  # fmt: skip
    node.children[-1] = child
    return child


def test_compiled_plan_and_assembly_by_hand(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The compiled plan (children to make) and assembly (the children's hypotheses)
    against MHT._plan_plain and MHT._assemble on a cluster made by hand: the same pairs
    and births (the same objects, in order), the same children by the same keys, with the
    same tracks (sorted by family where a track was born), histories, models and weights
    (two children of no tracks joined by logaddexp), their hypotheses made in the same
    order."""
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    mht = LegMHTTracker(LegTrackerParams()).mht
    monkeypatch.setattr(mht, "_occluded_child", _occluded)
    monkeypatch.setattr(mht, "_prune_children", lambda children: children)
    measurements = object()
    sol, parents, tracks_of, meas_list, _ = _cluster_by_hand()
    got_plan = clisting.plan_plain(sol, tracks_of, meas_list, measurements)
    want_plan = mht._plan_plain(sol, tracks_of, meas_list, measurements)
    assert got_plan[0] == want_plan[0] and list(got_plan[1].items()) == list(want_plan[1].items())
    assert [(p[0].node_id, p[1]) for p in got_plan[0]] == []  # (every child made already)
    assert list(got_plan[1]) == [5, 3]

    n_scan = mht.params.depth
    want = mht._assemble(sol, parents, tracks_of, [meas_list] * 2, [0] * 2, _cluster_by_hand()[4],
                         1.0, models=False)  # fmt: skip
    sol, parents, tracks_of, meas_list, new_nodes = _cluster_by_hand()
    got = clisting.assemble_plain(sol, parents, tracks_of, meas_list, new_nodes, _occluded, 1.0,
                                  Hypothesis, n_scan, np.logaddexp)  # fmt: skip
    assert list(got) == list(want) == [(101, 21, 10), (21, 20), (), (20, 11), (12, 10)]
    for g, w in zip(got.values(), want.values(), strict=True):
        assert [t.node_id for t in g.tracks] == [t.node_id for t in w.tracks]
        assert g.log_weight == pytest.approx(w.log_weight, rel=0.0, abs=WEIGHT_TOL)
        assert g.ancestors == w.ancestors
        assert g.model == w.model == 0
    empty = got[()]
    assert empty.log_weight == pytest.approx(float(np.logaddexp(-2.5, -3.0)), abs=WEIGHT_TOL)
    ids_got = [h.hypothesis_id for h in got.values()]
    ids_want = [h.hypothesis_id for h in want.values()]
    assert [i - ids_got[0] for i in ids_got] == [i - ids_want[0] for i in ids_want]
    assert got[(101, 21, 10)].tracks[0].family == 2  # (b occluded, born 6, a detected)
    assert [t.family for t in got[(21, 20)].tracks] == [6, 7]
    assert got[(101, 21, 10)].ancestors == (40, 41, 50)[-n_scan:]


def test_compiled_plan_and_assembly_leave_other_solutions_to_python(
    clisting: ModuleType,
) -> None:
    """Solutions that are not the listing's (a parent out of range, labels of the wrong
    length, a detection of no measurement, a tuple where a list is expected) and parents
    whose ancestors are not a tuple: NotImplemented, nothing made."""
    from laserpeople.tracking.mht.matrix import LabelledAssignment

    def La(tlabels: list[int], tmeas: tuple[int, ...], mlabels: list[int]) -> Any:  # noqa: N802
        return LabelledAssignment(tlabels, tmeas, mlabels, 0.0)

    sol, parents, tracks_of, meas_list, new_nodes = _cluster_by_hand()
    bad = [
        [(2, sol[0][1], 1.0)],
        [(0, La([0], (0,), [0, 0]), 1.0)],
        [(0, La([0, 0], (0, 2), [0, 0]), 1.0)],
        [(0, La([1, 1], (-1, -1), [0]), 1.0)],
        [(0, sol[0][1], 1)],
        [[0, sol[0][1], 1.0]],
    ]
    for solutions in bad:
        assert clisting.plan_plain(solutions, tracks_of, meas_list, None) is NotImplemented
        out = clisting.assemble_plain(solutions, parents, tracks_of, meas_list, new_nodes,
                                      _occluded, 1.0, Hypothesis, 3, np.logaddexp)  # fmt: skip
        assert out is NotImplemented
    parents[0].ancestors = [40, 41]  # type: ignore[assignment]
    out = clisting.assemble_plain(sol, parents, tracks_of, meas_list, new_nodes, _occluded,
                                  1.0, Hypothesis, 3, np.logaddexp)  # fmt: skip
    assert out is NotImplemented and -1 not in tracks_of[0][0].children


@pytest.mark.parametrize("compiled", ["pruning", "plan, assembly and pruning"])
def test_tracker_with_the_compiled_bookkeeping_holds_the_same_hypotheses(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch, compiled: str
) -> None:
    """Two leg MHTs stepped side by side over a scene of six walkers with clutter, one
    with the ``compiled`` parts, one with their Python references: after every scan the
    same hypotheses (node ids, histories' lengths; weights within WEIGHT_TOL), the same
    live nodes by family, the same links, the same reported tracks; the compiled part
    counted (the pruning, or the assembly) took every cluster it was offered, over 200."""
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    fast, slow = LegMHTTracker(LegTrackerParams()), LegMHTTracker(LegTrackerParams())
    taken = {"compiled": 0, "python": 0}

    def counted(part: Any) -> Any:
        def call(*args: Any) -> Any:
            out = part(*args)
            taken["python" if out is NotImplemented else "compiled"] += 1
            return out

        return call

    if compiled == "pruning":
        parts = {"COMPILED_PRUNE": counted(clisting.prune)}
    else:
        parts = {
            "COMPILED_PRUNE": clisting.prune,
            "COMPILED_PLAN_PLAIN": clisting.plan_plain,
            "COMPILED_ASSEMBLE_PLAIN": counted(clisting.assemble_plain),
        }

    def state(tracker: LegMHTTracker) -> tuple[Any, ...]:
        hyps = [h for c in tracker.mht.clusters for h in c.hypotheses]
        tree = {f: [n.node_id for n in ns] for f, ns in tracker.mht.tree.nodes_by_family.items()}
        return (
            [[t.node_id for t in h.tracks] for h in hyps],
            [len(h.ancestors) for h in hyps],
            list(tree.items()),
            list(tracker.mht.links.items()),
            [h.log_weight for h in hyps],
        )

    for d in walkers_scene(21, 1.5).detections:
        for name, part in parts.items():
            monkeypatch.setattr(listing, name, part)
        out_fast = fast.update(d)
        for name in parts:
            monkeypatch.setattr(listing, name, None)
        out_slow = slow.update(d)
        _same_state(state(fast), state(slow), d.scan_index)
        _same_tracks(out_fast, out_slow)
    assert taken["compiled"] > 200 and taken["python"] == 0


@pytest.mark.parametrize("plan", ["refused", "planned"])
def test_refused_children_go_to_the_python_code(monkeypatch: pytest.MonkeyPatch, plan: str) -> None:
    """Where the compiled plan, node making, assembly or pruning refuse (NotImplemented),
    the Python code makes the children: a tracker whose compiled parts refuse every call
    (or whose plan is the Python one's and the others refuse) holds the hypotheses and
    reports the tracks of one without them (built or not)."""
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams
    from laserpeople.tracking.mht.core import MHT

    calls = {"plan": 0, "assemble": 0, "prune": 0, "make": 0}

    def part(name: str) -> Any:
        def refuse_or_plan(*args: Any) -> Any:
            calls[name] += 1
            if name == "plan" and plan == "planned":
                return MHT._plan_plain(*args)
            return NotImplemented

        return refuse_or_plan

    names = {"plan": "COMPILED_PLAN_PLAIN", "assemble": "COMPILED_ASSEMBLE_PLAIN",
             "prune": "COMPILED_PRUNE", "make": "COMPILED_MAKE_PLAIN"}  # fmt: skip
    refusing, without = LegMHTTracker(LegTrackerParams()), LegMHTTracker(LegTrackerParams())

    def hypotheses(tracker: LegMHTTracker) -> list[list[int]]:
        return [[t.node_id for t in h.tracks] for c in tracker.mht.clusters for h in c.hypotheses]

    for d in walkers_scene(21, 1.5).detections[:150]:
        for key, name in names.items():
            monkeypatch.setattr(listing, name, part(key))
        out_refusing = refusing.update(d)
        for name in names.values():
            monkeypatch.setattr(listing, name, None)
        out_without = without.update(d)
        assert hypotheses(refusing) == hypotheses(without)
        _same_tracks(out_refusing, out_without)
    assert calls["plan"] > 50 and calls["prune"] > 50 and calls["make"] > 50
    # (a refused plan leaves the assembly to Python without asking the compiled one)
    assert (calls["assemble"] > 50) == (plan == "planned") == (calls["assemble"] > 0)


def test_compiled_node_making_is_the_pythons(
    clisting: ModuleType, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Two leg MHTs stepped side by side over a scene of six walkers with clutter, one
    making its general path's detected children and new tracks by the compiled
    ``make_plain``, one by ``MHT._make_detected_children`` and ``MHT._new_nodes``: after
    every scan the same live nodes, every field the same (ids, families, parents,
    measurements, hits, misses, ages, stamps, labels, log-likelihoods to the bit: one
    float read from the same table), the same hypotheses and the same reported tracks;
    the compiled one took every call, over 200."""
    from laserpeople.tracking.legs import LegMHTTracker, LegTrackerParams

    fast, slow = LegMHTTracker(LegTrackerParams()), LegMHTTracker(LegTrackerParams())
    calls = {"compiled": 0, "python": 0}

    def counted(*args: Any) -> Any:
        out = clisting.make_plain(*args)
        calls["python" if out is NotImplemented else "compiled"] += 1
        return out

    fields = ("node_id", "family", "parent_id", "measurement", "hits", "misses", "age",
              "stamp", "detected_stamp", "label", "loglik")  # fmt: skip

    def nodes(tracker: LegMHTTracker) -> list[Any]:
        return [
            (tuple(getattr(n, f) for f in fields), n.mean.tobytes(), n.cov.tobytes())
            for ns in tracker.mht.tree.nodes_by_family.values()
            for n in ns
        ]

    for d in walkers_scene(21, 1.5).detections:
        monkeypatch.setattr(listing, "COMPILED_MAKE_PLAIN", counted)
        out_fast = fast.update(d)
        monkeypatch.setattr(listing, "COMPILED_MAKE_PLAIN", None)
        out_slow = slow.update(d)
        assert nodes(fast) == nodes(slow), d.scan_index
        hyps = [[[t.node_id for t in h.tracks] for h in c.hypotheses] for c in fast.mht.clusters]
        assert hyps == [[[t.node_id for t in h.tracks] for h in c.hypotheses]
                        for c in slow.mht.clusters]  # fmt: skip
        _same_tracks(out_fast, out_slow)
    assert calls["compiled"] > 200 and calls["python"] == 0


def test_compiled_node_making_leaves_other_input_to_python(clisting: ModuleType) -> None:
    """``make_plain`` by hand: the detected child of each pair (its fields from its parent,
    its log-likelihood from the table's row of the parent and column of the measurement,
    stored among the parent's children and listed with it) and the new tracks in the order
    of their measurements (ids after the children's, families from the counter); input the
    Python code takes (a node not scored this scan, a measurement outside the table or not
    an int, a table not of float64, a birth not keyed by its measurement) returns
    NotImplemented with nothing made."""
    import itertools

    from laserpeople.tracking.mht.tracktree import TrackNode

    deferred = np.full(0, np.nan)
    loglik = np.array([[-1.0, -2.0, -3.0], [-4.0, -5.0, -6.0]])
    parent = TrackNode(7, 3, 1, np.zeros(4), np.eye(4), 0.5, "detected", 0, 4, 0, 9)
    other = TrackNode(8, 5, 2, np.zeros(4), np.eye(4), 0.5, "occluded", -1, 2, 1, 3)
    ids, fams = itertools.count(100), itertools.count(40)

    def call(pairs: Any, born: Any, table: Any = loglik, rows: Any = None) -> Any:
        made: list[Any] = []
        births: list[Any] = []
        rows = {7: 1, 8: 0} if rows is None else rows
        out = clisting.make_plain(pairs, born, table, rows, TrackNode, ids.__next__,
                                  fams.__next__, 1.5, deferred, "detected", "new", made,
                                  births)  # fmt: skip
        return out, made, births

    m = object()  # (the measurement set: passed through, never read)
    out, made, births = call([(parent, 2, m, 2), (other, 0, m, 0)], {1: (m, 1, 1), 0: (m, 0, 0)})
    child, child2 = parent.children[2], other.children[0]
    assert [(c.node_id, c.family, c.parent_id, c.measurement, c.hits, c.misses, c.age, c.loglik)
            for c in (child, child2)] == [(100, 3, 7, 2, 5, 0, 10, -6.0),
                                          (101, 5, 8, 0, 3, 0, 4, -1.0)]  # fmt: skip
    assert child.stamp == child.detected_stamp == 1.5 and child.label == "detected"
    assert child.mean is deferred and child.payload is None
    assert made == [(child, parent, 2), (child2, other, 0)]
    assert list(out) == [0, 1] and [(n.node_id, n.family) for n in out.values()] == [
        (102, 40),
        (103, 41),
    ]
    assert out[0].label == "new" and out[0].parent_id == -1 and out[0].measurement == 0
    assert births == [(out[0], 0), (out[1], 1)]
    for pairs, born, table, rows in (
        ([(parent, 1, m, 1)], {}, loglik, {8: 0}),  # the parent not scored
        ([(parent, 1, m, 3)], {}, loglik, None),  # beyond the table
        ([(parent, 1, m, -1)], {}, loglik, None),  # (numpy's last column: Python's)
        ([(parent, 1, m, 1.0)], {}, loglik, None),
        ([(parent, 1, m, 1)], {}, loglik.astype(np.float32), None),
        ([(parent, 1, m, 1)], {0: (m, 1, 1)}, loglik, None),  # birth keyed otherwise
    ):
        before = dict(parent.children)
        out, made, births = call(pairs, born, table, rows)
        assert out is NotImplemented and made == births == [] and parent.children == before
    assert next(ids) == 104 and next(fams) == 42  # (no id taken by a refused call)
