"""What a reader does with a damaged record in the middle of a recording.

``on_error="stop"`` (the default) ends the read with a
:class:`~laserpeople.errors.RecordingError` that names the file, the topic, the index of
the damaged scan and how many scans were read before it. ``on_error="skip"`` leaves the
damaged record out, counts it in :class:`DamagedRecords` and reads on, so that the rest of
a long recording can be salvaged; the command then says how many were skipped.

A damaged record is one whose bytes cannot be decoded into a laser scan (a message that
does not deserialise, a record filed under a connection of another message type, a scan
header that disagrees with its data, a non-finite stamp or angle). Damage to the file's
structure that ends the stream itself (a chunk that cannot be read) is reported in both
modes: with ``skip`` the scans before it are kept and the read ends there with a warning.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal, get_args

from laserpeople.errors import ConfigError, RecordingError

OnError = Literal["stop", "skip"]
ON_ERROR_CHOICES: tuple[str, ...] = get_args(OnError)
SKIP_HINT = (
    "the recording is corrupt or truncated here; "
    "use --on-error skip to leave damaged scans out and read the rest"
)
BACKWARD_HINT = (
    "use --on-error skip to leave out the scans stamped before an earlier one of their laser "
    "(counted), or fix the recording's stamps"
)


def stamp_back(stamp: float, last: float) -> str:
    """Why a scan stamped ``stamp`` [s] after one stamped ``last`` is a damaged record."""
    return f"stamp {stamp:.6f} s is {last - stamp:.6f} s before the previous scan's"


_EXAMPLES = 5


def check_on_error(value: str) -> OnError:
    """``value`` as an :data:`OnError`; raises :class:`ConfigError` naming the choices."""
    if value not in ON_ERROR_CHOICES:
        raise ConfigError(
            f"on_error must be one of {', '.join(ON_ERROR_CHOICES)}, not {value!r}",
            hint="--on-error stop ends at the first damaged scan; skip leaves it out",
        )
    return value  # type: ignore[return-value]


class DamagedRecords:
    """The damaged records of one read of a recording, and the policy for them.

    Attributes:
        on_error: ``"stop"`` or ``"skip"``.
        count: Damaged records skipped so far (``skip`` only).
        truncated: Why the stream ended early, when structural damage ended it (``skip``).
        examples: The first few skipped records as ``"topic scan k: reason"``.
        intensities_dropped: Scans read without their intensities, which did not match
            their ranges in number (the ranges are sound; nothing in tracking reads
            intensities).
        cut: What was left out of a file cut short that is read up to the cut (``skip``;
            it stays through :meth:`reset`: it is the file's, not one read's).
    """

    def __init__(self, path: str | Path, on_error: OnError = "stop") -> None:
        self.path = Path(path)
        self.on_error: OnError = check_on_error(on_error)
        self.count = 0
        self.truncated: str | None = None
        self.examples: list[str] = []
        self.intensities_dropped = 0
        self._intensities_example = ""
        self.cut: str | None = None

    def reset(self) -> None:
        """Forget the records of an earlier read."""
        self.count = 0
        self.truncated = None
        self.examples = []
        self.intensities_dropped = 0
        self._intensities_example = ""

    def drop_intensities(self, *, topic: str, scan: int, intensities: int, ranges: int) -> None:
        """Count a scan read without its ``intensities`` values, which do not match its
        ``ranges`` in number (in both modes: the scan itself is sound)."""
        if not self.intensities_dropped:
            self._intensities_example = (
                f"first {topic} scan {scan}: {intensities} intensities for {ranges} ranges"
            )
        self.intensities_dropped += 1

    def record(
        self,
        reason: str,
        *,
        topic: str,
        scan: int,
        read: int,
        kind: type[RecordingError] = RecordingError,
        hint: str = SKIP_HINT,
    ) -> None:
        """Handle one damaged record: raise (``stop``) or count it (``skip``).

        Args:
            reason: What is wrong with it.
            topic: Topic (sensor) of the record.
            scan: Index the scan would have had on its topic.
            read: Scans of this topic read before it.
            kind: The error class raised with ``stop`` (e.g. ``ScanFormatError``).
            hint: What to do, in the error raised with ``stop``.

        Raises:
            RecordingError: with ``on_error="stop"``.
        """
        if self.on_error == "stop":
            raise kind(
                f"topic {topic!r}: scan {scan} is damaged ({reason}); "
                f"{read} scans of this topic were read before it",
                path=self.path,
                scan=scan,
                hint=hint,
            )
        self.count += 1
        if len(self.examples) < _EXAMPLES:
            self.examples.append(f"{topic} scan {scan}: {reason}")

    def end(self, reason: str, *, topic: str, scan: int, read: int) -> None:
        """Structural damage ends the stream of ``topic``: raise (``stop``) or note it
        (``skip``, the scans before it are kept)."""
        where = (
            "cannot read its first scan" if scan <= 0 else f"cannot read on after scan {scan - 1}"
        )
        if self.on_error == "stop":
            raise RecordingError(
                f"topic {topic!r}: {where} ({reason}); {read} scans of this topic were read",
                path=self.path,
                scan=scan,
                hint=(
                    "the recording is damaged from its start; re-copy or re-record it"
                    if scan <= 0
                    else "the recording is damaged here; the scans before it can be used with "
                    "--on-error skip"
                )
                + "; for a ROS 1 bag try `rosbag reindex`",
            )
        self.truncated = f"topic {topic!r} ends early after {read} scans: {reason}"

    def check_read(self, read: int) -> None:
        """At the end of a whole read of ``read`` good scans: a read whose every scan was
        damaged (skipped, or the stream ended before the first good one) is an error,
        never an empty result.

        Raises:
            RecordingError: ``read`` is 0 and damage was met.
        """
        if read == 0 and (self.count or self.truncated):
            details = self.summary().replace(f"{self.path}: ", "")
            raise RecordingError(
                f"every scan is damaged, none could be used ({details})",
                path=self.path,
                hint="the recording is corrupt throughout; re-record or re-copy it",
            )

    def summary(self) -> str:
        """Lines for the user; empty when nothing was skipped or left out."""
        parts = [f"{self.path}: {self.cut}"] if self.cut else []
        if self.count:
            shown = "; ".join(self.examples)
            more = "" if self.count <= len(self.examples) else f"; and {self.count - 5} more"
            parts.append(f"{self.path}: skipped {self.count} damaged scan(s) ({shown}{more})")
        if self.truncated:
            parts.append(f"{self.path}: {self.truncated}")
        if self.intensities_dropped:
            parts.append(
                f"{self.path}: {self.intensities_dropped} scan(s) read without their "
                f"intensities, which do not match their ranges in number "
                f"({self._intensities_example}); the ranges are kept"
            )
        return "\n".join(parts)
