"""``laserpeople fit``: read labelled recordings, split them, learn, validate, write.

:func:`learn` does everything but writing; :func:`write_result` writes the TOML file.
"""

from __future__ import annotations

import datetime
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from laserpeople.config import load_config, section_name
from laserpeople.fitting import data
from laserpeople.fitting.estimates import Estimate, FitError
from laserpeople.fitting.validate import ValidationRow
from laserpeople.scan import Scan
from laserpeople.tracks import Detections

TRACKERS = ("leg-mht", "group-mht")
"""Trackers whose parameters can be learned."""


@dataclass(frozen=True)
class FitResult:
    """What :func:`learn` found.

    Attributes:
        tracker: The tracker.
        params: Its parameters with the learned values.
        estimates: The learned values with their counts.
        kept: Keys not learned, with the reason.
        counts: One line of the events counted.
        training: Names of the training recordings (or parts).
        validation: Names of the validation recordings (or parts).
        rows: Validation scores, default and learned parameters.
    """

    tracker: str
    params: Any
    estimates: tuple[Estimate, ...]
    kept: tuple[tuple[str, str], ...]
    counts: str
    training: tuple[str, ...]
    validation: tuple[str, ...]
    rows: tuple[ValidationRow, ...]

    def header(self) -> list[str]:
        """Comment lines for the TOML file."""
        from laserpeople import __version__

        today = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d")
        return [
            f"Learned by `laserpeople fit --tracker {self.tracker}` (laserpeople "
            f"{__version__}, {today}) by counting events in labelled data (Arras et al. "
            "2008 Sec. 3.4 and 4.6).",
            f"training data: {', '.join(self.training)}",
            f"validation data: {', '.join(self.validation) or 'none'}",
            f"counts: {self.counts}",
            *(f"WARNING: {line}" for line in self.worse_than_default()),
        ]

    def worse_than_default(self) -> list[str]:
        """One line per validation recording on which the learned parameters score below
        the defaults by more than :data:`WORSE_BY` on the headline score (the first of
        :data:`HEADLINES` the rows hold): a value counted from few events can stop a
        tracker altogether (e.g. a ``lambda_new`` so small that no track starts)."""
        scores: dict[str, dict[str, dict[str, float]]] = {}
        for row in self.rows:
            scores.setdefault(row.recording, {})[row.label] = row.scores
        out = []
        for recording, by_label in scores.items():
            default, learned = by_label.get("default"), by_label.get("learned")
            if default is None or learned is None:
                continue
            for name, higher_is_better in HEADLINES:
                if name in default and name in learned:
                    was, now = default[name], learned[name]
                    loss = was - now if higher_is_better else now - was
                    if loss > WORSE_BY:
                        out.append(
                            f"on {recording} the learned parameters score below the "
                            f"defaults ({name} {was:.3f} -> {now:.3f}): keep only the keys "
                            "that win (--learn PATTERN) or learn from more data"
                        )
                    break
        return out


HEADLINES = (("MOTA", True), ("identity recall", True), ("clustering error", False))
"""The validation scores :meth:`FitResult.worse_than_default` compares, the first a row
holds (full truth, a followed person, groups), and whether a higher value is better."""

WORSE_BY = 0.01
"""How much lower (for an error: higher) the learned parameters' headline validation score
may be than the defaults' before :meth:`FitResult.worse_than_default` says so: the
validation scores move by about this much with one scan's decision."""


