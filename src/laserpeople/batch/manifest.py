"""The manifest of a batch output folder: what is done, keyed by content and configuration.

``manifest.jsonl`` in the output folder (JSON lines, never pickle) holds one line per
finished task: the recording's name, its content hash, the configuration digest and the
summary rows its task returned; a later line for the same name replaces an earlier one. A
recording is done when its entry has the same content hash and digest, every row is
``done`` and every tracks file it names exists; a rerun skips it. A changed recording or
configuration, a failed row or a missing tracks file makes it run again.

Each finished task appends one line and flushes it, so that a run killed at any moment
leaves the lines of what had finished (a line cut off by the kill is ignored, its
recording runs again) and the cost of recording stays constant per task however many
recordings a run has. :meth:`Manifest.compact` (at the end of a run) rewrites the file with
one line per recording, to a temporary name and then renamed.

A line that is none of these (text or JSON another program or a person added, anywhere but
a cut-off last line) is foreign: a warning names its line numbers, it counts for no
recording, and :meth:`Manifest.compact` keeps it, after the entries, as it was.
"""

from __future__ import annotations

import contextlib
import json
import os
import warnings
from dataclasses import asdict
from pathlib import Path
from typing import Any

from laserpeople.batch.task import DONE, SKIPPED, TopicRow
from laserpeople.errors import ConfigError, LaserPeopleWarning, RecordingError
from laserpeople.io.paths import why_unwritable

MANIFEST = "manifest.jsonl"
VERSION = 1
ENTRY_KEYS = frozenset({"version", "name", "input_hash", "config_hash", "rows"})
"""The keys of every entry (line) of a manifest."""
LINE_START = json.dumps({"version": VERSION})[:-1]
"""How every line of a manifest starts (a line cut off by a kill too)."""


class Manifest:
    """The entries of ``out/manifest.jsonl`` (see the module docstring).

    Args:
        out: The output folder.

    Attributes:
        torn: Lines that could not be read (cut off by a kill); their recordings run again.
        foreign: Lines that are no entry of a manifest (see the module docstring), as
            they were; kept by :meth:`compact`.
    """

    def __init__(self, out: str | Path) -> None:
        self.path = Path(out) / MANIFEST
        self.entries: dict[str, dict[str, Any]] = {}
        self.torn = 0
        self.foreign: list[str] = []
        self._cut_off = False  # the file ends without a newline (a line cut off by a kill)
        if self.path.exists():
            self._read()

    def _read(self) -> None:
        try:
            text = self.path.read_text(encoding="utf-8")
            lines = text.splitlines()
            self._cut_off = bool(text) and not text.endswith("\n")
        except (OSError, UnicodeDecodeError) as exc:
            raise ConfigError(
                f"the manifest cannot be read: {exc}",
                path=self.path,
                hint="delete it (every recording is then tracked again) or use --force",
            ) from None
        foreign: list[int] = []
        for number, line in enumerate(lines, start=1):
            if not line.strip():
                continue
            try:
                entry = json.loads(line)
            except ValueError:
                if number == len(lines) or line.startswith(LINE_START):  # cut off by a kill
                    self.torn += 1
                else:
                    foreign.append(number)
                    self.foreign.append(line)
                continue
            if isinstance(entry, dict) and "version" in entry and entry["version"] != VERSION:
                raise ConfigError(
                    f"line {number}: not a batch manifest of version {VERSION} "
                    f"(version {entry['version']!r})",
                    path=self.path,
                    hint="delete it, or choose another --out folder",
                )
            if not (isinstance(entry, dict) and entry.keys() >= ENTRY_KEYS):
                foreign.append(number)
                self.foreign.append(line)
                continue
            self.entries[str(entry["name"])] = entry
        if foreign:
            shown = ", ".join(map(str, foreign[:10])) + (" ..." if len(foreign) > 10 else "")
            warnings.warn(
                f"{self.path}: line{'s' if len(foreign) > 1 else ''} {shown} "
                f"{'are' if len(foreign) > 1 else 'is'} no entry of a batch manifest "
                f"(one JSON object with {', '.join(sorted(ENTRY_KEYS))}); "
                "no recording counts as done by them, and they are kept as they are",
                LaserPeopleWarning,
                stacklevel=3,
            )

    def done_rows(self, name: str, input_hash: str, digest: str) -> list[TopicRow] | None:
        """The rows of ``name`` when it is done with this content and configuration (each
        marked ``skipped``), else None."""
        entry = self.entries.get(name)
        if not entry or entry.get("input_hash") != input_hash or entry.get("config_hash") != digest:
            return None
        rows = [TopicRow(**r) for r in entry.get("rows", [])]
        out = self.path.parent
        if not rows or any(r.status != DONE or not (out / r.output).is_file() for r in rows):
            return None
        return [TopicRow(**dict(r.__dict__, status=SKIPPED, attempts=0)) for r in rows]

    def record(self, name: str, input_hash: str, digest: str, rows: list[TopicRow]) -> None:
        """Store ``name``'s rows: append one line and flush it."""
        entry = {
            "version": VERSION,
            "name": name,
            "input_hash": input_hash,
            "config_hash": digest,
            "rows": [asdict(r) for r in rows],
        }
        self.entries[name] = entry
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with self.path.open("a", encoding="utf-8") as f:
                # (a line cut off by a kill is ended first: this one must not join it)
                f.write(("\n" if self._cut_off else "") + json.dumps(entry) + "\n")
                self._cut_off = False
                f.flush()
        except OSError as exc:
            raise self._unwritable(exc, f"the line of {name}") from exc

    def compact(self) -> None:
        """Rewrite the file with one line per recording (temporary name, then rename)."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        temp = self.path.with_name(f".{MANIFEST}.{os.getpid()}.tmp")
        text = "".join(json.dumps(e) + "\n" for e in self.entries.values())
        text += "".join(line + "\n" for line in self.foreign)
        try:
            temp.write_text(text, encoding="utf-8")
            os.replace(temp, self.path)
        except OSError as exc:
            with contextlib.suppress(OSError):
                temp.unlink(missing_ok=True)
            raise self._unwritable(exc, "its lines in one per recording") from exc
        self.torn = 0
        self._cut_off = False

    def _unwritable(self, exc: OSError, what: str) -> RecordingError:
        """The error of a write of ``what`` that failed (a full disk): the lines written
        before stay, and a rerun tracks what they do not hold."""
        return RecordingError(
            f"cannot write {what} into the manifest: {why_unwritable(exc, self.path)}; the "
            "lines written before are kept",
            path=self.path,
            hint="free disk space, then run the same command again: it tracks the recordings "
            "the manifest does not hold as done",
        )


__all__ = ["MANIFEST", "Manifest"]
