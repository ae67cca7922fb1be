"""The stage protocols of a pipeline and the check that a pipeline can feed its consumers.

A *stage* (preprocess or observe) reads some fields of a frame and returns a copy with
others filled in: ``stage(frame) -> frame``, declaring ``consumes`` and ``provides``. A
*tracker* (:class:`~laserpeople.frame.FrameTracker`) consumes fields and returns tracks;
an *identifier* refines the tracks' identities (colour re-identification);
a *sink* writes what comes out.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Protocol

from laserpeople.errors import ConfigError
from laserpeople.frame import Frame, FrameField
from laserpeople.tracks import Tracks


class Stage(Protocol):
    """A preprocess or observe stage."""

    consumes: frozenset[FrameField]
    provides: frozenset[FrameField]

    def __call__(self, frame: Frame) -> Frame:
        """``frame`` with the fields of :attr:`provides` filled in."""
        ...


class Identifier(Protocol):
    """An identify stage: keeps identities over time (e.g. by clothing colour, 002)."""

    consumes: frozenset[FrameField]

    def update(self, tracks: Tracks, frame: Frame) -> Tracks:
        """The tracks of ``frame`` with identities revised."""
        ...


class Sink(Protocol):
    """Where a pipeline's results go, frame by frame."""

    def write(self, frame: Frame, tracks: Tracks | None) -> None:
        """Write one frame's results (``tracks`` is None in a pipeline without a tracker)."""
        ...

    def close(self) -> None:
        """Finish the output (also after an error, unless the sink has an ``abandon()``
        method: then that is called instead after an error, and what it returns, if not
        None, is added to the error's message: e.g. that an older file was left as it
        was)."""
        ...


def provided_by(stage: object) -> frozenset[FrameField]:
    """What a stage fills in; a static world model (no ``provides``) fills ``foreground``."""
    provides = getattr(stage, "provides", None)
    if provides is None:
        return frozenset({"foreground"})
    return frozenset(provides)


def check_feeds(
    source_fields: Iterable[FrameField],
    stages: Iterable[object],
    consumers: Iterable[tuple[str, object]],
) -> frozenset[FrameField]:
    """Raise a ConfigError unless every stage and consumer gets the fields it consumes from
    the source or an earlier stage; returns the fields available after the stages.

    Args:
        source_fields: What the source fills (``scans``, and ``appearance`` for a source
            with a camera or the simulator).
        stages: The preprocess and observe stages, in order.
        consumers: ``(name, consumer)`` of the tracker and identifiers, run after the stages.
    """
    have: set[FrameField] = set(source_fields)
    for stage in stages:
        need = frozenset(getattr(stage, "consumes", frozenset()))
        missing = need - have
        if missing:
            raise ConfigError(
                f"stage {type(stage).__name__} consumes {', '.join(sorted(missing))}, "
                "which no earlier stage provides",
                hint="reorder the stages or add the one that provides it",
            )
        have |= provided_by(stage)
    for name, consumer in consumers:
        need = frozenset(getattr(consumer, "consumes", frozenset()))
        missing = need - have
        if missing:
            raise ConfigError(
                f"{name} consumes {', '.join(sorted(missing))}, but this pipeline provides "
                f"only {', '.join(sorted(have))}",
                hint=_how_to_provide(missing),
            )
    return frozenset(have)


_PROVIDERS: dict[str, str] = {
    "points": "a Fuse stage (preprocess)",
    "foreground": "a Fuse stage or a static world model (preprocess)",
    "clusters": "a ClusterPoints stage (observe)",
    "legs": "a DetectLegs stage (observe)",
    "appearance": "a source with appearance (a camera or the simulator)",
    "scans": "a source",
}


def _how_to_provide(missing: Iterable[str]) -> str:
    return "add " + "; ".join(f"{_PROVIDERS.get(m, m)} for {m}" for m in sorted(missing))


__all__ = ["Identifier", "Sink", "Stage", "check_feeds", "provided_by"]
