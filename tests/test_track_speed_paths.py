"""The faster code paths of the leg MHT (session 7) give bit-identical results to the
straightforward code they replace, on random inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

# two code paths giving the same bits may hold on one CPU only: CI runs these again on
# another CPU path (.ci/run)
pytestmark = pytest.mark.regression


def _transition_ref(dt: np.ndarray) -> np.ndarray:
    f = np.broadcast_to(np.eye(4), (dt.size, 4, 4)).copy()
    f[:, 0, 2] = dt
    f[:, 1, 3] = dt
    return f


def _process_noise_ref(dt: np.ndarray, q: float) -> np.ndarray:
    out = np.zeros((dt.size, 4, 4))
    pp, pv, vv = q * dt**3 / 3.0, q * dt**2 / 2.0, q * dt
    for i in (0, 1):
        out[:, i, i] = pp
        out[:, i, i + 2] = pv
        out[:, i + 2, i] = pv
        out[:, i + 2, i + 2] = vv
    return out


def _random_states(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    means = rng.normal(size=(n, 4))
    a = rng.normal(size=(n, 4, 4))
    return means, a @ a.transpose(0, 2, 1) + 0.1 * np.eye(4)


def test_transition_and_process_noise_are_the_textbook_matrices() -> None:
    """F = [[I, dt I], [0, I]] and the white-acceleration Q, element by element as written
    out (Bar-Shalom & Li), bit for bit, for random steps."""
    from laserpeople.tracking import kalman

    rng = np.random.default_rng(7)
    for n in (0, 1, 5, 40):
        dt = rng.uniform(0.0, 0.5, size=n)
        assert np.array_equal(kalman.transition(dt), _transition_ref(dt))
        assert np.array_equal(kalman.process_noise(dt, 32.0), _process_noise_ref(dt, 32.0))
    f = kalman.transition(np.array([0.1]))[0]
    assert f[0, 2] == f[1, 3] == 0.1 and np.trace(f) == 4.0 and np.count_nonzero(f) == 6


def test_predict_and_coast_equal_predict_and_coast_apart() -> None:
    """The shared-noise batch gives the same arrays as the two calls (and as the
    predict written with the reference matrices), for finite and infinite tau."""
    from laserpeople.tracking import kalman

    rng = np.random.default_rng(8)
    for n in (1, 3, 30):
        means, covs = _random_states(rng, n)
        dt = rng.uniform(0.0, 0.3, size=n)
        for tau in (0.5, 2.0, math.inf):
            pm, pc, cm, cc = kalman.predict_and_coast(means, covs, dt, 16.0, tau)
            em, ec = kalman.predict(means, covs, dt, 16.0)
            fm, fc = kalman.coast(means, covs, dt, 16.0, tau)
            assert np.array_equal(pm, em) and np.array_equal(pc, ec)
            assert np.array_equal(cm, fm) and np.array_equal(cc, fc)
        f = _transition_ref(dt)
        ref = f @ covs @ f.transpose(0, 2, 1) + _process_noise_ref(dt, 16.0)
        # (within 1e-12: the compiled steps' fused products against numpy's, which another
        # CPU's OpenBLAS rounds otherwise)
        np.testing.assert_allclose(kalman.predict(means, covs, dt, 16.0)[1], ref, rtol=1e-12)


def test_update_batch_is_the_joseph_form_of_each_state() -> None:
    """The batch update against the one-state Joseph form (independent code path)."""
    from laserpeople.tracking import kalman

    rng = np.random.default_rng(9)
    means, covs = _random_states(rng, 12)
    z = rng.normal(size=(12, 2))
    r = np.broadcast_to(np.diag([0.01, 0.02]), (12, 2, 2)).copy()
    bm, bc = kalman.update_batch(means, covs, z, r)
    for i in range(12):
        m1, c1 = kalman.update(means[i], covs[i], z[i], r[i])
        np.testing.assert_allclose(bm[i], m1, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(bc[i], c1, rtol=1e-12, atol=1e-12)


def _prune_ref(hyps: list, depth: int, ratio: float) -> list:
    from laserpeople.tracking.mht.hypothesis import (
        n_scan_prune,
        normalise_hypotheses,
        ratio_prune,
    )

    return ratio_prune(n_scan_prune(normalise_hypotheses(hyps), depth), ratio)


def _random_children(rng: np.random.Generator, depth: int, ties: bool) -> list:
    from laserpeople.tracking.mht.hypothesis import Hypothesis

    n = int(rng.integers(1, 25))
    if ties:
        weights = rng.choice([-1.0, -2.0, -3.5, -np.inf], size=n, p=[0.4, 0.3, 0.2, 0.1])
    else:
        weights = rng.normal(-3.0, 3.0, size=n)
    out = []
    for i, w in enumerate(weights.tolist()):
        length = depth if rng.random() < 0.9 else int(rng.integers(0, max(depth, 1)))
        ancestors = tuple(int(rng.integers(0, 3)) for _ in range(length))
        out.append(Hypothesis(w, (), ancestors, hypothesis_id=i))
    return out


def test_prune_children_equals_normalise_n_scan_and_ratio_pruning() -> None:
    """The fused pruning against the three steps on random children (equal weights,
    -inf weights, all -inf, short histories, one or several ancestor groups, depth 0):
    the same hypotheses in the same order with the same log weights as exact floats."""
    import copy

    from laserpeople.tracking.mht.hypothesis import Hypothesis, prune_children

    rng = np.random.default_rng(11)
    groups = set()
    for trial in range(4000):
        depth = int(rng.choice([0, 1, 2, 3, 8]))
        ratio = float(rng.choice([0.0, 1e-3, 0.1, 0.5]))
        hyps = _random_children(rng, depth, ties=trial % 2 == 1)
        if trial % 97 == 0:
            for h in hyps:
                h.log_weight = -math.inf
        ref = _prune_ref(copy.deepcopy(hyps), depth, ratio)
        got = prune_children(hyps, depth, ratio)
        assert [h.hypothesis_id for h in got] == [h.hypothesis_id for h in ref], trial
        for a, b in zip(got, ref, strict=True):
            assert a.log_weight == b.log_weight or (
                math.isnan(a.log_weight) and math.isnan(b.log_weight)
            ), trial
        if depth and all(len(h.ancestors) >= depth for h in hyps):
            groups.add(len({h.ancestors[-depth] for h in hyps}) > 1)
    assert groups == {False, True}  # both N-scan cases were met
    assert prune_children([], 3, 1e-3) == []
    assert prune_children([Hypothesis(-2.0, ())], 3, 1e-3)[0].log_weight == 0.0


def _components_ref(
    fam_meas: dict[int, set[int]], links: list[tuple[int, int]], n_meas: int
) -> list[tuple[frozenset[int], list[int]]]:
    """Components by flood fill (not union-find), ordered as documented."""
    adj: dict[object, set[object]] = {f: set() for f in fam_meas}
    for j in range(n_meas):
        adj[("m", j)] = set()
    for a, b in links:
        adj[a].add(b)
        adj[b].add(a)
    for f, js in fam_meas.items():
        for j in js:
            adj[f].add(("m", j))
            adj[("m", j)].add(f)
    seen: set[object] = set()
    out = []
    for start in [*fam_meas, *[("m", j) for j in range(n_meas)]]:
        if start in seen:
            continue
        stack, comp = [start], []
        seen.add(start)
        while stack:
            x = stack.pop()
            comp.append(x)
            for y in adj[x]:
                if y not in seen:
                    seen.add(y)
                    stack.append(y)
        fams = frozenset(x for x in comp if isinstance(x, int))
        meas = sorted(x[1] for x in comp if isinstance(x, tuple))
        out.append((fams, meas))
    return out


def test_components_against_a_flood_fill() -> None:
    """Clusters of families and measurements (gates and links) on random graphs: same
    components, same order, as a flood fill."""
    from laserpeople.tracking.mht.core import components

    rng = np.random.default_rng(12)
    for _ in range(2000):
        fams = [int(f) for f in rng.choice(60, size=int(rng.integers(0, 12)), replace=False)]
        n_meas = int(rng.integers(0, 10))
        fam_meas = {
            f: {j for j in range(n_meas) if rng.random() < 0.15}
            for f in rng.permutation(fams).tolist()
        }
        links = [(int(a), int(b)) for a in fams for b in fams if a < b and rng.random() < 0.05]
        assert components(fam_meas, links, n_meas) == _components_ref(fam_meas, links, n_meas)
