"""Errors a user can cause, each with a message that says what to do.

Every error the command line reports without a traceback derives from
:class:`LaserPeopleError`. Messages name the file and, where it applies, the
scan (0-based index on its topic) so that a user can find the bad spot.
"""

from __future__ import annotations

import re
from pathlib import Path

ECHO_LIMIT = 80
"""Characters of a long value (an option value, a token of a file) an error message shows
before it is cut with "…"."""
LONG_WORD = 200
"""A run of this many characters without a space in a message is a long value and cut."""
_LONG = re.compile(r"\S{" + str(LONG_WORD + 1) + ",}")


def shorten(text: str, limit: int = ECHO_LIMIT) -> str:
    """``text`` cut to its first ``limit`` characters and "…" when it is longer."""
    return text if len(text) <= limit else text[:limit] + "…"


def cut_long_values(text: str) -> str:
    """``text`` with every run of more than :data:`LONG_WORD` non-space characters cut to
    :func:`shorten` (a 5,000-character option value is echoed as its first 80)."""
    return _LONG.sub(lambda m: shorten(m.group(0)), text)


class LaserPeopleWarning(UserWarning):
    """Base class of this package's warnings about input (what was left out or not read);
    the command line prints one as ``warning: MESSAGE``, without Python's source line."""


class LaserPeopleError(Exception):
    """Base class of every error caused by input, files or parameters."""

    def __init__(
        self,
        message: str,
        *,
        path: str | Path | None = None,
        scan: int | None = None,
        hint: str | None = None,
    ) -> None:
        self.path = None if path is None else str(path)
        self.scan = scan
        self.hint = None if hint is None else cut_long_values(hint)
        self.detail = cut_long_values(message)
        super().__init__(self._compose())

    def located(self, path: str | Path) -> LaserPeopleError:
        """This error, naming the file ``path`` when it names none yet (an error raised
        where the file is not known, re-raised where it is)."""
        if self.path is None:
            self.path = str(path)
            self.args = (self._compose(),)
        return self

    def noted(self, note: str) -> LaserPeopleError:
        """This error with ``note`` (what became of an output) after its message."""
        self.detail = f"{self.detail}; {note}"
        self.args = (self._compose(),)
        return self

    def moved(self, old: str | Path, new: str | Path) -> LaserPeopleError:
        """This error naming ``new`` where it named ``old`` (an output written under a
        staging name beside ``new`` and moved into place once complete)."""
        if self.path == str(old):
            self.path = str(new)
            self.args = (self._compose(),)
        return self

    def _compose(self) -> str:
        where = []
        if self.path is not None:
            where.append(self.path)
        if self.scan is not None:
            where.append(f"scan {self.scan}")
        text = f"{': '.join(where)}: {self.detail}" if where else self.detail
        if self.hint:
            text = f"{text} ({self.hint})"
        return text


class RecordingError(LaserPeopleError):
    """A recording cannot be opened or read (missing, corrupt, truncated, unknown format)."""


class TopicNotFoundError(RecordingError):
    """A requested topic is not in the recording; the message lists the topics that are."""


class MessageTypeError(RecordingError):
    """A topic carries a message type the reader cannot turn into scans or poses."""


class ScanFormatError(RecordingError):
    """A scan is internally inconsistent (beam count vs angles, bad increment, ...)."""


class UnsortedStampsError(RecordingError):
    """Scan stamps on one topic go backwards."""


class PoseUnavailableError(RecordingError):
    """No sensor pose can be given for a scan (no tf/odom covering its stamp)."""


class ModelFileError(LaserPeopleError):
    """A detector model file is missing, malformed, of a foreign format or a newer version."""


class ConfigError(LaserPeopleError):
    """A configuration file or parameter value is invalid."""


class NotBuiltError(LaserPeopleError):
    """A command or feature that this version does not provide yet."""


class EvaluationError(LaserPeopleError):
    """Tracks cannot be scored against the given ground truth (no truth, frames out of order,
    duplicate ids in one scan, nothing to score)."""
