"""The AdaBoost of 000 Table 1 with decision stumps (000 eq. 1), in numpy.

Follows scikit-learn conventions: ``fit(X, y)``, ``predict(X)``, ``decision_function(X)``,
learned state in attributes ending with ``_``. Labels are +1 (leg) and -1 (not a leg);
``fit`` also accepts {0, 1} or booleans.

A weak classifier on feature ``j`` with threshold ``theta`` and polarity ``p`` is
``h(x) = +1 if p * x_j < p * theta else -1`` (000 eq. 1). Training sorts every feature once;
in each round the weighted-label cumulative sum over that order gives ``r`` (000 Table 1,
step 3) for every threshold of every feature at once, and because flipping the polarity
negates ``r`` the best stump is the one of largest ``|r|``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from laserpeople.detection import compiled

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

_extension = compiled.EXTENSION
"""The C extension whose ``stump_sums`` is :meth:`_StumpTables.evaluate` (the same floats),
or None: the Python one runs (:mod:`~laserpeople.detection.compiled`)."""

R_CLIP = 1.0 - 1e-10
"""A perfect stump (r = 1) would get an infinite weight; r is clipped to this."""
TIE_TOLERANCE = 1e-12
"""Stumps whose r differ by less than this are ties."""


@dataclass(frozen=True)
class Stump:
    """One weak classifier h_t with its weight alpha_t (feature index is 0-based)."""

    feature: int
    threshold: float
    polarity: int
    alpha: float
    r: float


class AdaBoostLegClassifier:
    """Boosted decision stumps as in 000 Table 1.

    Args:
        n_rounds: Number of rounds T (000 Sec. 2.3 found T = 10 the best trade-off).

    Learned attributes:
        features_: Feature index (T',) of each stump (0-based column of X).
        thresholds_: Thresholds theta_t (T',).
        polarities_: Polarities p_t in {+1, -1} (T',).
        alphas_: Weights alpha_t (T',).
        r_: The weighted correlation r_t of each chosen stump (T',).
        n_features_in_: Number of columns of X.
        classes_: ``array([-1, 1])``.

    T' < T when a round finds no stump better than chance (r = 0) or a perfect one.
    """

    def __init__(self, n_rounds: int = 10) -> None:
        self.n_rounds = n_rounds

    # ------------------------------------------------------------------ training
    def fit(
        self, X: ArrayLike, y: ArrayLike, sample_weight: ArrayLike | None = None
    ) -> AdaBoostLegClassifier:
        """Train on examples X (N, F) with labels y (N,) in {+1, -1} (or {1, 0}).

        The initial weights are 1/(2a) for the a positives and 1/(2b) for the b negatives
        (000 Table 1); ``sample_weight`` multiplies them when given.
        """
        X = _as_matrix(X)
        labels = _as_labels(y, X.shape[0])
        if self.n_rounds < 1:
            raise ValueError(f"n_rounds must be at least 1, got {self.n_rounds}")
        pos = labels > 0
        a, b = int(pos.sum()), int((~pos).sum())
        if a == 0 or b == 0:
            raise ValueError(f"need positive and negative examples, got {a} and {b}")
        weights = np.where(pos, 1.0 / (2.0 * a), 1.0 / (2.0 * b))
        if sample_weight is not None:
            weights = weights * np.asarray(sample_weight, dtype=np.float64).reshape(-1)

        order = np.argsort(X, axis=0, kind="stable")  # (N, F), sorted once
        xs = np.take_along_axis(X, order, axis=0)
        # A split before sorted position k (1..N-1) is possible only between distinct values;
        # k = 0 and k = N are the constant classifiers.
        n = X.shape[0]
        splittable = np.ones((n + 1, X.shape[1]), dtype=bool)
        splittable[1:-1] = xs[1:] > xs[:-1]
        below = np.vstack([xs[:1] - 1.0, xs])  # value just below split k
        above = np.vstack([xs, xs[-1:] + 1.0])  # value just above split k
        thresholds = np.where(
            np.arange(n + 1)[:, None] == 0,
            xs[:1] - 1.0,
            np.where(np.arange(n + 1)[:, None] == n, xs[-1:] + 1.0, 0.5 * (below + above)),
        )

        chosen: list[Stump] = []
        for _ in range(self.n_rounds):
            weights = weights / weights.sum()
            wl = weights * labels
            cum = np.zeros((n + 1, X.shape[1]))
            np.cumsum(wl[order], axis=0, out=cum[1:])
            r_plus = 2.0 * cum - wl.sum()  # r of polarity +1 (h = +1 below theta)
            score = np.where(splittable, np.abs(r_plus), -1.0).T  # (F, N + 1)
            # ties (within round-off) go to the lowest feature, then the lowest threshold
            best = int(np.argmax(score >= score.max() - TIE_TOLERANCE))
            j, k = np.unravel_index(best, score.shape)
            r = float(abs(r_plus[k, j]))
            if r <= 0.0:
                break
            polarity = 1 if r_plus[k, j] >= 0.0 else -1
            r_c = min(r, R_CLIP)
            alpha = 0.5 * float(np.log((1.0 + r_c) / (1.0 - r_c)))
            stump = Stump(int(j), float(thresholds[k, j]), polarity, alpha, r)
            chosen.append(stump)
            h = _stump_output(X[:, stump.feature], stump.threshold, stump.polarity)
            weights = weights * np.exp(-alpha * labels * h)
            if r >= R_CLIP:
                break
        self._set_stumps(chosen, X.shape[1])
        return self

    def _set_stumps(self, stumps: list[Stump], n_features: int) -> None:
        self.features_ = np.array([s.feature for s in stumps], dtype=np.int64)
        self.thresholds_ = np.array([s.threshold for s in stumps], dtype=np.float64)
        self.polarities_ = np.array([s.polarity for s in stumps], dtype=np.int64)
        self.alphas_ = np.array([s.alpha for s in stumps], dtype=np.float64)
        self.r_ = np.array([s.r for s in stumps], dtype=np.float64)
        self.n_features_in_ = n_features
        self.classes_ = np.array([-1, 1], dtype=np.int64)
        self._tables = _stump_tables(
            self.features_, self.thresholds_, self.polarities_, self.alphas_
        )
        self._bound_tables: dict[tuple[int, ...], _StumpTables] = {}

    @classmethod
    def from_stumps(cls, stumps: list[Stump], n_features: int) -> AdaBoostLegClassifier:
        """A fitted classifier from given stumps (used when loading a model file)."""
        clf = cls(n_rounds=max(len(stumps), 1))
        clf._set_stumps(stumps, n_features)
        return clf

    @property
    def stumps(self) -> list[Stump]:
        """The learned weak classifiers in the order they were chosen."""
        self._check_fitted()
        return [
            Stump(int(f), float(t), int(p), float(a), float(r))
            for f, t, p, a, r in zip(
                self.features_,
                self.thresholds_,
                self.polarities_,
                self.alphas_,
                self.r_,
                strict=True,
            )
        ]

    # ---------------------------------------------------------------- prediction
    def decision_function(self, X: ArrayLike) -> FloatArray:
        """F(e) = sum_t alpha_t h_t(e) for every row of X (N,)."""
        self._check_fitted()
        X = _as_matrix(X)
        if X.shape[1] != self.n_features_in_:
            raise ValueError(f"X has {X.shape[1]} features, the model {self.n_features_in_}")
        if self._tables.values.shape[0] == 0 or X.shape[0] == 0:
            return np.zeros(X.shape[0])
        return self._tables.evaluate(X)

    def margin_bounds(self, X: FloatArray, unknown: tuple[int, ...]) -> FloatArray:
        """Upper bounds (N,) of :meth:`decision_function` of the rows of X (N, F) whatever
        their values in the columns ``unknown`` (not read; the others finite): each stump
        group of an unknown column counts its largest sum. The groups are added in the same
        order as the margin's, and rounded addition is monotone, so a margin is never above
        its bound, to the last bit."""
        self._check_fitted()
        if X.shape[0] == 0 or self._tables.values.shape[0] == 0:
            return np.zeros(X.shape[0])
        tables = self._bound_tables.get(unknown)
        if tables is None:
            tables = _bounded(self._tables, unknown)
            self._bound_tables[unknown] = tables
        return tables.evaluate(X)

    def predict(self, X: ArrayLike) -> IntArray:
        """H(e) = sign(F(e)) in {+1, -1} (a margin of exactly 0 counts as -1)."""
        return np.where(self.decision_function(X) > 0.0, 1, -1).astype(np.int64)

    def feature_importances(self, n_features: int | None = None) -> FloatArray:
        """Summed alpha per feature column, normalised to sum 1."""
        self._check_fitted()
        n = self.n_features_in_ if n_features is None else n_features
        imp = np.bincount(self.features_, weights=self.alphas_, minlength=n)
        total = imp.sum()
        return np.asarray(imp / total if total > 0 else imp, dtype=np.float64)

    def _check_fitted(self) -> None:
        if not hasattr(self, "alphas_"):
            raise RuntimeError("this AdaBoostLegClassifier is not fitted yet; call fit first")


@dataclass(frozen=True)
class _StumpTables:
    """All stumps evaluated through two binary searches per scan.

    The stumps of one feature and one polarity (a *group*) sum, for polarity +1, to
    ``2 * sum(alpha of theta > x) - sum(alpha)`` and, for polarity -1, to
    ``2 * sum(alpha of theta < x) - sum(alpha)`` (ties x == theta give -1, as in 000 eq. 1),
    so each group's sum depends only on how many of its thresholds lie below x. All
    thresholds of all groups, sorted into one array ``grid``, give every value its rank
    (one ``searchsorted`` per side for every value of every feature); ``values[g, rank]``
    is group ``g``'s sum for any x of that rank. The groups' sums are then added in group
    order, as one loop over the groups would. With T stumps, G groups and N examples this
    costs O(N F log T) plus O(N G) table look-ups.
    """

    columns: IntArray  # (C,) feature columns used by some stump
    group_column: IntArray  # (G,) position in ``columns`` of each group's feature
    right: NDArray[np.bool_]  # (G,) polarity +1: the rank counts thresholds <= x
    grid: FloatArray  # (U,) every threshold, sorted ascending
    values: FloatArray  # (G, U + 1) each group's summed alpha_t h_t(x) by rank of x

    def evaluate(self, X: FloatArray) -> FloatArray:
        """The summed alpha_t h_t of all stumps for the rows of X (N, F) -> (N,)."""
        if _extension is not None:
            out = np.empty(X.shape[0])
            _extension.stump_sums(
                np.ascontiguousarray(X, dtype=np.float64),
                self.columns,
                self.group_column,
                self.right,
                self.grid,
                self.values,
                out,
            )
            return out
        cols = X[:, self.columns]
        ranks = np.where(
            self.right[:, None],
            np.searchsorted(self.grid, cols, side="right").T[self.group_column],
            np.searchsorted(self.grid, cols, side="left").T[self.group_column],
        )
        rows = np.arange(self.values.shape[0])[:, None]
        # groups added in order, the floats a loop over the groups gives, for any number of
        # rows (a cumulative sum adds in order; ``np.add.reduce`` over the groups would
        # add pairwise when X has a single row, so a row's score would depend on the rows
        # scored with it)
        return np.asarray(np.cumsum(self.values[rows, ranks], axis=0)[-1], dtype=np.float64)


def _stump_tables(
    features: IntArray, thresholds: FloatArray, polarities: IntArray, alphas: FloatArray
) -> _StumpTables:
    # (sorted(set()), not np.unique: that imports numpy.ma, 0.1-0.3 s of every start-up)
    columns = sorted(set(features.tolist()))
    grid = np.sort(thresholds, kind="stable")
    group_column: list[int] = []
    right: list[bool] = []
    values: list[FloatArray] = []
    for c, j in enumerate(columns):
        for p in (1, -1):
            sel = (features == j) & (polarities == p)
            if not sel.any():
                continue
            order = np.argsort(thresholds[sel], kind="stable")
            th, al = thresholds[sel][order], alphas[sel][order]
            cum = np.concatenate(([0.0], np.cumsum(al)))
            # +1: alpha of stumps at sorted positions >= idx; -1: those before idx
            partial = cum[-1] - cum if p > 0 else cum
            # idx of every rank of x in the grid: this group's thresholds <= x (+1) or < x
            # (-1), which the rank (searched on the same side) counts among all thresholds
            idx = np.searchsorted(th, grid, side="right" if p > 0 else "left")
            idx_by_rank = np.concatenate(([0], idx)) if p > 0 else np.append(idx, th.size)
            values.append(2.0 * partial[idx_by_rank] - float(cum[-1]))
            group_column.append(c)
            right.append(p > 0)
    n_ranks = grid.size + 1
    return _StumpTables(
        np.array(columns, dtype=np.int64),
        np.array(group_column, dtype=np.int64),
        np.array(right, dtype=bool),
        grid,
        np.array(values, dtype=np.float64).reshape(len(values), n_ranks),
    )


def _bounded(tables: _StumpTables, unknown: tuple[int, ...]) -> _StumpTables:
    """``tables`` with each group of a feature column in ``unknown`` at its largest sum for
    every rank (those columns' values no longer matter)."""
    values = tables.values.copy()
    free = np.array([c in unknown for c in tables.columns[tables.group_column].tolist()], bool)
    values[free] = values[free].max(axis=1, keepdims=True)
    return _StumpTables(tables.columns, tables.group_column, tables.right, tables.grid, values)


def _stump_output(values: FloatArray, threshold: float, polarity: int) -> FloatArray:
    """h(x) of 000 eq. (1) for one feature column."""
    return np.where(polarity * values < polarity * threshold, 1.0, -1.0)


def _as_matrix(X: ArrayLike) -> FloatArray:
    arr = np.asarray(X, dtype=np.float64)
    if arr.ndim != 2:
        raise ValueError(f"X must be two-dimensional (N, F), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError("X contains NaN or infinite values")
    return arr


def _as_labels(y: ArrayLike, n: int) -> FloatArray:
    arr = np.asarray(y).reshape(-1)
    if arr.size != n:
        raise ValueError(f"{arr.size} labels for {n} examples")
    if arr.dtype == bool:
        return np.where(arr, 1.0, -1.0)
    values = set(np.unique(arr).tolist())
    if values <= {-1, 1}:
        return arr.astype(np.float64)
    if values <= {0, 1}:
        return np.where(arr > 0, 1.0, -1.0)
    raise ValueError(f"labels must be +1/-1 (or 1/0), got {sorted(values)[:5]}")
