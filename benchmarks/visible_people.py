"""Who the laser shows on a labelled scan, from the raw returns alone (no leg detector, no
tracker of ours): the oracle bound of ``moving_people.py --ceiling``.

1. **Objects.** The returns of a scan are cut into clusters where neighbouring valid
   returns lie :data:`GAP` or more apart. A cluster of at least :data:`MIN_POINTS` returns
   within :data:`RANGE` of the laser, at most :data:`MAX_WIDTH` from its first to its last
   return, is *person-sized* (a leg, or two legs seen as one; walls and long furniture
   are wider).
2. **Paths.** Person-sized clusters are chained from scan to scan in the world frame
   (the scans' sensor poses): each path takes the nearest cluster within :data:`STEP`
   per scan elapsed, for at most :data:`MAX_GAP` scans without one (nearest pairs first).
3. **Walkers.** A path has walked when (a) at some time it lies :data:`WALKED` or
   farther from where it began, and (b) on at least half of its scans, the scan
   :data:`LOOK` before or after sees *through* its place: every beam of that scan within
   :data:`HALF_WIDTH` of the place returns :data:`MARGIN` or more behind it, or has no
   return (+inf, NaN). A post, a bin or a piece of wall fails both (odometry drifts by
   centimetres over a few seconds; a chain that hops between neighbouring posts or
   slides along a wall seen at a grazing angle fails (b)). Every cluster of a path that
   has walked counts, its standing phases too.
4. **People.** On a scan, the walkers' clusters within :data:`PERSON_SPAN` of each other
   are one person (two legs); a person farther than the benchmark's gate from every
   label is unlabelled.

People who never walk while in view are not counted, nor are people farther than
:data:`RANGE`: the counts are lower bounds of the people the laser shows.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from laserpeople.scan import Scan

GAP = 0.13  # m, neighbouring returns this far apart or farther start a new cluster
MIN_POINTS = 3  # returns of a cluster that can be a leg
MAX_WIDTH = 0.6  # m, first to last return: a leg, or two legs seen as one
RANGE = 3.5  # m, farther clusters are left out (few returns; glass walls drop some)
STEP = 0.45  # m per scan elapsed: a leg swinging at 3 m/s at 7.5 Hz moves 0.4 m
MAX_GAP = 3  # scans a path may go without a cluster
WALKED = 0.5  # m from its first position: the path has walked
LOOK = 4  # scans (0.53 s at 7.5 Hz) between a scan and those that may see through a place
MARGIN = 0.3  # m, a beam "sees through" a place when it returns this far behind it
HALF_WIDTH = 0.05  # m, beams this close to the place laterally must all see through it
PERSON_SPAN = 0.8  # m, walkers' clusters closer than this are the legs of one person


def clusters(scan: Scan, max_range: float = RANGE) -> np.ndarray:
    """Centres (M, 2) [m, laser frame] of the person-sized clusters of ``scan`` within
    ``max_range`` [m] (module docstring, step 1)."""
    pts, _ = scan.valid_points("sensor")
    if len(pts) == 0:
        return np.empty((0, 2))
    gaps = np.hypot(*(pts[1:] - pts[:-1]).T)
    cuts = np.concatenate(([0], np.flatnonzero(gaps >= GAP) + 1, [len(pts)])).tolist()
    out = []
    for a, b in itertools.pairwise(cuts):
        c = pts[a:b]
        centre = c.mean(axis=0)
        wide = float(np.hypot(*(c[-1] - c[0]))) > MAX_WIDTH
        if len(c) >= MIN_POINTS and not wide and float(np.hypot(*centre)) <= max_range:
            out.append(centre)
    return np.array(out).reshape(-1, 2)


def seen_through(scan: Scan, world_xy: np.ndarray) -> bool:
    """Whether every beam of ``scan`` within :data:`HALF_WIDTH` of the world point
    ``world_xy`` (2,) [m] returns :data:`MARGIN` or more behind it or has no return
    (+inf or NaN); False for a point outside the field of view, for a beam that returns
    in front of or at it, and for a scan without a sensor pose."""
    if scan.pose is None:
        return False
    x, y = scan.pose.inverse_transform_points(np.asarray(world_xy)[None])[0].tolist()
    r = math.hypot(x, y)
    if r <= HALF_WIDTH:
        return False
    centre = (math.atan2(y, x) - scan.angle_min) / scan.angle_increment
    span = math.atan2(HALF_WIDTH, r) / abs(scan.angle_increment)
    lo = min(math.ceil(centre - span), round(centre))
    hi = max(math.floor(centre + span), round(centre))
    if lo < 0 or hi >= scan.n_beams:
        return False
    beams = scan.ranges[lo : hi + 1]
    return bool(((beams >= r + MARGIN) | np.isnan(beams)).all())


@dataclass
class Path:
    """One chain of person-sized clusters.

    Attributes:
        scans: Scan index of each cluster.
        world: World position of each cluster [m].
        sensor: Laser-frame position of each cluster [m].
    """

    scans: list[int] = field(default_factory=list)
    world: list[np.ndarray] = field(default_factory=list)
    sensor: list[np.ndarray] = field(default_factory=list)

    def walked(self, scans: Mapping[int, Scan]) -> bool:
        """Whether the path has walked (module docstring, step 3; ``scans``: index ->
        scan, those :data:`LOOK` before and after the path's scans among them)."""
        first = self.world[0]
        if all(float(np.hypot(*(w - first))) < WALKED for w in self.world):
            return False
        through = sum(
            any(seen_through(scans[j], w) for j in (i - LOOK, i + LOOK) if j in scans)
            for i, w in zip(self.scans, self.world, strict=True)
        )
        return 2 * through >= len(self.scans)


def paths(scans: Iterable[Scan]) -> list[Path]:
    """The paths of the person-sized clusters of ``scans`` (in time order; scans without
    a sensor pose are skipped; module docstring, step 2)."""
    done: list[Path] = []
    active: list[Path] = []
    for scan in scans:
        if scan.pose is None:
            continue
        local = clusters(scan)
        world = scan.pose.transform_points(local) if len(local) else local
        done += [p for p in active if scan.index - p.scans[-1] > MAX_GAP]
        active = [p for p in active if scan.index - p.scans[-1] <= MAX_GAP]
        pairs = sorted(
            (float(np.hypot(*(w - p.world[-1]))), k, j)
            for k, p in enumerate(active)
            for j, w in enumerate(world)
            if float(np.hypot(*(w - p.world[-1]))) <= STEP * (scan.index - p.scans[-1])
        )
        taken_paths: set[int] = set()
        taken: set[int] = set()
        for _, k, j in pairs:
            if k in taken_paths or j in taken:
                continue
            taken_paths.add(k)
            taken.add(j)
            active[k].scans.append(scan.index)
            active[k].world.append(world[j])
            active[k].sensor.append(local[j])
        for j in range(len(world)):
            if j not in taken:
                active.append(Path([scan.index], [world[j]], [local[j]]))
    return done + active


def people(centres: np.ndarray) -> list[np.ndarray]:
    """``centres`` (M, 2) [m] grouped into people: single linkage within
    :data:`PERSON_SPAN`; each person is the mean of its group (in order of first member)."""
    n = len(centres)
    group = list(range(n))
    for i in range(n):
        for j in range(i):
            if float(np.hypot(*(centres[i] - centres[j]))) < PERSON_SPAN:
                old, new = group[i], group[j]
                group = [new if g == old else g for g in group]
    firsts = sorted(set(group), key=group.index)
    return [centres[[k for k in range(n) if group[k] == g]].mean(axis=0) for g in firsts]


@dataclass(frozen=True)
class Unlabelled:
    """The walkers the raw scan shows farther than the gate from every label.

    Attributes:
        scan: Scan index.
        beside: Positions (laser frame [m]) of those inside the place beside the robot.
        others: Positions of the others.
    """

    scan: int
    beside: tuple[tuple[float, float], ...]
    others: tuple[tuple[float, float], ...]


def unlabelled_people(
    scans: Sequence[Scan],
    labels: Mapping[int, Mapping[int, np.ndarray]],
    box: tuple[float, float, float, float],
    gate: float,
) -> list[Unlabelled]:
    """Per labelled scan (in order), the people of the walking paths (:func:`paths`,
    :func:`people`) farther than ``gate`` [m] from every label, split by whether they lie
    in ``box`` (x_min, x_max, y_min, y_max [m], laser frame). ``scans``: every scan of the
    recording in time order, each with its own ranges (a reader may reuse its buffer)."""
    shown: dict[int, list[np.ndarray]] = {i: [] for i in labels}
    by_index = {s.index: s for s in scans}
    for path in paths(scans):
        if path.walked(by_index):
            for i, xy in zip(path.scans, path.sensor, strict=True):
                if i in shown:
                    shown[i].append(xy)
    x0, x1, y0, y1 = box
    out = []
    for index in sorted(labels):
        truth = np.array(list(labels[index].values()), dtype=np.float64).reshape(-1, 2)
        beside: list[tuple[float, float]] = []
        others: list[tuple[float, float]] = []
        for p in people(np.array(shown[index]).reshape(-1, 2)):
            if len(truth) and float(np.hypot(*(truth - p).T).min()) <= gate:
                continue
            x, y = p.tolist()
            (beside if x0 < x < x1 and y0 < y < y1 else others).append((x, y))
        out.append(Unlabelled(index, tuple(beside), tuple(others)))
    return out


def labels_shown(
    scans: Iterable[Scan], labels: Mapping[int, Mapping[int, np.ndarray]], near: float
) -> int:
    """Labels (laser frame [m]) with the centre of a person-sized cluster of their scan,
    at any range, within ``near`` [m]."""
    shown = 0
    for scan in scans:
        if scan.index not in labels:
            continue
        centres = clusters(scan, math.inf)
        for pos in labels[scan.index].values():
            shown += bool(len(centres)) and float(np.hypot(*(centres - pos).T).min()) <= near
    return shown


@dataclass(frozen=True)
class Oracle:
    """What a tracker that reports every person the laser shows can score.

    Attributes:
        labels: Labels.
        shown: Labels with a person-sized cluster within the benchmark's ``near``
            (:func:`labels_shown`).
        scans: Labelled scans.
        beside: Labelled scans with an unlabelled person beside the robot.
        unlabelled: Unlabelled people summed over the labelled scans (those beside the
            robot included).
    """

    labels: int
    shown: int
    scans: int
    beside: int
    unlabelled: int

    @property
    def mota(self) -> float:
        """MOTA of a perfect tracker of every person shown (every label matched, every
        unlabelled person a false positive): 1 - unlabelled / labels."""
        return 1.0 - self.unlabelled / self.labels

    def mota_at_recall(self, recall: float) -> float:
        """MOTA with the fewest matches that reach ``recall``, every unlabelled person
        reported: 1 - (misses + unlabelled) / labels."""
        return 1.0 - (self._misses(recall) + self.unlabelled) / self.labels

    def max_false_positives(self, recall: float, mota: float) -> int:
        """The most false positives with which the fewest matches that reach ``recall``
        still reach ``mota``."""
        return math.floor((1.0 - mota) * self.labels + 1e-9) - self._misses(recall)

    def min_recall(self, mota: float) -> float:
        """The recall a tracker that reports every unlabelled person needs to reach
        ``mota`` (above 1: not reachable)."""
        misses = math.floor((1.0 - mota) * self.labels + 1e-9) - self.unlabelled
        return (self.labels - misses) / self.labels

    def _misses(self, recall: float) -> int:
        return self.labels - math.ceil(recall * self.labels - 1e-9)


def oracle(
    labels: Mapping[int, Mapping[int, np.ndarray]], shown: int, seen: list[Unlabelled]
) -> Oracle:
    """:class:`Oracle` of the ``labels``, the ``shown`` of them (:func:`labels_shown`) and
    the unlabelled people ``seen`` on their scans."""
    return Oracle(
        labels=sum(len(p) for p in labels.values()),
        shown=shown,
        scans=len(labels),
        beside=sum(bool(u.beside) for u in seen),
        unlabelled=sum(len(u.beside) + len(u.others) for u in seen),
    )
