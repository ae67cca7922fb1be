"""The leg MHT of 000 Sec. 3 (eqs. 2-15, Table 10) and its people from leg pairs (Sec.
3.3), through the code the leg tracker runs, against a computation written out here.

The MHT's hypothesis probabilities after a scan are compared with eq. 15 enumerated
literally: every parent hypothesis, every labelling of its tracks (detected by one gated
measurement, occluded, deleted) and of the measurements left (new track, false alarm),
weighted by p(parent) * prod N(z_i) * prod p_label|class * lambda_new^N_new *
lambda_fal^N_fal and normalised (eta''). N(z) is computed here from a constant-velocity
Kalman filter written out (x = (x, y, vx, vy), new tracks with v = 0, white-acceleration
noise). Children that leave the same tracks (a deleted track and a false alarm, say, from
either parent) are one state of the world: their probabilities add.

The label probabilities are Table 10's for free tracks and, for the legs of a validated
person (*approved*, eqs. 9-10), the approved column: the tests tell the two apart, and tell
occluded from deleted and lambda_new from lambda_fal.

The person layer (000 Sec. 3.3, policy ``arras``): S = sum_t <theta_i^t, theta_j^t> over a
window of L steps, a person's state the covariance-weighted mean of its legs, deletion
after L consecutive steps with the legs farther apart than theta_d. The orientation
theta is the direction of the leg's displacement over ``orientation_span`` (not 000's
velocity direction, see docs/papers.md); on the straight walks here both are the same.
"""

from __future__ import annotations

import itertools
import math
from collections import defaultdict
from collections.abc import Sequence

import numpy as np
import pytest

from laserpeople.tracking.kalman import KalmanParams
from laserpeople.tracking.legs import LegLabelModel, LegTrackerParams
from laserpeople.tracking.mht.core import MHT, MHTParams
from laserpeople.tracking.people import LegState, PersonFuser, PersonParams
from laserpeople.tracking.point_model import KalmanPointModel, PointMeasurements

STD = 0.03
"""Measurement standard deviation [m] of the detections here."""
KP = KalmanParams(init_velocity_std=0.7, accel_psd=20.0)
"""A motion model of other values than the defaults (1 m/s, 32 m^2/s^3), so that a
standard deviation taken for a variance is seen."""
FREE = (0.3, 0.63, 0.07)
APPROVED = (0.2, 0.79, 0.01)
LAMBDA_NEW, LAMBDA_FAL = 0.001, 0.003
UNPRUNED = MHTParams(min_ratio=0.0, k_best=1000, n_scan=20, existence_ratio=0.0)


def _meas(points: Sequence[tuple[float, float]]) -> PointMeasurements:
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    return PointMeasurements(p, np.tile(np.eye(2) * STD**2, (len(p), 1, 1)))


def _params(**kw: object) -> LegTrackerParams:
    return LegTrackerParams(kalman=KP, **kw)  # type: ignore[arg-type]


def _mht(params: LegTrackerParams) -> tuple[MHT[PointMeasurements], LegLabelModel]:
    labels = LegLabelModel(params)
    return MHT(UNPRUNED, KalmanPointModel(params.kalman), labels), labels


def _loglik_new_track(z0: np.ndarray, z: np.ndarray, dt: float) -> float:
    """log N(z; z_hat, S) of a track born at z0 (v = 0) one step of dt later: P_0 =
    diag(R, sigma_v^2 I), P = F P_0 F^T + Q (white acceleration), S = H P H^T + R."""
    r = STD**2
    q = KP.accel_psd
    var = r + dt * dt * KP.init_velocity_std**2 + q * dt**3 / 3.0  # per axis, no x-y term
    s = var + r
    d = z - z0
    return float(-0.5 * (d @ d) / s - math.log(2.0 * math.pi * s))


