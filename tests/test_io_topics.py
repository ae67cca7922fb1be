"""Matching requested topic names against a recording's (shared by the bag and CARMEN readers)."""

from __future__ import annotations

import pytest

from laserpeople.errors import TopicNotFoundError
from laserpeople.io.topics import match_topics


def _bare(name: str) -> str:
    return name.lstrip("/")


def test_exact_name_wins_then_the_key_decides_and_repeats_are_dropped() -> None:
    available = ["scan", "/scan", "/front"]
    got = match_topics(
        ["/scan", "front", "scan", "/front"],
        available,
        key=_bare,
        path="x.bag",
        what="topic",
        hint="",
    )
    assert got == ["/scan", "/front", "scan"]


def test_a_missing_name_is_reported_with_the_hint() -> None:
    with pytest.raises(
        TopicNotFoundError, match=r"x\.log: no laser 'ODOM' \(lasers here: FLASER\)"
    ):
        match_topics(
            ["flaser", "ODOM"],
            ["FLASER"],
            key=str.upper,
            path="x.log",
            what="laser",
            hint="lasers here: FLASER",
        )
