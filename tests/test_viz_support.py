"""Small synthetic scenes for the viz tests: a room, a scanner, two walking people.

No tests live here; the other ``test_viz_*`` files import these builders.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from laserpeople.io import write_recording
from laserpeople.io.tracks_csv import TracksCsvWriter
from laserpeople.scan import Pose2D, Scan
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame
from laserpeople.viz.figure import AXES_BOX
from laserpeople.viz.geometry import square_extent

ROOM = (-4.0, 6.0, -3.0, 5.0)  # xmin, xmax, ymin, ymax [m]
SENSOR = Pose2D(0.5, 1.0, 0.3)
N_BEAMS = 360
RADIUS = 0.2
DT = 0.1


def people_at(k: int) -> np.ndarray:
    """World positions (2, 2) of the two people at scan k."""
    t = k * DT
    return np.array([[-2.0 + 0.8 * t, 3.0], [4.0, -1.5 + 0.5 * t]])


def ray_cast(pose: Pose2D, angles: np.ndarray, circles: np.ndarray) -> np.ndarray:
    """Ranges of rays from ``pose`` (sensor-frame ``angles``) to the room walls and circles."""
    world = angles + pose.theta
    d = np.stack([np.cos(world), np.sin(world)], axis=1)
    o = np.array([pose.x, pose.y])
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(d[:, 0] > 0, (ROOM[1] - o[0]) / d[:, 0], (ROOM[0] - o[0]) / d[:, 0])
        ty = np.where(d[:, 1] > 0, (ROOM[3] - o[1]) / d[:, 1], (ROOM[2] - o[1]) / d[:, 1])
    r = np.minimum(np.where(np.isfinite(tx), tx, np.inf), np.where(np.isfinite(ty), ty, np.inf))
    for c in circles:
        oc = o - c
        b = d @ oc
        disc = b * b - (oc @ oc - RADIUS**2)
        hit = disc >= 0
        t = -b - np.sqrt(np.where(hit, disc, 0.0))
        r = np.where(hit & (t > 0) & (t < r), t, r)
    return r


def make_scans(n: int, pose: Pose2D | None = SENSOR) -> list[Scan]:
    """``n`` scans of the room with the two people, sensor at ``pose`` (None: no pose)."""
    inc = 2 * np.pi / N_BEAMS
    angles = -np.pi + inc + np.arange(N_BEAMS) * inc
    p = pose if pose is not None else Pose2D()
    return [
        Scan(
            stamp=100.0 + k * DT,
            angle_min=float(angles[0]),
            angle_increment=inc,
            ranges=ray_cast(p, angles, people_at(k)),
            range_max=20.0,
            pose=pose,
            index=k,
            sensor="front",
        )
        for k in range(n)
    ]


def make_tracks(n: int) -> list[Tracks]:
    """Perfect person tracks (ids 3 and 8) plus a group track (id 1) of both from scan 2 on."""
    out = []
    for k in range(n):
        pos = people_at(k)
        tracks = [
            Track(3, "person", pos[0], [0.8, 0.0], np.diag([0.04, 0.01])),
            Track(8, "person", pos[1], [0.0, 0.5], np.diag([0.01, 0.04])),
        ]
        if k >= 2:
            centre = pos.mean(axis=0)
            contour = np.array([pos[0] + [0, 0.4], pos[1] + [0.4, 0], pos[1] - [0, 0.4]])
            tracks.append(
                Track(1, "group", centre, [0.4, 0.25], np.eye(2) * 0.2, 2, "3|8", contour=contour)
            )
        out.append(Tracks(100.0 + k * DT, k, tuple(tracks), "world", SENSOR))
    return out


def make_truth(n: int) -> list[TruthFrame]:
    """Truth frames for the two people (ids 0 and 1)."""
    return [
        TruthFrame.from_positions(100.0 + k * DT, k, np.array([0, 1]), people_at(k))
        for k in range(n)
    ]


def write_scene(tmp: Path, n: int = 12) -> tuple[Path, Path]:
    """A recording with truth and a tracks CSV (world frame) in ``tmp``."""
    rec = write_recording(tmp / "scene.npz", make_scans(n), make_truth(n), {"test": True})
    csv = tmp / "tracks.csv"
    with TracksCsvWriter(csv, frame="world") as w:
        for t in make_tracks(n):
            w.write(t)
    return rec, csv


def pixel_of(
    xy: np.ndarray, extent: tuple[float, float, float, float], size: tuple[int, int]
) -> tuple[int, int]:
    """Where a point lands in the picture, computed from the layout alone."""
    box_w, box_h = AXES_BOX[2] * size[0], AXES_BOX[3] * size[1]
    x0, x1, y0, y1 = square_extent(extent, (box_w, box_h))
    col = AXES_BOX[0] * size[0] + (xy[0] - x0) / (x1 - x0) * box_w
    row = size[1] - (AXES_BOX[1] * size[1] + (xy[1] - y0) / (y1 - y0) * box_h)
    return round(col), round(row)


def near_colour(
    img: np.ndarray, col: int, row: int, rgb: tuple[int, int, int], r: int = 2, tol: int = 3
) -> bool:
    """Whether some pixel within ``r`` px of ``(col, row)`` has every channel within ``tol``
    of ``rgb``."""
    patch = img[row - r : row + r + 1, col - r : col + r + 1].astype(int)
    return bool(np.any(np.all(np.abs(patch - np.array(rgb)) <= tol, axis=-1)))
