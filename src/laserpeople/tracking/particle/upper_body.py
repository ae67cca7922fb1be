"""The upper-body tracker of 004 Sec. 2.2: one particle filter per person at torso height.

- Detection: mean-shift clusters of foreground points whose covariance has a largest
  eigenvalue of at least ``min_eigenvalue`` (the minimal body size) and that no filter
  already explains start a filter at the cluster centre.
- State (x, y, theta, v): position [m], direction of motion [rad], speed [m/s]; linear
  motion (eq. 8) plus Gaussian diffusion of every parameter.
- Weight of a particle (eq. 9): sum over the foreground points of its filter's Voronoi cell
  of exp(-d^2 / zeta^2), each point first moved ``surface_offset`` along its beam away
  from its laser (the torso's centre lies behind the surface the laser sees; a departure
  from 004); a point belongs to the cell of the nearest filter (and to none
  when farther than ``cell_radius`` from all), so a filter never takes the points of a
  person another filter tracks.
- Death: a filter without points in its cell for ``miss_time``, or one that comes within
  ``merge_distance`` of an older filter, is removed.
- Objects too big to be a person (a departure from 004, measured on the baggage cart of
  Exp. 6; :mod:`~laserpeople.tracking.particle.objects`): points of a connected object
  whose covariance has a largest eigenvalue above ``max_eigenvalue`` neither start a
  filter nor count as a filter's support, and (``weigh_objects`` False) they are left
  out of eq. 9, so that a filter born on a cart while it was half hidden dies once the
  whole cart is seen and a filter is not pulled onto the cart its person pushes.
- Things carried in front (a departure from 004, measured on the carried item of Exp. 6;
  ``carry_depth``, 0 restores 004): a moving filter leaves out of eq. 9 the points of its
  cell lying more than ``carry_depth`` ahead, along its mean velocity, of the cell's
  rearmost point (:func:`carried_ahead`); a torso is shallower than that, so what lies
  beyond is carried and would draw the estimate ahead of the body.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from laserpeople.clustering import cluster_covariances, mean_shift
from laserpeople.clustering.trees import close_pairs, nearest
from laserpeople.config import param
from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.tracking.particle.bank import FilterBank
from laserpeople.tracking.particle.frames import shifted_foreground
from laserpeople.tracking.particle.objects import (
    ObjectMemory,
    largest_eigenvalue,
    small_objects,
)
from laserpeople.tracks import Tracks

X, Y, THETA, V = range(4)


@dataclass(frozen=True)
class UpperBodyParams:
    """Parameters of the upper-body particle-filter tracker (004 Sec. 2.2)."""

    config_section = "upper_body_pf"
    paper_preset = MappingProxyType(
        {  # 004 where the defaults depart from it (docs/papers.md)
            "max_eigenvalue": 0.0,
            "object_memory": 0.0,
            "weigh_objects": True,
            "surface_offset": 0.0,
            "carry_depth": 0.0,
            "leg_reid": False,
        }
    )

    particles: int = param(
        500,
        "assumption: 500 particles per filter meets the speed target (docs/schenk-tables.md)",
        "particles per filter",
    )
    zeta: float = param(0.25, "assumed (004 eq. 9 gives no value)", "zeta of eq. 9", "m")
    bandwidth: float = param(0.35, "assumed", "mean-shift bandwidth for detection", "m")
    min_eigenvalue: float = param(
        0.003,
        "assumed: a torso arc >= ~0.2 m wide (004 Sec. 2.2 'minimal human body size')",
        "smallest largest-eigenvalue of a cluster's covariance that starts a filter",
        "m^2",
    )
    min_points: int = param(4, "assumed", "fewest points of a cluster that starts a filter")
    max_eigenvalue: float = param(
        0.065,
        "departure from 004 (which bounds size only by the mean-shift bandwidth); measured "
        "on seeds 0..2: people (with shoulder bag or carried box) <= 0.057, a whole "
        "baggage cart 0.08-0.11",
        "an object (single-linkage points) whose covariance has a larger largest eigenvalue "
        "is no person: it starts no filter and supports none; 0 disables",
        "m^2",
    )
    link_distance: float = param(
        0.15,
        "assumed: 3x the point spacing of an LMS151 at 5 m, below the ~0.2 m gap between a "
        "person and the cart they push",
        "points closer than this belong to one object (for max_eigenvalue)",
        "m",
    )
    object_memory: float = param(
        1.0,
        "departure from 004 (0 here); the pieces of a baggage cart at the far end of the "
        "room, seen at a grazing angle, started filters (cart, seeds 200-203: MOTP 0.73 "
        "at 0, 0.79 at 1 s)",
        "how long the pieces of an object last seen too big (max_eigenvalue) start no "
        "filter (objects.ObjectMemory); 0 disables",
        "s",
    )
    object_reach: float = param(
        0.1,
        "assumed: 4x the ~0.025 m a walking person's cart moves between scans at 50 Hz",
        "a point this close to a remembered point of the previous scan is remembered "
        "(at 50 Hz; scaled up with the time between scans)",
        "m",
    )
    weigh_objects: bool = param(
        False,
        "departure from 004 (which has no size bound); True is the behaviour before the "
        "cart fix: points of too-big objects were still summed in eq. 9 and pulled a "
        "filter onto the cart its person pushes (cart, seeds 200-203: MOTP 0.51 with "
        "True, 0.73 with False, 0.79 with object_memory too)",
        "points of objects above max_eigenvalue count in eq. 9 (True) or are left out of "
        "every filter's cell (False)",
    )
    surface_offset: float = param(
        0.15,
        "departure from 004 (eq. 9 uses the points as measured, 0): about half a torso's "
        "depth; measured on seeds 0-1 (join, shoulder bag, carried item, cart, 5 people: "
        "MOTP 0.85 at 0, 0.90 at 0.15, 0.80 at 0.2)",
        "in eq. 9 every foreground point is moved this far along its beam, away from its "
        "laser (a body's centre lies behind the surface the laser sees)",
        "m",
    )
    cell_radius: float = param(
        0.6, "assumed", "points farther than this from every filter belong to no cell", "m"
    )
    carry_depth: float = param(
        0.45,
        "departure from 004 (0 here: all of a cell's points weigh); a box carried in front "
        "joins the torso's cluster (004 Sec. 3.5) and drew eq. 9's mode 0.25 m ahead of the "
        "body (carrying, seeds 200-203: MOTP 0.69 at 0, 0.94 at 0.4 and 0.45, 0.85 at 0.5)",
        "in eq. 9 a moving filter leaves out the points of its cell lying more than this "
        "far ahead, along its direction of motion, of the cell's rearmost point (a torso is "
        "<= ~0.3 m deep; what lies farther ahead is carried); 0 disables",
        "m",
    )
    carry_min_speed: float = param(
        0.3,
        "assumed: below a slow walk the direction of motion is unreliable",
        "carry_depth applies to filters whose mean velocity is at least this",
        "m/s",
    )
    birth_exclusion: float = param(
        0.6, "assumed", "no filter starts this close to an existing one", "m"
    )
    sigma_position: float = param(0.15, "assumed", "position diffusion", "m/sqrt(s)")
    sigma_heading: float = param(1.5, "assumed", "direction diffusion", "rad/sqrt(s)")
    sigma_speed: float = param(1.0, "assumed", "speed diffusion", "m/s/sqrt(s)")
    max_speed: float = param(3.5, "assumed (running in 004 Exp. 1)", "largest speed", "m/s")
    initial_speed: float = param(1.5, "assumed", "initial speeds are drawn in [0, this]", "m/s")
    miss_time: float = param(
        0.2,
        "assumed; tuned on 5 simulated runs (speed-normal, speed-fast, people-3, cross, stop)",
        "a filter without points in its cell this long is removed",
        "s",
    )
    merge_distance: float = param(
        0.25, "assumed", "a filter this close to an older one is removed", "m"
    )
    confirm_scans: int = param(
        2,
        "assumed; tuned with miss_time",
        "scans with points in its cell before a filter is reported",
    )
    resample_threshold: float = param(
        0.5, "Thrun et al. 2005 (common choice)", "resample when ESS < this x particles"
    )
    weight_floor: float = param(
        1e-9, "assumed", "added to every eq. 9 weight so that no filter degenerates"
    )
    seed: int = param(0, "reproducibility", "random seed of the filters")

    leg_reid: bool = param(
        True,
        "measured (docs/trackers.md, the real followed-person recording): identity recall "
        "of the followed person 0.57 -> 0.88; false in the paper preset (004 has none)",
        "give people who come back after a loss their old id by their leg widths ([leg_reid], "
        "identity/leg_width.py)",
    )

    def __post_init__(self) -> None:
        if self.particles < 1:
            raise ConfigError(f"particles must be >= 1, got {self.particles}")
        for name in ("zeta", "bandwidth", "cell_radius", "max_speed"):
            if not getattr(self, name) > 0.0:
                raise ConfigError(f"{name} must be positive, got {getattr(self, name)}")


def linear_motion(states: NDArray[np.float64], dt: float) -> NDArray[np.float64]:
    """004 eq. 8: (x, y, theta, v) + (cos theta, sin theta, 0, 0) * dt * v, for states
    (..., 4); returns a new array."""
    out = np.array(states, dtype=np.float64, copy=True)
    step = dt * states[..., V]
    out[..., X] += np.cos(states[..., THETA]) * step
    out[..., Y] += np.sin(states[..., THETA]) * step
    return out


def cell_weights(
    particles_xy: NDArray[np.float64],
    cell_points: NDArray[np.float64],
    cell_mask: NDArray[np.bool_],
    zeta: float,
) -> NDArray[np.float64]:
    """004 eq. 9: w_i = sum_j exp(-|p_i - z_j|^2 / zeta^2) over the points of each filter's
    cell. ``particles_xy`` (F, P, 2), ``cell_points`` (F, K, 2) padded, ``cell_mask`` (F, K)
    True for real points; returns (F, P)."""
    f32 = particles_xy.astype(np.float32)
    z32 = cell_points.astype(np.float32)
    d2 = (  # |p - z|^2 as one batched product; padding points pushed far away
        np.einsum("fpc,fpc->fp", f32, f32)[:, :, None]
        + np.where(cell_mask, np.einsum("fkc,fkc->fk", z32, z32), np.float32(1e6))[:, None, :]
        - 2.0 * np.matmul(f32, z32.transpose(0, 2, 1))
    )
    kernel = np.exp(np.maximum(d2, 0.0) * np.float32(-1.0 / (zeta * zeta)))
    return np.asarray(kernel.sum(axis=2, dtype=np.float64), dtype=np.float64)


def voronoi_cells(
    points: NDArray[np.float64], centres: NDArray[np.float64], radius: float
) -> NDArray[np.int64]:
    """The filter (index into ``centres`` (F, 2)) whose Voronoi cell holds each point
    (N, 2): the nearest centre, or -1 when it is farther than ``radius``."""
    if len(centres) == 0 or len(points) == 0:
        return np.full(len(points), -1, dtype=np.int64)
    d, j = nearest(points, centres)
    return np.where(d <= radius, j, -1).astype(np.int64)


def gather_cells(
    points: NDArray[np.float64], cell: NDArray[np.int64], n_filters: int
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Points (N, ...) grouped by cell into a padded (F, K, ...) array and its (F, K) mask
    (rows of any width: (N, 2) points, or (N, 3) points with a weight)."""
    inside = cell >= 0
    c = cell[inside]
    pts = points[inside]
    counts = np.bincount(c, minlength=n_filters)
    k = int(counts.max()) if counts.size else 0
    order = np.argsort(c, kind="stable")
    c, pts = c[order], pts[order]
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    slot = np.arange(c.size) - start[c]
    out = np.zeros((n_filters, max(k, 1), *points.shape[1:]))
    mask = np.zeros((n_filters, max(k, 1)), dtype=bool)
    out[c, slot] = pts
    mask[c, slot] = True
    return out, mask


