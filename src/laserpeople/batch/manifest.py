"""The manifest of a batch output folder: what is done, keyed by content and configuration.

``manifest.json`` in the output folder (JSON, never pickle) holds one entry per recording
name: the recording's content hash, the configuration digest, and the summary rows its
task returned. A recording is done when its entry has the same content hash and digest,
every row is ``done`` and every tracks file it names exists; a rerun skips it. A changed
recording or configuration, a failed row or a missing tracks file makes it run again.
The file is rewritten (to a temporary name, then renamed) after every finished task, so a
run killed at any moment leaves a manifest of what had finished.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict
from pathlib import Path
from typing import Any

from laserpeople.batch.task import DONE, TopicRow
from laserpeople.errors import ConfigError

MANIFEST = "manifest.json"
VERSION = 1


class Manifest:
    """The entries of ``out/manifest.json`` (see the module docstring).

    Args:
        out: The output folder.
    """

    def __init__(self, out: str | Path) -> None:
        self.path = Path(out) / MANIFEST
        self.entries: dict[str, dict[str, Any]] = {}
        if self.path.exists():
            self.entries = self._read()

    def _read(self) -> dict[str, dict[str, Any]]:
        try:
            data = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise ConfigError(
                f"the manifest cannot be read: {exc}",
                path=self.path,
                hint="delete it (every recording is then tracked again) or use --force",
            ) from None
        if not isinstance(data, dict) or data.get("version") != VERSION:
            raise ConfigError(
                f"not a batch manifest of version {VERSION}",
                path=self.path,
                hint="delete it, or choose another --out folder",
            )
        entries = data.get("entries", {})
        return entries if isinstance(entries, dict) else {}

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
        return [TopicRow(**dict(r.__dict__, status="skipped", attempts=0)) for r in rows]

    def record(self, name: str, input_hash: str, digest: str, rows: list[TopicRow]) -> None:
        """Store ``name``'s rows and rewrite the file."""
        self.entries[name] = {
            "input_hash": input_hash,
            "config_hash": digest,
            "rows": [asdict(r) for r in rows],
        }
        self.save()

    def save(self) -> None:
        """Write the file atomically (temporary name, then rename)."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        temp = self.path.with_name(f".{MANIFEST}.{os.getpid()}.tmp")
        text = json.dumps({"version": VERSION, "entries": self.entries}, indent=1)
        temp.write_text(text, encoding="utf-8")
        os.replace(temp, self.path)


__all__ = ["MANIFEST", "Manifest"]
