"""The compiled segment features and AdaBoost margins (``_cfeatures.c``; see
:mod:`laserpeople.detection.compiled`)."""

import numpy as np
from numpy.typing import NDArray

SOURCE_HASH: str

def pass1(
    points: NDArray[np.float64],
    offsets: NDArray[np.int64],
    tables: NDArray[np.int64],
    circle: NDArray[np.int64],
    changes: list[
        tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], float]
        | None
    ]
    | None,
    no_neighbour_jump: float,
    out: NDArray[np.float64],
    centres: NDArray[np.float64],
    max_motion: NDArray[np.float64],
    work: NDArray[np.float64],
    ys: NDArray[np.float64],
    xs: NDArray[np.float64],
    defer: bool,
    /,
) -> int: ...
def pass2(
    points: NDArray[np.float64],
    offsets: NDArray[np.int64],
    tables: NDArray[np.int64],
    flip: NDArray[np.int64],
    angles: NDArray[np.float64],
    no_circle_radius: float,
    out: NDArray[np.float64],
    centres: NDArray[np.float64],
    work: NDArray[np.float64],
    circle_centres: NDArray[np.float64],
    defer: bool,
    /,
) -> None: ...
def complete(
    points: NDArray[np.float64],
    offsets: NDArray[np.int64],
    rows: NDArray[np.int64],
    centres: NDArray[np.float64],
    work: NDArray[np.float64],
    out: NDArray[np.float64],
    /,
) -> None: ...
def jumps(points: NDArray[np.float64], threshold: float, out: NDArray[np.bool_], /) -> None: ...
def stump_sums(
    X: NDArray[np.float64],
    columns: NDArray[np.int64],
    group_column: NDArray[np.int64],
    right: NDArray[np.bool_],
    grid: NDArray[np.float64],
    values: NDArray[np.float64],
    out: NDArray[np.float64],
    /,
) -> None: ...
def segment(
    points: NDArray[np.float64],
    beams: NDArray[np.int64],
    bounds: NDArray[np.int64],
    wrap: NDArray[np.int64],
    threshold: float,
    /,
) -> tuple[bytes, bytes, bytes, bytes]: ...
def sparse(
    offsets: NDArray[np.int64],
    beams: NDArray[np.int64],
    points: NDArray[np.float64],
    table_starts: NDArray[np.int64],
    ranges: list[NDArray[np.float64]],
    valid: list[NDArray[np.bool_]],
    increment: NDArray[np.float64],
    full: NDArray[np.int64],
    min_points: int,
    leg_width: float,
    jump_distance: float,
    /,
) -> bytes: ...
def scan_points(
    ranges: NDArray[np.float64],
    range_min: float,
    range_max: float,
    cos: NDArray[np.float64],
    sin: NDArray[np.float64],
    /,
) -> tuple[bytearray, bytes, bytes, bytes]: ...
