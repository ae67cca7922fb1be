"""Several lasers in one frame: known mounts, or mounts estimated from the data (004 Sec. 2).

004 aligns all lasers in a global frame before anything else. When the mounts are known
(tf, ``--mount``, a TOML file written by :func:`write_mounts`) nothing is estimated. When
they are not, the pose of each laser in the frame of a reference laser is found by
point-to-line ICP over scipy's KD-tree:

- static lasers (``static=True``): each laser's static background, the per-beam median
  range over its scans, is registered to the reference laser's;
- lasers on a moving robot: scans of the two lasers taken within ``max_pair_dt`` of each
  other are registered jointly (one pose for all pairs).

Each source point is matched to its nearest target point within a shrinking distance; the
target's local line (normal from the ``normal_neighbours`` nearest target points) gives the
residual n . (R p + t - q), and one Gauss-Newton step on (x, y, theta) per iteration
minimises their sum of squares. Without an initial pose a coarse search over headings
(every ``coarse_step``), each with the translation most point pairs agree on, gives the
starts; the refined pose that explains most points wins. The RMS residual of the matched
points is reported.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from laserpeople.config import param
from laserpeople.errors import ConfigError, LaserPeopleError
from laserpeople.scan import Pose2D, Scan, wrap_angle

FloatArray = NDArray[np.float64]


class AlignmentError(LaserPeopleError):
    """Lasers cannot be aligned (too few overlapping points, a laser missing)."""


@dataclass(frozen=True)
class AlignmentParams:
    """Parameters of the laser alignment by point-to-line ICP."""

    config_section = "alignment"

    iterations: int = param(40, "assumed", "ICP iterations per start")
    max_distance: float = param(
        0.5, "assumed", "largest point-to-point match distance at the first iteration", "m"
    )
    min_distance: float = param(
        0.08, "assumed", "the match distance shrinks to this by the last iteration", "m"
    )
    normal_neighbours: int = param(6, "assumed", "target points per local line fit")
    max_pair_dt: float = param(
        0.05,
        "assumed: the MiR bag's two lasers scan ~33 ms apart (< 5 cm of motion at 1 m/s)",
        "largest stamp gap of a scan pair",
        "s",
    )
    max_pairs: int = param(40, "assumed", "scan pairs used (evenly spread over the recording)")
    coarse_step: float = param(
        math.radians(3.0), "assumed", "heading step of the coarse search", "rad"
    )
    coarse_points: int = param(150, "assumed", "points per laser in the coarse search")
    coarse_cell: float = param(0.1, "assumed", "displacement bin of the coarse search", "m")
    coarse_starts: int = param(12, "assumed", "best coarse poses refined by ICP")
    explained_distance: float = param(
        0.05, "assumed", "a point this close to the other laser's points is explained", "m"
    )


@dataclass(frozen=True)
class Alignment:
    """The estimated mount of one laser.

    Attributes:
        sensor: The laser.
        reference: The laser whose frame ``pose`` is in.
        pose: Pose of ``sensor`` in ``reference``'s frame.
        residual: RMS point-to-line distance of the matched points [m].
        explained: Share of ``sensor``'s points within ``explained_distance`` of the
            reference laser's points.
        matches: Number of matched points in the last iteration.
        pairs: Scan pairs (or 1 for static backgrounds) used.
    """

    sensor: str
    reference: str
    pose: Pose2D
    residual: float
    explained: float
    matches: int
    pairs: int


def line_normals(points: FloatArray, k: int) -> FloatArray:
    """Unit normals (N, 2) of the line through each point's ``k`` nearest neighbours
    (smallest principal direction, closed form); NaN where fewer than 3 points exist."""
    n = len(points)
    if n < 3:
        return np.full((n, 2), np.nan)
    k = min(k, n)
    _, idx = cKDTree(points).query(points, k=k)
    nb = points[idx]
    d = nb - nb.mean(axis=1, keepdims=True)
    sxx = np.einsum("nk,nk->n", d[..., 0], d[..., 0])
    syy = np.einsum("nk,nk->n", d[..., 1], d[..., 1])
    sxy = np.einsum("nk,nk->n", d[..., 0], d[..., 1])
    # principal (line) direction angle; the normal is perpendicular to it
    phi = 0.5 * np.arctan2(2.0 * sxy, sxx - syy)
    return np.column_stack([-np.sin(phi), np.cos(phi)])


@dataclass
class _Target:
    points: FloatArray
    normals: FloatArray
    tree: cKDTree


def _targets(sets: Sequence[FloatArray], k: int) -> list[_Target]:
    return [_Target(p, line_normals(p, k), cKDTree(p)) for p in sets]


def _transform(pose: FloatArray, pts: FloatArray) -> FloatArray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.asarray(pts @ np.array([[c, s], [-s, c]]) + pose[:2], dtype=np.float64)


def _icp(
    sources: Sequence[FloatArray],
    targets: Sequence[_Target],
    start: FloatArray,
    iterations: int,
    p: AlignmentParams,
) -> tuple[FloatArray, float, int]:
    """Point-to-line ICP of all pairs at once from ``start`` (x, y, theta)."""
    pose = np.array(start, dtype=np.float64)
    resid, matches = math.inf, 0
    for it in range(iterations):
        frac = it / max(iterations - 1, 1)
        gate = p.max_distance * (p.min_distance / p.max_distance) ** frac
        rows_j, rows_r = [], []
        for src, tgt in zip(sources, targets, strict=True):
            moved = _transform(pose, src)
            d, j = tgt.tree.query(moved, k=1, distance_upper_bound=gate)
            ok = np.isfinite(d)
            if not ok.any():
                continue
            q, n, m = tgt.points[j[ok]], tgt.normals[j[ok]], moved[ok]
            good = np.isfinite(n).all(axis=1)
            q, n, m = q[good], n[good], m[good]
            r = np.einsum("nc,nc->n", n, m - q)
            # d/dtheta of a rotation of the moved points m about the target origin
            dm = np.column_stack([-m[:, 1], m[:, 0]])
            rows_j.append(np.column_stack([n[:, 0], n[:, 1], np.einsum("nc,nc->n", n, dm)]))
            rows_r.append(r)
        if not rows_j:
            return pose, math.inf, 0
        jac, res = np.concatenate(rows_j), np.concatenate(rows_r)
        matches = res.size
        resid = float(np.sqrt(np.mean(res * res)))
        if matches < 3:
            return pose, math.inf, matches
        step, *_ = np.linalg.lstsq(jac, -res, rcond=None)
        # the increment (dx, dy, dtheta) acts on the transformed points: compose on the left
        c, s = math.cos(step[2]), math.sin(step[2])
        x, y = pose[0], pose[1]
        pose = np.array([c * x - s * y + step[0], s * x + c * y + step[1], pose[2] + step[2]])
        if np.abs(step[:2]).max() < 1e-6 and abs(step[2]) < 1e-7:
            break
    pose[2] = float(wrap_angle(pose[2]))
    return pose, resid, matches


def _explained(
    sources: Sequence[FloatArray], targets: Sequence[_Target], pose: FloatArray, dist: float
) -> float:
    total, hit = 0, 0
    for src, tgt in zip(sources, targets, strict=True):
        d, _ = tgt.tree.query(_transform(pose, src), k=1)
        total += len(src)
        hit += int(np.count_nonzero(d <= dist))
    return hit / total if total else 0.0


def _coarse_starts(
    sources: Sequence[FloatArray], targets: Sequence[FloatArray], p: AlignmentParams
) -> list[FloatArray]:
    """Starting poses by voting: for each heading (every ``coarse_step``) the displacements
    between up to ``coarse_points`` target points and rotated source points are binned on a
    ``coarse_cell`` grid; the fullest bins over all headings are the starts."""
    src = _subsample(np.concatenate(list(sources)), p.coarse_points)
    tgt = _subsample(np.concatenate(list(targets)), p.coarse_points)
    found: list[tuple[float, FloatArray]] = []
    for th in np.arange(-math.pi, math.pi, p.coarse_step):
        rotated = _transform(np.array([0.0, 0.0, th]), src)
        disp = (tgt[:, None, :] - rotated[None, :, :]).reshape(-1, 2)
        cells = np.floor(disp / p.coarse_cell).astype(np.int64)
        lo = cells.min(axis=0)
        width = int(cells[:, 1].max() - lo[1]) + 1
        flat = (cells[:, 0] - lo[0]) * width + (cells[:, 1] - lo[1])
        counts = np.bincount(flat)
        for b in np.argsort(counts)[-2:]:
            t = (np.array([b // width, b % width]) + lo + 0.5) * p.coarse_cell
            found.append((float(counts[b]), np.array([t[0], t[1], th])))
    found.sort(key=lambda e: -e[0])
    return [pose for _, pose in found[: p.coarse_starts]]


def _subsample(points: FloatArray, n: int) -> FloatArray:
    if len(points) <= n:
        return points
    return points[np.linspace(0, len(points) - 1, n).round().astype(int)]


def register_point_sets(
    sources: Sequence[FloatArray],
    targets: Sequence[FloatArray],
    initial: Pose2D | None = None,
    params: AlignmentParams | None = None,
) -> tuple[Pose2D, float, float, int]:
    """The pose T with T(source_k) on target_k for every pair k (points (N, 2) in each
    laser's own frame). Returns (T, RMS residual [m], explained share, matches)."""
    p = params or AlignmentParams()
    if not sources or any(len(s) < 3 for s in sources) or any(len(t) < 3 for t in targets):
        raise AlignmentError("too few points to align", hint="use scans that see walls")
    tg = _targets(targets, p.normal_neighbours)
    starts = [initial.as_array()] if initial is not None else _coarse_starts(sources, targets, p)
    if len(starts) > 1:  # rank the starts on a few pairs, refine the best on all of them
        few = np.linspace(0, len(sources) - 1, min(5, len(sources))).round().astype(int)
        s_few, t_few = [sources[i] for i in few], [tg[i] for i in few]
        ranked = []
        for start in starts:
            pose, _, _ = _icp(s_few, t_few, start, p.iterations // 2, p)
            ranked.append((_explained(s_few, t_few, pose, p.explained_distance), pose))
        starts = [max(ranked, key=lambda e: e[0])[1]]
    best: tuple[float, FloatArray, float, int] | None = None
    for start in starts:
        pose, resid, matches = _icp(sources, tg, start, p.iterations, p)
        share = _explained(sources, tg, pose, p.explained_distance)
        if best is None or share > best[0]:
            best = (share, pose, resid, matches)
    assert best is not None
    share, pose, resid, matches = best
    return Pose2D.from_array(pose), resid, share, matches


def background_points(scans: Iterable[Scan]) -> FloatArray:
    """The static background of one static laser: per-beam median of the valid ranges over
    ``scans``, as points (K, 2) in the laser frame."""
    ranges, first = [], None
    for s in scans:
        first = first or s
        ranges.append(np.where(s.valid, s.ranges, np.nan))
    if first is None:
        raise AlignmentError("no scans of the laser", hint="check the topic names")
    with np.errstate(all="ignore"):
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            med = np.nanmedian(np.stack(ranges), axis=0)
    ok = np.isfinite(med)
    a = first.angles[ok]
    return np.column_stack([med[ok] * np.cos(a), med[ok] * np.sin(a)])


def scan_pairs(
    scans: Iterable[Scan], sensor: str, reference: str, max_dt: float, max_pairs: int
) -> list[tuple[Scan, Scan]]:
    """Pairs (sensor scan, reference scan) taken within ``max_dt`` [s] of each other,
    at most ``max_pairs`` spread evenly over the recording."""
    mine = [s for s in scans if s.sensor in (sensor, reference)]
    ref = [s for s in mine if s.sensor == reference]
    src = [s for s in mine if s.sensor == sensor]
    if not ref or not src:
        missing = reference if not ref else sensor
        raise AlignmentError(f"no scans of laser {missing!r}", hint="check the topic names")
    stamps = np.array([s.stamp for s in ref])
    pairs = []
    for s in src:
        k = int(np.argmin(np.abs(stamps - s.stamp)))
        if abs(stamps[k] - s.stamp) <= max_dt:
            pairs.append((s, ref[k]))
    if len(pairs) > max_pairs:
        pick = np.linspace(0, len(pairs) - 1, max_pairs).round().astype(int)
        pairs = [pairs[i] for i in pick]
    return pairs


def align_lasers(
    scans: Sequence[Scan],
    reference: str | None = None,
    *,
    static: bool = False,
    initial: Mapping[str, Pose2D] | None = None,
    params: AlignmentParams | None = None,
) -> dict[str, Alignment]:
    """Estimate the pose of every laser in the frame of ``reference`` (default: the first
    laser seen). ``initial`` gives starting poses (else a coarse search runs)."""
    p = params or AlignmentParams()
    names = list(dict.fromkeys(s.sensor for s in scans))
    if len(names) < 2:
        raise AlignmentError(
            f"need two lasers to align, found {len(names)}" + (f" ({names[0]})" if names else ""),
            hint="give a recording of several lasers that see the same walls",
        )
    ref = reference or names[0]
    if ref not in names:
        raise AlignmentError(
            f"no laser {ref!r} in the recording", hint=f"choose one of {', '.join(names)}"
        )
    out: dict[str, Alignment] = {}
    for name in names:
        if name == ref:
            continue
        if static:
            src = [background_points(s for s in scans if s.sensor == name)]
            tgt = [background_points(s for s in scans if s.sensor == ref)]
            n_pairs = 1
        else:
            pairs = scan_pairs(scans, name, ref, p.max_pair_dt, p.max_pairs)
            if not pairs:
                raise AlignmentError(
                    f"no scans of {name!r} and {ref!r} within {p.max_pair_dt * 1000:.0f} ms",
                    hint="pass --static for static lasers",
                )
            src = [a.valid_points()[0] for a, _ in pairs]
            tgt = [b.valid_points()[0] for _, b in pairs]
            n_pairs = len(pairs)
        start = None if initial is None else initial.get(name)
        pose, resid, share, matches = register_point_sets(src, tgt, start, p)
        out[name] = Alignment(name, ref, pose, resid, share, matches, n_pairs)
    return out


@dataclass(frozen=True)
class Mount:
    """A laser's mount in a parent frame, as estimated (or given, for the reference).

    Attributes:
        laser: The laser's frame (topic / frame id).
        parent: The parent frame of ``pose``.
        pose: The laser's pose in ``parent``.
        fit: The alignment behind the estimate (None for a given reference mount).
        given: The mount given on input for comparison, if any.
    """

    laser: str
    parent: str
    pose: Pose2D
    fit: Alignment | None
    given: Pose2D | None = None


def align_recording(
    path: str | Path,
    *,
    reference: str | None = None,
    static: bool = False,
    mounts: Mapping[str, tuple[str, Pose2D]] | None = None,
    params: AlignmentParams | None = None,
    notes: list[str] | None = None,
) -> list[Mount]:
    """Estimate the mounts of the lasers of the recording at ``path``.

    Poses are estimated in the frame of ``reference`` (default: the first laser). When
    ``mounts`` (laser -> (parent, pose), e.g. from ``--mount mir100``) holds the reference
    laser, every estimate is expressed in that parent frame and the other given mounts
    are the ICP's initial poses and are reported beside the estimates.

    In a ROS bag a laser is named by its scans' ``header.frame_id`` (what ``track
    --mount`` reads), else by its sensor name; ``reference`` may also be its topic. A
    given mount that names no laser is appended to ``notes`` (when given) and not used.
    """
    from laserpeople.io import open_recording
    from laserpeople.io.poses import normalise_frame, stray_mount_notes

    rec = open_recording(path, poses=False) if _is_bag(path) else open_recording(path)
    try:
        scans = list(rec.scans())
        frame_ids: dict[str, str] = getattr(rec, "laser_frames", dict)()  # topic -> frame id
    finally:
        rec.close()
    rename = {s.sensor: frame_ids.get(s.sensor, s.sensor) for s in scans}
    if frame_ids:
        scans = [replace(s, sensor=rename[s.sensor]) for s in scans]
        given = {
            normalise_frame(k): (normalise_frame(p), q) for k, (p, q) in (mounts or {}).items()
        }
    else:
        given = dict(mounts or {})
    names = list(dict.fromkeys(s.sensor for s in scans))
    if notes is not None and frame_ids:
        notes += stray_mount_notes(given, frame_ids)
    if reference is not None and frame_ids:  # a topic or a frame id
        reference = rename.get(reference, normalise_frame(reference))
    ref = reference or next((n for n in names if n in given), names[0] if names else "")
    anchor = given.get(ref)
    initial = None
    if anchor is not None:
        initial = {
            n: anchor[1].inverse().compose(given[n][1])
            for n in names
            if n in given and given[n][0] == anchor[0]
        }
    try:
        fits = align_lasers(scans, ref, static=static, initial=initial, params=params)
    except AlignmentError as exc:
        raise exc.located(path) from exc.__cause__
    out = []
    if anchor is not None:
        out.append(Mount(ref, anchor[0], anchor[1], None, anchor[1]))
    for name, fit in fits.items():
        if anchor is None:
            out.append(Mount(name, ref, fit.pose, fit))
        else:
            other = given.get(name)
            out.append(
                Mount(
                    name,
                    anchor[0],
                    anchor[1].compose(fit.pose),
                    fit,
                    other[1] if other is not None and other[0] == anchor[0] else None,
                )
            )
    return out


def _is_bag(path: str | Path) -> bool:
    return Path(path).suffix.lower() in {".bag", ".db3", ".mcap"} or Path(path).is_dir()


def write_mounts(path: str | Path, mounts: Sequence[Mount], source: str = "") -> Path:
    """Write mounts as TOML: one ``[mounts.LASER]`` table each with ``parent``, ``x``,
    ``y`` [m], ``theta`` [rad] and, for estimates, the fit's ``residual_m``, ``explained``
    and ``scan_pairs``."""
    lines = [f"# laser mounts estimated by `laserpeople align` {source}".rstrip(), ""]
    for m in mounts:
        lines += [
            f'[mounts."{m.laser}"]',
            f'parent = "{m.parent}"',
            f"x = {m.pose.x:.6f}",
            f"y = {m.pose.y:.6f}",
            f"theta = {m.pose.theta:.6f}",
        ]
        if m.fit is None:
            lines.append("given = true")
        else:
            lines += [
                f"residual_m = {m.fit.residual:.6f}",
                f"explained = {m.fit.explained:.4f}",
                f"scan_pairs = {m.fit.pairs}",
            ]
        lines.append("")
    from laserpeople.io.paths import write_text_file

    return write_text_file(path, "\n".join(lines), "mounts")


def read_mounts(path: str | Path) -> dict[str, tuple[str, Pose2D]]:
    """Mounts (child -> (parent, pose)) from a TOML file written by :func:`write_mounts`
    (or by hand), in the form ``laserpeople.io.poses.add_mounts`` takes."""
    from laserpeople.config import read_toml
    from laserpeople.io.poses import mount_pose

    p = Path(path)
    data = read_toml(p, "mounts file")
    table = data.get("mounts")
    if not isinstance(table, dict) or not table:
        raise ConfigError(
            "no [mounts.LASER] table in the mounts file",
            path=p,
            hint="write it with laserpeople align -o mounts.toml",
        )
    out: dict[str, tuple[str, Pose2D]] = {}
    for child, entry in table.items():
        try:
            parent = str(entry["parent"])
            x, y, theta = (float(entry[k]) for k in ("x", "y", "theta"))
        except (KeyError, TypeError, ValueError) as exc:
            raise ConfigError(
                f"mount {child!r} needs parent, x, y and theta ({exc})", path=p
            ) from exc
        out[child] = (parent, mount_pose(x, y, theta, what=f"mount {child!r}", path=p))
    return out


__all__ = [
    "Alignment",
    "AlignmentError",
    "AlignmentParams",
    "Mount",
    "align_lasers",
    "align_recording",
    "background_points",
    "line_normals",
    "read_mounts",
    "register_point_sets",
    "scan_pairs",
    "write_mounts",
]
