"""The compiled listing (``_clisting.c``; see :mod:`laserpeople.tracking.mht.compiled`)."""

from collections.abc import Sequence
from types import NotImplementedType

from laserpeople.tracking.mht.matrix import LabelledAssignment

SOURCE_HASH: str

def setup(
    labelled_assignment: type[LabelledAssignment],
    max_listed_measurements: int,
    track_labels: tuple[int, int, int],
    measurement_labels: tuple[int, int, int],
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
