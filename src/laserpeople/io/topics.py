"""Matching the topic names a user asks for against the names a recording has."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import NoReturn

from laserpeople.errors import TopicNotFoundError
from laserpeople.spelling import did_you_mean


def match_topics(
    requested: Sequence[str],
    available: Sequence[str],
    *,
    key: Callable[[str], str],
    path: str | Path,
    what: str,
    hint: str,
) -> list[str]:
    """The available name for each requested one, in request order without repeats.

    A requested name matches an available name that equals it, or else the first one that
    is the same under ``key`` (for example without the leading ``/``). A name that matches
    none is an error naming the closest names (a misspelling, the start of a name).

    Args:
        requested: Names as the user gave them.
        available: Names in the recording.
        key: Normalisation under which two names are the same topic.
        path: The recording, for the error message.
        what: What a name names, for the error message (``"topic"``, ``"laser"``).
        hint: What to do when a name is missing (usually the names there are).

    Raises:
        TopicNotFoundError: A requested name matches no available name.
        TypeError: ``requested`` is one name (a string), which would be taken letter by
            letter; names what to give.
    """
    check_names(requested, what)
    out: list[str] = []
    for name in requested:
        found = name if name in available else None
        if found is None:
            found = next((a for a in available if key(a) == key(name)), None)
        if found is None:
            guess = did_you_mean(name, available, key=key, lead="; ")
            raise TopicNotFoundError(f"no {what} {name!r}{guess}", path=path, hint=hint)
        if found not in out:
            out.append(found)
    return out


def check_names(requested: object, what: str = "topic") -> None:
    """Refuse one name given where a list of names goes (``scans("/scan")``: its letters
    would be taken for topics, the first ``'/'`` said not found).

    Raises:
        TypeError: ``requested`` is a string; names what to give.
    """
    if isinstance(requested, str | bytes):
        raise TypeError(
            f"topics must be a list of {what} names (None: all of them), got the string "
            f"{requested!r}: give [{requested!r}]"
        )


def no_laser_topic(recording: object, path: str | Path) -> NoReturn:
    """Raise the error of a recording without a laser topic: a bag's own, which names the
    topics the bag has (``/chatter (std_msgs/msg/String)``), else a plain one.

    Raises:
        TopicNotFoundError: always.
    """
    resolve = getattr(recording, "resolve_topics", None)
    if callable(resolve):
        resolve(None)  # a bag's reader raises, naming its topics
    raise TopicNotFoundError("the recording has no laser topic", path=path)