def _enumerate(
    parents: Sequence[tuple[float, dict[int, tuple[np.ndarray, str]]]],
    z: np.ndarray,
    dt: float,
    probs: dict[str, tuple[float, float, float]],
) -> dict[frozenset[tuple[object, str]], float]:
    """000 eq. 15 for every child of every parent, normalised; children keyed by what
    they leave: (family, "detected"/"occluded") of the tracks kept and ("new", j) of the
    new tracks. ``parents``: (probability, {family: (birth position, class)}) with every
    track born one step of ``dt`` before."""
    out: dict[frozenset[tuple[object, str]], float] = defaultdict(float)
    m = len(z)
    for p_parent, tracks in parents:
        fams = sorted(tracks)
        options = [[("d", j) for j in range(m)] + [("o", -1), ("x", -1)] for _ in fams]
        for combo in itertools.product(*options):
            used = [j for kind, j in combo if kind == "d"]
            if len(used) != len(set(used)):
                continue
            w = p_parent
            kept: list[tuple[object, str]] = []
            for fam, (kind, j) in zip(fams, combo, strict=True):
                z0, cls = tracks[fam]
                p_det, p_occ, p_del = probs[cls]
                if kind == "d":
                    w *= p_det * math.exp(_loglik_new_track(z0, z[j], dt))
                    kept.append((fam, "detected"))
                elif kind == "o":
                    w *= p_occ
                    kept.append((fam, "occluded"))
                else:
                    w *= p_del
            rest = [j for j in range(m) if j not in used]
            for labels in itertools.product(("new", "fal"), repeat=len(rest)):
                v = w
                news = []
                for j, lab in zip(rest, labels, strict=True):
                    v *= LAMBDA_NEW if lab == "new" else LAMBDA_FAL
                    if lab == "new":
                        news.append(("new", str(j)))
                out[frozenset(kept + news)] += v
    total = sum(out.values())
    return {k: v / total for k, v in out.items()}


def _mht_children(
    mht: MHT[PointMeasurements], born: set[int]
) -> dict[frozenset[tuple[object, str]], float]:
    """The MHT's hypotheses after the step, keyed as :func:`_enumerate` keys them (the
    families in ``born`` existed before the step)."""
    out: dict[frozenset[tuple[object, str]], float] = defaultdict(float)
    for cluster in mht.clusters:
        for h in cluster.hypotheses:
            key = frozenset(
                (t.family, t.label) if t.family in born else ("new", str(t.measurement))
                for t in h.tracks
            )
            out[key] += math.exp(h.log_weight)
    return dict(out)


def _compare(got: dict, want: dict) -> None:
    assert set(got) == set(want)
    for key, p in want.items():
        assert got[key] == pytest.approx(p, rel=1e-9, abs=1e-15), key


def _one_track_then_one_measurement(
    params: LegTrackerParams, approved: bool
) -> tuple[dict, dict[str, object], np.ndarray]:
    """The children after a scan of one measurement at (1, 0) and one at (1.02, 0.01)
    0.1 s later, with the track born in the first scan approved or not; the track's
    family and birth position (``fam``, ``z0``); the second scan's measurement (1, 2)."""
    mht, labels = _mht(params)
    z0 = np.array([1.0, 0.0])
    mht.step(_meas([tuple(z0)]), 0.0)
    # first scan: a new track (lambda_new) or a false alarm (lambda_fal): 1/4, 3/4
    (fam,) = {t.family for c in mht.clusters for h in c.hypotheses for t in h.tracks}
    first = _mht_children(mht, set())
    assert first[frozenset({("new", "0")})] == pytest.approx(0.25, rel=1e-12)
    assert first[frozenset()] == pytest.approx(0.75, rel=1e-12)
    labels.approved = frozenset({fam}) if approved else frozenset()
    z = np.array([[1.02, 0.01]])
    mht.step(_meas([tuple(z[0])]), 0.1)
    got = _mht_children(mht, {fam})
    return got, {"fam": fam, "z0": z0}, z


def _table10(params: LegTrackerParams) -> dict[str, tuple[float, float, float]]:
    return {
        "free": (params.p_det_free, params.p_occ_free, params.p_del_free),
        "approved": (params.p_det_approved, params.p_occ_approved, params.p_del_approved),
    }


@pytest.mark.parametrize("cls", ["free", "approved"])
def test_eq15_one_track_one_measurement_by_class(cls: str) -> None:
    """Children of {track} (1/4) and {} (3/4): detected p_det N, occluded or deleted with
    the measurement new or a false alarm; the approved class uses Table 10's A column."""
    params = _params()
    got, info, z = _one_track_then_one_measurement(params, cls == "approved")
    fam, z0 = info["fam"], info["z0"]
    want = _enumerate([(0.25, {fam: (z0, cls)}), (0.75, {})], z, 0.1, _table10(params))
    _compare(got, want)
    # the values tell the classes, occluded from deleted and new from false alarm apart
    other = "free" if cls == "approved" else "approved"
    miss = _enumerate([(0.25, {fam: (z0, other)}), (0.75, {})], z, 0.1, _table10(params))
    assert max(abs(miss[k] - want[k]) / want[k] for k in want) > 0.1
    occluded = frozenset({(fam, "occluded")})
    occluded_new = frozenset({(fam, "occluded"), ("new", "0")})
    assert want[occluded] / want[occluded_new] == pytest.approx(LAMBDA_FAL / LAMBDA_NEW)