def learn(
    recordings: Sequence[Path],
    truths: Sequence[str] = (),
    *,
    tracker: str = "leg-mht",
    validation: float = 0.3,
    topic: str | None = None,
    config: Path | None = None,
    min_events: int | None = None,
    select: Sequence[str] = (),
    say: Callable[[str], None] | None = None,
) -> FitResult:
    """Learn ``tracker``'s parameters from ``recordings`` and score them on a held-out part.

    Args:
        recordings: Recordings: simulated ``.npz`` with truth, or any recording with one
            truth per recording in ``truths``.
        truths: None, or one CSV / ``BAG[:TOPIC]`` per recording, in order.
        tracker: ``leg-mht`` or ``group-mht``.
        validation: Share held out: the last recordings, or the last scans of a single one.
        topic: Laser topic of bags.
        config: TOML with the base parameters (kept where nothing is learned) and the
            ``[fit_legs]`` / ``[fit_groups]`` counting settings.
        min_events: Overrides the settings' least number of events per value.
        select: Shell patterns of the keys to keep (``p_m``, ``people.*``); all when empty.
            The others keep their base values.
        say: Receives progress lines.

    Raises:
        FitError: unknown tracker, truth that cannot be paired, too few events.
    """
    from dataclasses import replace

    if tracker not in TRACKERS:
        raise FitError(
            f"cannot learn the parameters of tracker {tracker!r}",
            hint=f"choose one of: {', '.join(TRACKERS)}",
        )
    if not recordings:
        raise FitError("no recording given")
    if truths and len(truths) != len(recordings):
        raise FitError(
            f"{len(truths)} --truth for {len(recordings)} recordings",
            hint="give one --truth per recording, in the same order, or none for .npz with truth",
        )
    tell = say or (lambda _line: None)
    detect = _detector(tracker, config)
    loaded = []
    for k, path in enumerate(recordings):
        rec = data.load(Path(path), truths[k] if truths else None, detect, topic)
        tell(
            f"{rec.name}: {len(rec)} scans, {len(rec.truth)} labelled, "
            f"{'followed-person' if rec.followed else 'full'} truth"
            + (f" ({'; '.join(rec.notes)})" if rec.notes else "")
        )
        loaded.append(rec)
    train, held = data.split(loaded, validation)
    validate: Callable[..., list[ValidationRow]]
    base: Any
    if tracker == "leg-mht":
        from laserpeople.fitting.legs import LegFitParams, LegMHTFitter
        from laserpeople.fitting.validate import validate_legs
        from laserpeople.tracking.legs import LegTrackerParams

        base = load_config(LegTrackerParams, config)
        settings = load_config(LegFitParams, config)
        if min_events is not None:
            settings = replace(settings, min_events=min_events)
        legs = LegMHTFitter(base, settings).fit(train)
        params, estimates, kept = legs.params_, legs.estimates_, legs.kept_
        counts = legs.counts_.summary()
        validate = validate_legs
    else:
        from laserpeople.fitting.groups import GroupFitParams, GroupModelFitter
        from laserpeople.fitting.validate import validate_groups
        from laserpeople.tracking.groups.params import GroupTrackerParams

        base = load_config(GroupTrackerParams, config)
        gsettings = load_config(GroupFitParams, config)
        if min_events is not None:
            gsettings = replace(gsettings, min_events=min_events)
        groups = GroupModelFitter(base, gsettings).fit(train)
        params, estimates, kept = groups.params_, groups.estimates_, groups.kept_
        counts = groups.counts_.summary()
        validate = validate_groups
    tell(f"counted: {counts}")
    if select:
        estimates, kept, params = _select(select, estimates, kept, base)
    rows = validate(held, {"default": base, "learned": params})
    return FitResult(
        tracker,
        params,
        tuple(estimates),
        tuple(kept),
        counts,
        tuple(r.name for r in train),
        tuple(r.name for r in held),
        tuple(rows),
    )


def _in_section(pattern: str, section: str) -> str:
    """``pattern`` of ``--learn`` without the tracker's section, as the written TOML names
    the key (``leg_tracker.p_det_free`` or ``[leg_tracker] p_det_free``: ``p_det_free``).

    Raises:
        FitError: the pattern starts with another tracker's section (``[csa] ...``).
    """
    text = pattern.strip()
    for prefix in (f"[{section}]", f"{section}."):
        if text.startswith(prefix):
            return text[len(prefix) :].strip().lstrip(".")
    if text.startswith("["):
        other = text[1:].split("]", 1)[0]
        raise FitError(
            f"--learn {pattern!r} names the section [{other}], not the tracker's [{section}]",
            hint=f"give the keys as written under [{section}], e.g. --learn 'p_*'",
        )
    return text


def _select(
    patterns: Sequence[str],
    estimates: Sequence[Estimate],
    kept: Sequence[tuple[str, str]],
    base: Any,
) -> tuple[tuple[Estimate, ...], tuple[tuple[str, str], ...], Any]:
    """The estimates whose keys match ``patterns``, the kept keys with the others added, and
    the base parameters with the chosen values.

    Raises:
        FitError: no learned key matches, or a pattern names another section than the
            tracker's.
    """
    from fnmatch import fnmatchcase

    from laserpeople.fitting.legs import with_learned

    patterns = [_in_section(p, section_name(type(base))) for p in patterns]
    chosen = tuple(e for e in estimates if any(fnmatchcase(e.key, p) for p in patterns))
    if not chosen:
        raise FitError(
            f"no learned value matches --learn {' '.join(patterns)}",
            hint=f"learned: {', '.join(e.key for e in estimates)}",
        )
    left = [(e.key, "not chosen by --learn") for e in estimates if e not in chosen]
    return chosen, (*kept, *left), with_learned(base, chosen)


def _detector(tracker: str, config: Path | None) -> Callable[[Scan], Detections]:
    """The leg detector the tracker is fed by (none for the group tracker)."""
    if tracker == "group-mht":
        return lambda scan: Detections.empty(scan.stamp, scan.index, "sensor", scan.pose)
    from laserpeople.detection.detector import AdaBoostLegDetector, LegDetectorParams

    detector = AdaBoostLegDetector.default(load_config(LegDetectorParams, config))
    return detector.detect


def write_result(result: FitResult, path: Path) -> None:
    """Write ``result`` as a TOML file for ``track --config`` (checked and read back)."""
    from laserpeople.fitting.output import write

    write(Path(path), result.params, result.estimates, result.kept, result.header())
