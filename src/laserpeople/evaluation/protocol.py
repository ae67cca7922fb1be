"""The metric protocol: feed frames one by one, then ask for the numbers."""

from __future__ import annotations

from typing import Protocol, TypeVar, runtime_checkable

from laserpeople.evaluation.detail import FrameTable
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

R_co = TypeVar("R_co", covariant=True)


@runtime_checkable
class Metric(Protocol[R_co]):
    """A tracking metric, fed one scored frame at a time.

    ``accumulate`` takes the ground truth of one scan and the tracks the tracker reported for
    that same scan (``None`` or an empty :class:`Tracks` when it reported none: then every
    person of the frame is missed). ``result`` returns a frozen dataclass of numbers and may
    be called at any time; ``frames`` returns the per-frame detail.
    """

    def accumulate(self, truth_frame: TruthFrame, tracks: Tracks | None) -> None:
        """Score one frame."""
        ...

    def result(self) -> R_co:
        """The metric over all frames so far."""
        ...

    def frames(self) -> FrameTable:
        """One row per frame accumulated so far."""
        ...
