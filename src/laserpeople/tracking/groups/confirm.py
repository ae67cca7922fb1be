"""Track confirmation of the group tracker's reports (an extension of 000 Sec. 4).

000 reports every group of the best hypothesis in every scan; on real recordings that
shows ids living 1-3 scans (flicker at wall edges, short merges of walkers passing each
other). Here a *family* (one group identity of the MHT) is reported once it has been in
the best hypothesis in at least ``scans`` of the last ``window`` scans, and from then on
for as long as it is there. A family made by a split or merge whose labels come from a
group already reported (its people were reported) waits ``event_scans`` instead. The MHT
itself (hypotheses, scores, pruning) does not see any of this.

What it remembers is bounded by what is alive (:meth:`Confirmation.prune`): families and
label roots that no track of any hypothesis carries any more can never be asked again.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class ConfirmSettings:
    """When a family of the best hypothesis is reported.

    Attributes:
        scans: Scans in the best hypothesis (within ``window``) before a family born from
            an observation is reported (1: at once, as 000).
        window: The last scans ``scans`` are counted over (``scans``: consecutive).
        event_scans: The same for a family made by a split or merge of which some label
            comes from a group already reported.
    """

    scans: int = 1
    window: int = 1
    event_scans: int = 1

    def __post_init__(self) -> None:
        if self.scans < 1 or self.event_scans < 1:
            raise ValueError("confirm_scans and confirm_event_scans must be at least 1")
        if self.window < max(self.scans, self.event_scans):
            raise ValueError(
                "confirm_window must be at least confirm_scans and confirm_event_scans"
            )


@dataclass(frozen=True)
class Candidate:
    """One group of the best hypothesis in one scan.

    Attributes:
        family: Its family (track identity).
        event: "split" or "merge" when a model made the family, "" when born.
        labels: Its internal label set (roots are the families of born groups).
        visible: False when another rule hides it this scan (it still counts as present).
    """

    family: int
    event: str
    labels: tuple[str, ...]
    visible: bool = True


class Confirmation:
    """Which families of the best hypothesis are reported (see the module doc)."""

    def __init__(self, settings: ConfirmSettings) -> None:
        self.s = settings
        self._confirmed: set[int] = set()
        self._seen: dict[int, deque[int]] = {}  # unconfirmed family -> scans it was present
        self._roots: set[str] = set()  # label roots of the groups reported so far
        self.withheld_born = 0
        """Group-scans of families born from an observation not reported yet (visible ones)."""
        self.withheld_event = 0
        """Group-scans of families made by a split or merge not reported yet (visible ones)."""

    @property
    def withheld(self) -> int:
        """Visible group-scans not reported because their family was not confirmed yet."""
        return self.withheld_born + self.withheld_event

    def select(self, index: int, candidates: Sequence[Candidate]) -> list[bool]:
        """Whether each of scan ``index``'s ``candidates`` is reported (visible and its
        family confirmed); counts the visible ones withheld."""
        out = []
        for c in candidates:
            confirmed = c.family in self._confirmed or self._confirm(index, c)
            if c.visible and not confirmed:
                if c.event:
                    self.withheld_event += 1
                else:
                    self.withheld_born += 1
            reported = c.visible and confirmed
            if reported:
                self._roots.update(label.partition("-")[0] for label in c.labels)
            out.append(reported)
        if len(self._seen) > 4 * (len(candidates) + 1):  # forget families gone for long
            self._seen = {f: s for f, s in self._seen.items() if index - s[-1] < self.s.window}
        return out

    def confirm(self, family: int) -> None:
        """Report ``family`` from now on, without waiting (it takes the place of a group
        reported before)."""
        self._confirmed.add(family)
        self._seen.pop(family, None)

    def is_confirmed(self, family: int) -> bool:
        """True once ``family`` is reported whenever it is in the best hypothesis."""
        return family in self._confirmed

    def prune(self, families: Iterable[int], roots: Iterable[str] | None = None) -> None:
        """Forget the confirmed families not in ``families`` and, when given, the label
        roots not in ``roots``: the families and roots of every track still alive in some
        hypothesis. Family ids are never reused, and every label a track will carry comes
        from its own family or from the labels of tracks alive now (splits append to them,
        merges unite them), so nothing forgotten can be asked again and :meth:`select`
        answers as before."""
        self._confirmed.intersection_update(families)
        if roots is not None:
            self._roots.intersection_update(roots)

    def sizes(self) -> dict[str, int]:
        """How many families and roots are remembered (for soak tests)."""
        return {
            "confirmed": len(self._confirmed),
            "seen": len(self._seen),
            "reported_roots": len(self._roots),
        }

    def _confirm(self, index: int, c: Candidate) -> bool:
        """Count scan ``index`` for ``c``'s family; True (and remembered) once confirmed."""
        wait = self.s.scans
        if c.event and any(label.partition("-")[0] in self._roots for label in c.labels):
            wait = self.s.event_scans
        seen = self._seen.get(c.family)
        if seen is None:
            seen = self._seen[c.family] = deque(maxlen=self.s.window)
        if not seen or seen[-1] != index:
            seen.append(index)
        if sum(1 for k in seen if index - k < self.s.window) < wait:
            return False
        self._confirmed.add(c.family)
        del self._seen[c.family]
        return True


__all__ = ["Candidate", "ConfirmSettings", "Confirmation"]