def carried_ahead(
    points: NDArray[np.float64],
    cell: NDArray[np.int64],
    velocities: NDArray[np.float64],
    depth: float,
    min_speed: float,
) -> NDArray[np.bool_]:
    """Points (N, 2) [m] of each cell (index into the filters' mean ``velocities`` (F, 2)
    [m/s], -1 for none) that lie more than ``depth`` [m] ahead of their cell's rearmost
    point along the filter's direction of motion, for filters at least ``min_speed``
    [m/s] fast: what a person carries in front of the body. Returns a mask (N,)."""
    out = np.zeros(len(points), dtype=bool)
    speed = np.hypot(velocities[:, 0], velocities[:, 1])
    moving = speed >= max(min_speed, 1e-9)
    sel = np.flatnonzero((cell >= 0) & moving[np.maximum(cell, 0)])
    if sel.size == 0:
        return out
    c = cell[sel]
    unit = velocities[c] / speed[c, None]
    along = np.einsum("nc,nc->n", points[sel], unit)
    rear = np.full(len(velocities), np.inf)
    np.minimum.at(rear, c, along)
    out[sel] = along - rear[c] > depth
    return out


def detect_bodies(points: NDArray[np.float64], p: UpperBodyParams) -> NDArray[np.float64]:
    """Centres (M, 2) of the mean-shift clusters of ``points`` big enough to be a person
    (largest covariance eigenvalue >= ``min_eigenvalue``, >= ``min_points`` points)."""
    if len(points) < p.min_points:
        return np.empty((0, 2))
    ms = mean_shift(points, p.bandwidth)
    mean, cov, cnt = cluster_covariances(points, ms.labels, ms.n_clusters)
    ok = (cnt >= p.min_points) & (largest_eigenvalue(cov) >= p.min_eigenvalue)
    return np.asarray(mean[ok], dtype=np.float64)


