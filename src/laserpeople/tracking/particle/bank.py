"""A bank of particle filters, one per person, stored as arrays (F filters x P particles).

The trackers of 004 keep one particle filter per person (Sec. 2); here all filters live in
one (F, P, D) state array and one (F, P) weight array so that prediction, weighting and
resampling run once per scan for every filter together. The bank also keeps each
filter's identity, birth time, the last time it saw support, and its number of supported
scans, and it adds and removes filters: the birth/death bookkeeping and the reported
tracks the feet and the upper-body tracker share.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from laserpeople.frame import Frame
from laserpeople.tracking.particle.resampling import (
    effective_sample_size,
    normalise,
    systematic_resample,
)
from laserpeople.tracks import Track, Tracks


class FilterBank:
    """F particle filters of P particles with D state parameters each."""

    def __init__(self, n_particles: int, dim: int) -> None:
        self.n_particles = n_particles
        self.dim = dim
        self.states = np.empty((0, n_particles, dim))
        self.weights = np.empty((0, n_particles))
        self.ids = np.empty(0, dtype=np.int64)
        self.born = np.empty(0)
        self.last_seen = np.empty(0)
        self.hits = np.empty(0, dtype=np.int64)
        self.quality = np.empty(0)
        self._next_id = 0

    def __len__(self) -> int:
        return int(self.ids.size)

    def add(self, states: NDArray[np.float64], stamp: float) -> None:
        """Append filters with initial particles ``states`` (K, P, D) and uniform weights."""
        k = states.shape[0]
        if k == 0:
            return
        self.states = np.concatenate([self.states, states])
        self.weights = np.concatenate(
            [self.weights, np.full((k, self.n_particles), 1.0 / self.n_particles)]
        )
        self.ids = np.concatenate([self.ids, self._next_id + np.arange(k, dtype=np.int64)])
        self._next_id += k
        self.born = np.concatenate([self.born, np.full(k, stamp)])
        self.last_seen = np.concatenate([self.last_seen, np.full(k, stamp)])
        self.hits = np.concatenate([self.hits, np.ones(k, dtype=np.int64)])
        self.quality = np.concatenate([self.quality, np.zeros(k)])

    def keep(self, mask: NDArray[np.bool_]) -> None:
        """Keep only the filters where ``mask`` (F,) is True."""
        self.states = self.states[mask]
        self.weights = self.weights[mask]
        self.ids = self.ids[mask]
        self.born = self.born[mask]
        self.last_seen = self.last_seen[mask]
        self.hits = self.hits[mask]
        self.quality = self.quality[mask]

    def reweight(
        self, likelihood: NDArray[np.float64], rng: np.random.Generator, threshold: float
    ) -> None:
        """Update each filter's ``quality`` (exponentially smoothed log of the marginal
        likelihood sum_i w_i l_i), multiply the weights by ``likelihood`` (F, P),
        normalise, and resample
        systematically every filter whose effective sample size fell below
        ``threshold * P``."""
        if len(self) == 0:
            return
        marginal = np.einsum("fp,fp->f", self.weights, likelihood)
        self.quality = 0.9 * self.quality + 0.1 * np.log(np.maximum(marginal, 1e-300))
        self.weights = normalise(self.weights * likelihood)
        low = effective_sample_size(self.weights) < threshold * self.n_particles
        if low.any():
            idx = systematic_resample(self.weights[low], rng)
            rows = np.flatnonzero(low)[:, None]
            self.states[low] = self.states[rows, idx]
            self.weights[low] = 1.0 / self.n_particles

    def support(self, seen: NDArray[np.bool_], stamp: float) -> None:
        """Filters where ``seen`` (F,) is True had support in the frame at ``stamp``."""
        self.last_seen[seen] = stamp
        self.hits[seen] += 1

    def cull(
        self,
        stamp: float,
        miss_time: float,
        pairs: Iterable[tuple[int, int]],
        by_quality: bool,
        keep_identity_age: float = 0.0,
    ) -> None:
        """Filter death (004 Sec. 2): remove every filter without support for longer than
        ``miss_time`` [s], and one of each pair of alive filters in ``pairs`` (two filters
        close together): the younger one, or with ``by_quality`` the one with the lower
        smoothed likelihood, whose survivor then keeps the older identity
        (:meth:`replace_by`), unless both were born at least ``keep_identity_age`` [s] ago
        (> 0; two people who cross): then it keeps its own."""
        alive = stamp - self.last_seen <= miss_time
        for i, j in sorted({(min(a, b), max(a, b)) for a, b in pairs if a != b}):
            if not (alive[i] and alive[j]):
                continue
            if by_quality:
                loser, winner = (i, j) if self.quality[i] < self.quality[j] else (j, i)
                young = stamp - max(self.born[i], self.born[j]) < keep_identity_age
                if keep_identity_age <= 0.0 or young:
                    self.replace_by(loser, winner)
            else:
                older = (self.born[i], self.ids[i]) < (self.born[j], self.ids[j])
                loser = j if older else i
            alive[loser] = False
        self.keep(alive)

    def tracks(
        self,
        positions: NDArray[np.float64],
        velocities: NDArray[np.float64],
        confirm: int,
        frame: Frame,
        shown: NDArray[np.bool_] | None = None,
    ) -> Tracks:
        """The frame's tracks: for every filter with at least ``confirm`` supported scans
        (and ``shown`` (F,) True, if given), the weighted mean of the particles'
        ``positions`` (F, P, 2) [m] and ``velocities`` (F, P, 2) [m/s], with the
        positions' weighted covariance."""
        out = []
        if len(self):
            est = np.einsum("fp,fpc->fc", self.weights, positions)
            vel = np.einsum("fp,fpc->fc", self.weights, velocities)
            d = positions - est[:, None, :]
            cov = np.einsum("fp,fpa,fpb->fab", self.weights, d, d)
            ok = self.hits >= confirm
            if shown is not None:
                ok &= shown
            for f in np.flatnonzero(ok):
                out.append(Track(int(self.ids[f]), "person", est[f], vel[f], cov[f]))
        return Tracks(frame.stamp, frame.index, tuple(out), frame.frame, frame.sensor_pose)

    def replace_by(self, loser: int, winner: int) -> None:
        """Let filter ``winner`` take over the identity of ``loser`` when ``loser`` is the
        older one (the person keeps the id under which it was first reported); ``loser``
        must then be removed with :meth:`keep`."""
        if (self.born[loser], self.ids[loser]) < (self.born[winner], self.ids[winner]):
            self.ids[winner] = self.ids[loser]
            self.born[winner] = self.born[loser]
            self.hits[winner] = max(self.hits[winner], self.hits[loser])

    def mean(self, columns: slice | list[int]) -> NDArray[np.float64]:
        """Weighted mean (F, len(columns)) of the state columns."""
        return np.asarray(
            np.einsum("fp,fpd->fd", self.weights, self.states[:, :, columns]), dtype=np.float64
        )


__all__ = ["FilterBank"]
