"""The compiled listing (``_clisting.c``; see :mod:`laserpeople.tracking.mht.compiled`)."""

from collections.abc import Callable, Hashable, Iterable, Sequence
from types import NotImplementedType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.tracking.mht.hypothesis import Hypothesis
from laserpeople.tracking.mht.matrix import LabelledAssignment
from laserpeople.tracking.mht.tracktree import TrackNode

SOURCE_HASH: str

def setup(
    labelled_assignment: type[LabelledAssignment],
    max_listed_measurements: int,
    track_labels: tuple[int, int, int],
    measurement_labels: tuple[int, int, int],
    listing_limit: int,
    listing_budget: int,
    /,
) -> None: ...
def list_children(
    priors: Sequence[float],
    rows: Sequence[Sequence[int]],
    tm: list[list[float]],
    c_occ: list[float],
    c_del: list[float],
    c_new: list[float],
    c_fal: list[float],
    k: int,
    max_gap: float,
    limit: int,
    shortcut: bool,
    budget: int,
    /,
) -> list[tuple[int, LabelledAssignment, float]] | NotImplementedType | None: ...
def k_best_plain(
    tracks_of: list[tuple[TrackNode, ...]],
    priors: list[float],
    row_of: dict[int, int],
    cost_live: NDArray[np.float64],
    meas_idx: list[int],
    occ_all: list[float],
    del_all: list[float],
    new_all: list[float],
    fal_all: list[float],
    k: int,
    max_gap: float,
    shortcut: bool,
    max_cluster_size: int,
    /,
) -> tuple[list[tuple[int, LabelledAssignment, float]], int] | NotImplementedType: ...
def components(
    fam_meas: dict[int, set[int]],
    links: Iterable[tuple[int, int]],
    n_meas: int,
    /,
) -> list[tuple[frozenset[int], list[int]]] | NotImplementedType: ...
def static_few(
    evidence: NDArray[np.float64],
    touched: NDArray[np.float64],
    since: NDArray[np.float64],
    first_sight: NDArray[np.bool_],
    o0: int,
    o1: int,
    xy: list[list[float]],
    resolution: float,
    n: int,
    stamp: float,
    decay_time: float,
    threshold: float,
    hold: float,
    extra: float,
    near: float,
    /,
) -> list[float] | NotImplementedType: ...
def grid_hits(
    points: NDArray[np.float64],
    touched: NDArray[np.float64],
    o0: int,
    o1: int,
    resolution: float,
    stamp: float,
    decay_time: float,
    hit_out: NDArray[np.int64],
    exponent_out: NDArray[np.float64],
    /,
) -> int | NotImplementedType: ...
def grid_mark(
    evidence: NDArray[np.float64],
    touched: NDArray[np.float64],
    since: NDArray[np.float64],
    first_sight: NDArray[np.bool_],
    seen_free: NDArray[np.float64],
    hit: NDArray[np.int64],
    factor: NDArray[np.float64],
    stamp: float,
    occupied: float,
    hit_evidence: float,
    max_evidence: float,
    arrival_window: float,
    casting: bool,
    cover: NDArray[np.int32] | None,
    hit_frame: NDArray[np.int64] | None,
    frame: int,
    cast_stamp: float,
    /,
) -> NotImplementedType | None: ...
def still_cast_usual(
    ids: NDArray[np.int64],
    listed: NDArray[np.int64],
    u: NDArray[np.float64],
    listed_u: NDArray[np.float64],
    n: NDArray[np.int64],
    listed_n: NDArray[np.int64],
    cells: NDArray[np.int64],
    cover: NDArray[np.int32],
    hit_frame: NDArray[np.int64],
    seen_free: NDArray[np.float64],
    hit: NDArray[np.int64],
    safe: NDArray[np.bool_],
    frame: int,
    stamp: float,
    tolerance: float,
    /,
) -> NotImplementedType | None: ...
def still_cast_apply(
    n_new: NDArray[np.int64],
    listed_n: NDArray[np.int64],
    cells: NDArray[np.int64],
    cover: NDArray[np.int32],
    hit_frame: NDArray[np.int64],
    seen_free: NDArray[np.float64],
    hit: NDArray[np.int64],
    lost: NDArray[np.int64] | None,
    frame: int,
    stamp: float,
    /,
) -> NotImplementedType | None: ...
def histogram_foreground(
    ranges: NDArray[np.float64],
    valid_beams: NDArray[np.int64],
    static: NDArray[np.bool_],
    nearest: NDArray[np.int64],
    candidate: NDArray[np.int64] | None,
    bin_width: float,
    reach: int,
    point_beams: NDArray[np.int64],
    fg_out: NDArray[np.bool_],
    /,
) -> bool | NotImplementedType: ...
def prune(
    hypotheses: list[Hypothesis], depth: int, min_ratio: float, /
) -> list[Hypothesis] | NotImplementedType: ...
def plan_plain(
    solutions: list[tuple[int, LabelledAssignment, float]],
    tracks_of: list[tuple[TrackNode, ...]],
    meas_list: list[int],
    measurements: Any,
    /,
) -> (
    tuple[list[tuple[TrackNode, Hashable, Any, int]], dict[Hashable, tuple[Any, int, int]]]
    | NotImplementedType
): ...
def assemble_plain(
    solutions: list[tuple[int, LabelledAssignment, float]],
    parents: list[Hypothesis],
    tracks_of: list[tuple[TrackNode, ...]],
    meas_list: list[int],
    new_nodes: dict[Hashable, TrackNode],
    occluded_child: Callable[[TrackNode, float], TrackNode],
    stamp: float,
    hypothesis: type[Hypothesis],
    n_scan: int,
    logaddexp: Callable[[float, float], Any],
    /,
) -> dict[tuple[int, ...], Hypothesis] | NotImplementedType: ...
def make_plain(
    pairs: list[tuple[TrackNode, Hashable, Any, int]],
    born: dict[Hashable, tuple[Any, int, int]],
    loglik: NDArray[np.float64],
    row_of: dict[int, int],
    node_type: type[TrackNode],
    new_node_id: Callable[[], int],
    new_family: Callable[[], int],
    stamp: float,
    deferred: NDArray[np.float64],
    detected: str,
    new_label: str,
    made: list[tuple[TrackNode, TrackNode, int]],
    births: list[tuple[TrackNode, int]],
    /,
) -> dict[Hashable, TrackNode] | NotImplementedType: ...
def detection_costs(
    gated: NDArray[np.bool_],
    loglik: NDArray[np.float64],
    lp: NDArray[np.float64],
    out: NDArray[np.float64],
    /,
) -> None: ...
def single_linkage_labels(
    points: NDArray[np.float64],
    mask: NDArray[np.bool_] | None,
    distance: float,
    min_points: int,
    labels_out: NDArray[np.int64],
    /,
) -> None: ...
def cluster_stats(
    points: NDArray[np.float64],
    labels: NDArray[np.int64],
    mean_out: NDArray[np.float64],
    cov_out: NDArray[np.float64],
    count_out: NDArray[np.int64],
    /,
) -> NotImplementedType | None: ...
def mean_shift_dense(
    points: NDArray[np.float64],
    bandwidth: float,
    tol: float,
    max_iter: int,
    radius: float,
    labels_out: NDArray[np.int64],
    centres_out: NDArray[np.float64],
    /,
) -> tuple[int, int] | NotImplementedType: ...
def cluster_links(
    points: NDArray[np.float64],
    labels: NDArray[np.int64],
    old: NDArray[np.float64],
    old_labels: NDArray[np.int64],
    reach: float,
    width: int,
    out: NDArray[np.int64],
    /,
) -> int | NotImplementedType: ...
def nearest_points(
    queries: NDArray[np.float64],
    refs: NDArray[np.float64],
    index_out: NDArray[np.int64],
    dist_out: NDArray[np.float64],
    /,
) -> NotImplementedType | None: ...
def close_pairs(
    points: NDArray[np.float64],
    radius: float,
    out: NDArray[np.int64],
    /,
) -> int | NotImplementedType: ...