class UpperBodyTracker:
    """Multi-person tracker at upper-body height (004 Sec. 2.2); a ``FrameTracker`` on the
    fused foreground points of the torso-height lasers."""

    consumes: frozenset[FrameField] = frozenset({"points", "foreground"})
    needs_steady_points = True
    """A filter dies after ``miss_time`` without points: on a moving laser the pipeline's
    foreground of points near legs holds missed legs for it
    (:mod:`laserpeople.pipeline.leg_foreground`)."""

    def __init__(self, params: UpperBodyParams | None = None) -> None:
        self.params = params or UpperBodyParams()
        self.rng = np.random.default_rng(self.params.seed)
        self.bank = FilterBank(self.params.particles, 4)
        self._stamp: float | None = None
        self.objects = ObjectMemory(self.params.object_reach, self.params.object_memory)

    def _predict(self, dt: float) -> None:
        p, bank = self.params, self.bank
        if len(bank) == 0 or dt <= 0.0:
            return
        s = bank.states
        s[:] = linear_motion(s, dt)
        root = np.sqrt(dt)
        shape = s.shape[:2]
        s[..., X] += self.rng.normal(0.0, p.sigma_position * root, shape)
        s[..., Y] += self.rng.normal(0.0, p.sigma_position * root, shape)
        s[..., THETA] += self.rng.normal(0.0, p.sigma_heading * root, shape)
        s[..., V] = np.clip(
            s[..., V] + self.rng.normal(0.0, p.sigma_speed * root, shape), 0.0, p.max_speed
        )

    def update(self, frame: Frame) -> Tracks:
        """Predict every filter to the frame's stamp, weight by eq. 9 in its Voronoi cell,
        resample, remove dead filters and start new ones."""
        p, bank = self.params, self.bank
        dt = 0.0 if self._stamp is None else frame.stamp - self._stamp
        self._stamp = frame.stamp
        pts = frame.foreground_points("the upper-body tracker")
        sized = small_objects(pts, p.link_distance, p.max_eigenvalue)
        remembered = self.objects.update(pts, ~sized, frame.stamp)
        self._predict(dt)
        if len(bank):
            centres = bank.mean([X, Y])
            cell = voronoi_cells(pts, centres, p.cell_radius)
            if not p.weigh_objects:
                cell[~sized] = -1  # a too-big object's points weigh no filter
            if p.carry_depth > 0.0:
                ahead = carried_ahead(
                    pts, cell, self._velocities(), p.carry_depth, p.carry_min_speed
                )
                cell[ahead] = -1  # carried in front of the body: weighs no filter
            surface = pts
            if p.surface_offset:
                surface = shifted_foreground(frame, p.surface_offset, "the upper-body tracker")
            cell_pts, mask = gather_cells(surface, cell, len(bank))
            lik = cell_weights(bank.states[..., :2], cell_pts, mask, p.zeta) + p.weight_floor
            bank.reweight(lik, self.rng, p.resample_threshold)
            seen = np.zeros(len(bank), dtype=bool)
            seen[cell[sized & (cell >= 0)]] = True
            bank.support(seen, frame.stamp)
            self._cull(frame.stamp)
        self._births(pts[~remembered], frame.stamp)
        return self._report(frame)

    def _cull(self, stamp: float) -> None:
        """Remove filters without points in their cell for ``miss_time`` and the younger
        of two filters closer than ``merge_distance``."""
        p, bank = self.params, self.bank
        pairs: list[tuple[int, int]] = []
        if len(bank) > 1:
            found = close_pairs(bank.mean([X, Y]), p.merge_distance)
            pairs = [(int(a), int(b)) for a, b in found]
        bank.cull(stamp, p.miss_time, pairs, by_quality=False)

    def _births(self, pts: NDArray[np.float64], stamp: float) -> None:
        p, bank = self.params, self.bank
        if len(pts) == 0:
            return
        if len(bank):
            d, _ = nearest(pts, bank.mean([X, Y]))
            pts = pts[d > p.birth_exclusion]
        found = detect_bodies(pts, p)
        if len(found) == 0:
            return
        # one birth per spot even when clusters lie close together
        keep: list[int] = []
        for i in range(len(found)):
            if all(np.hypot(*(found[i] - found[j])) > p.birth_exclusion for j in keep):
                keep.append(i)
        found = found[keep]
        n, k = p.particles, len(found)
        init = np.empty((k, n, 4))
        init[..., X] = found[:, None, 0] + self.rng.normal(0.0, 0.05, (k, n))
        init[..., Y] = found[:, None, 1] + self.rng.normal(0.0, 0.05, (k, n))
        init[..., THETA] = self.rng.uniform(-np.pi, np.pi, (k, n))
        init[..., V] = self.rng.uniform(0.0, p.initial_speed, (k, n))
        bank.add(init, stamp)

    def _particle_velocities(self) -> NDArray[np.float64]:
        st = self.bank.states
        return np.stack(
            [st[..., V] * np.cos(st[..., THETA]), st[..., V] * np.sin(st[..., THETA])], -1
        )

    def _velocities(self) -> NDArray[np.float64]:
        """Weighted mean velocity (F, 2) [m/s] of every filter."""
        w = self.bank.weights
        vel = self._particle_velocities()
        return np.asarray(
            np.einsum("fp,fpc->fc", w, vel) / w.sum(axis=1)[:, None], dtype=np.float64
        )

    def _report(self, frame: Frame) -> Tracks:
        vel = self._particle_velocities()
        return self.bank.tracks(self.bank.states[..., :2], vel, self.params.confirm_scans, frame)


__all__ = [
    "UpperBodyParams",
    "UpperBodyTracker",
    "carried_ahead",
    "cell_weights",
    "detect_bodies",
    "gather_cells",
    "largest_eigenvalue",
    "linear_motion",
    "voronoi_cells",
]
