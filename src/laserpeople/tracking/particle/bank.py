"""A bank of particle filters, one per person, stored as arrays (F filters x P particles).

The trackers of 004 keep one particle filter per person (Sec. 2); here all filters live in
one (F, P, D) state array and one (F, P) weight array so that prediction, weighting and
resampling run once per scan for every filter together. The bank also keeps each
filter's identity, birth time, the last time it saw support, and its number of supported
scans, and it adds and removes filters.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.particle.resampling import (
    effective_sample_size,
    normalise,
    systematic_resample,
)


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

    def keep(self, mask: NDArray[np.bool_]) -> None:
        """Keep only the filters where ``mask`` (F,) is True."""
        self.states = self.states[mask]
        self.weights = self.weights[mask]
        self.ids = self.ids[mask]
        self.born = self.born[mask]
        self.last_seen = self.last_seen[mask]
        self.hits = self.hits[mask]

    def reweight(
        self, likelihood: NDArray[np.float64], rng: np.random.Generator, threshold: float
    ) -> None:
        """Multiply the weights by ``likelihood`` (F, P), normalise, and resample
        systematically every filter whose effective sample size fell below
        ``threshold * P``."""
        if len(self) == 0:
            return
        self.weights = normalise(self.weights * likelihood)
        low = effective_sample_size(self.weights) < threshold * self.n_particles
        if low.any():
            idx = systematic_resample(self.weights[low], rng)
            rows = np.flatnonzero(low)[:, None]
            self.states[low] = self.states[rows, idx]
            self.weights[low] = 1.0 / self.n_particles

    def mean(self, columns: slice | list[int]) -> NDArray[np.float64]:
        """Weighted mean (F, len(columns)) of the state columns."""
        return np.asarray(
            np.einsum("fp,fpd->fd", self.weights, self.states[:, :, columns]), dtype=np.float64
        )


__all__ = ["FilterBank"]