def test_eq15_by_hand_free_track() -> None:
    """The same, by hand: S = 0.0009 + 0.01 + 32 * 0.001 / 3 + 0.0009 per axis; the
    detected child 0.25 * 0.3 * N, the empty one 0.25 * 0.07 * 0.003 + 0.75 * 0.003."""
    got, info, _ = _one_track_then_one_measurement(LegTrackerParams(), False)
    fam = info["fam"]
    s = 0.0009 + 0.01 + 32.0 * 0.001 / 3.0 + 0.0009
    n = math.exp(-0.5 * (0.02**2 + 0.01**2) / s) / (2.0 * math.pi * s)
    w = {
        frozenset({(fam, "detected")}): 0.25 * 0.3 * n,
        frozenset(): 0.25 * 0.07 * 0.003 + 0.75 * 0.003,
        frozenset({("new", "0")}): 0.25 * 0.07 * 0.001 + 0.75 * 0.001,
        frozenset({(fam, "occluded")}): 0.25 * 0.63 * 0.003,
        frozenset({(fam, "occluded"), ("new", "0")}): 0.25 * 0.63 * 0.001,
    }
    total = sum(w.values())
    _compare(got, {k: v / total for k, v in w.items()})


def test_eq15_two_tracks_one_approved_one_free_share_a_measurement() -> None:
    """Two legs 0.3 m apart, one of a validated person (approved), then one measurement
    between them that both gate: every labelling of both tracks (eq. 15 with the product
    of eqs. 9-10's two classes)."""
    params = _params()
    mht, labels = _mht(params)
    a0, b0 = np.array([1.0, 0.0]), np.array([1.0, 0.3])
    mht.step(_meas([tuple(a0), tuple(b0)]), 0.0)
    fam_of = {}
    for c in mht.clusters:
        for h in c.hypotheses:
            for t in h.tracks:
                fam_of[t.measurement] = t.family
    fa, fb = fam_of[0], fam_of[1]
    labels.approved = frozenset({fa})
    z = np.array([[1.03, 0.12]])
    mht.step(_meas([tuple(z[0])]), 0.1)
    got = _mht_children(mht, {fa, fb})
    # the first scan's four hypotheses: each measurement new (1/4) or a false alarm (3/4)
    parents = []
    for a_new, b_new in itertools.product((True, False), repeat=2):
        tracks = {}
        if a_new:
            tracks[fa] = (a0, "approved")
        if b_new:
            tracks[fb] = (b0, "free")
        parents.append(((0.25 if a_new else 0.75) * (0.25 if b_new else 0.75), tracks))
    _compare(got, _enumerate(parents, z, 0.1, _table10(params)))


@pytest.mark.parametrize("fixed", ["free", "approved"])
def test_nonadaptive_uses_one_class_for_every_track(fixed: str) -> None:
    """000 Sec. 3.4's non-adaptive comparison: one column for every track, approved or not."""
    params = _params(adaptive=False, nonadaptive_class=fixed)
    got, info, z = _one_track_then_one_measurement(params, True)
    fam, z0 = info["fam"], info["z0"]
    want = _enumerate([(0.25, {fam: (z0, fixed)}), (0.75, {})], z, 0.1, _table10(params))
    _compare(got, want)


# ---------------------------------------------------------------- people (000 Sec. 3.3)

DT = 0.125
"""Scan period [s] of the walks here (exact in binary: the stamps are exact)."""


def _leg(
    i: int, pos: Sequence[float], vel: Sequence[float], cov: np.ndarray | None = None
) -> LegState:
    c = np.diag([0.01, 0.01, 0.1, 0.1]) if cov is None else cov
    return LegState(i, np.array([*pos, *vel], dtype=np.float64), c)


def _heading(deg: float) -> np.ndarray:
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


@pytest.mark.parametrize("angle", [0.0, 60.0, 120.0])
def test_agreement_is_the_sum_of_cosines_over_the_window(angle: float) -> None:
    """Leg a walks along +x, leg b at ``angle`` to it, both at 1 m/s. The orientation
    exists from the third step (displacement over at least ``min_orientation_age`` 0.2 s);
    after 15 steps the window of L = 10 steps holds 10 of them: S = 10 cos(angle)
    (10, 5, -5), not its absolute value, not 11 or 13 terms."""
    fuser = PersonFuser(PersonParams(window=10, validate_still=False))
    va, vb = _heading(0.0), _heading(angle)
    start_b = np.array([0.0, 0.3])
    for k in range(15):
        t = k * DT
        fuser.update(
            {0: _leg(0, va * t, va), 1: _leg(1, start_b + vb * t, vb)},
            t,
        )
    assert fuser.agreement(0, 1) == pytest.approx(10.0 * math.cos(math.radians(angle)), abs=1e-9)


