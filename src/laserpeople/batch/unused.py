"""What a batch run's options did not do: one warning per option that had no effect on
some recordings (``--model`` on a still laser's ``feet-pf`` runs, ``--background`` on
``leg-mht`` runs with the arras people policy), with the rules ``track`` uses
(:mod:`laserpeople.pipeline.unused_options`)."""

from __future__ import annotations

from collections.abc import Sequence

from laserpeople.batch.options import TrackOptions
from laserpeople.batch.task import FAILED, UNKNOWN, TopicRow


def _runs(rows: Sequence[TopicRow], attribute: str) -> list[tuple[str, bool | None]]:
    """Each row's recording name and its ``attribute`` flag (None: a failed or empty row,
    or one whose flag is unknown)."""
    runs: list[tuple[str, bool | None]] = []
    for row in rows:
        flag = int(getattr(row, attribute))
        known = row.status != FAILED and row.scans > 0 and flag != UNKNOWN
        runs.append((row.name, bool(flag) if known else None))
    return runs


def unused_warnings(rows: Sequence[TopicRow], options: TrackOptions) -> list[str]:
    """The warnings of a batch run with ``options`` over ``rows`` (done and skipped rows
    alike): the leg detector options on the recordings where no run detected legs, and
    ``--background`` on those where no run held a static world model; empty when every
    option given had an effect wherever it could."""
    from laserpeople.pipeline.unused_options import (
        background_options,
        detector_options,
        fleet_warning,
        never_used,
        unused_background_reason,
        unused_detector_reason,
    )

    checks = (
        (
            detector_options(options.detector, options.model, options.config),
            "detector_used",
            unused_detector_reason(options.tracker, "these runs"),
        ),
        (
            background_options(options.background),
            "static_model_used",
            unused_background_reason(options.tracker),
        ),
    )
    said = []
    for asked, attribute, reason in checks:
        if not asked:
            continue
        names, judged = never_used(_runs(rows, attribute))
        line = fleet_warning(asked, names, judged, reason)
        if line:
            said.append(line)
    return said


__all__ = ["unused_warnings"]