def _walk_together(fuser: PersonFuser, steps: int, gap: float) -> list:
    out = []
    v = np.array([1.0, 0.0])
    for k in range(steps):
        t = k * DT
        out.append(fuser.update({0: _leg(0, v * t, v), 1: _leg(1, v * t + [0.0, gap], v)}, t))
    return out


def test_person_is_validated_once_s_exceeds_theta_a() -> None:
    """Two legs 0.2 m apart walking alike: each step with both orientations adds exactly 1
    to S (orientations from the third step); S > theta_a = 2 first holds at its third
    term, the fifth step (S = 2 at the fourth does not validate: the inequality is strict)."""
    fuser = PersonFuser(PersonParams(window=6, min_agreement=2.0, validate_still=False))
    out = _walk_together(fuser, 6, 0.2)
    persons = [len([t for t in tracks if t.kind == "person"]) for tracks in out]
    assert persons == [0, 0, 0, 0, 1, 1]


def test_person_is_the_covariance_weighted_mean_of_its_legs() -> None:
    """x = P (P_a^-1 x_a + P_b^-1 x_b), P = (P_a^-1 + P_b^-1)^-1 (000 Sec. 3.3, 1.), for
    legs of unequal, correlated covariances (not their midpoint)."""
    fuser = PersonFuser(PersonParams(window=4, min_agreement=1.5, validate_still=False))
    _walk_together(fuser, 5, 0.2)
    t = 5 * DT
    pa = np.array(
        [
            [0.010, 0.004, 0.0, 0.0],
            [0.004, 0.020, 0.0, 0.0],
            [0.0, 0.0, 0.2, 0.05],
            [0.0, 0.0, 0.05, 0.1],
        ]
    )
    pb = np.diag([0.04, 0.005, 0.05, 0.3])
    xa = np.array([t, 0.0, 1.0, 0.0])
    xb = np.array([t + 0.05, 0.2, 0.9, 0.1])
    tracks = fuser.update({0: LegState(0, xa, pa), 1: LegState(1, xb, pb)}, t)
    (person,) = [tr for tr in tracks if tr.kind == "person"]
    ia, ib = np.linalg.inv(pa), np.linalg.inv(pb)
    p = np.linalg.inv(ia + ib)
    x = p @ (ia @ xa + ib @ xb)
    assert np.abs(x[:2] - 0.5 * (xa[:2] + xb[:2])).max() > 0.01  # not the midpoint
    np.testing.assert_allclose(person.position, x[:2], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(person.velocity, x[2:], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(person.covariance, p[:2, :2], rtol=1e-9, atol=1e-15)


def test_person_deleted_after_l_consecutive_steps_apart() -> None:
    """After validation, leg b steps to 1.0 m from leg a (> theta_d = 0.75): the person is
    kept for L - 1 such steps and deleted at the L-th (L = 4); a step back within theta_d
    resets the count."""
    params = PersonParams(window=4, min_agreement=1.5, validate_still=False, relink_time=0.0)
    fuser = PersonFuser(params)
    out = _walk_together(fuser, 5, 0.2)
    assert any(t.kind == "person" for t in out[-1])
    v = np.array([1.0, 0.0])
    gaps = [1.0, 1.0, 1.0, 0.2, 1.0, 1.0, 1.0, 1.0]
    alive = []
    for i, gap in enumerate(gaps):
        t = (5 + i) * DT
        tracks = fuser.update({0: _leg(0, v * t, v), 1: _leg(1, v * t + [0.0, gap], v)}, t)
        alive.append(any(tr.kind == "person" for tr in tracks))
    assert alive == [True, True, True, True, True, True, True, False]


@pytest.mark.parametrize(("gap", "person"), [(0.7, True), (0.8, False)])
def test_person_candidate_needs_legs_within_theta_d(gap: float, person: bool) -> None:
    """Condition 2: legs closer than theta_d = 0.75 m form a candidate. Two legs walking one
    behind the other (no spread across the walking direction) agree in orientation at
    any distance; only theta_d tells 0.7 m from 0.8 m."""
    fuser = PersonFuser(PersonParams(window=4, min_agreement=1.5, validate_still=False))
    v = np.array([1.0, 0.0])
    found = False
    for k in range(10):
        t = k * DT
        tracks = fuser.update({0: _leg(0, v * t, v), 1: _leg(1, v * t + [gap, 0.0], v)}, t)
        found = found or any(tr.kind == "person" for tr in tracks)
    assert found is person
