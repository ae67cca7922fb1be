"""Options a run takes but did not use, and what ``track``, ``live`` and ``batch`` say.

A leg detector option (``--detector``, ``--model``, a ``[leg_detector]`` section) has no
effect on a run that detected no legs (a tracker of points on a still laser); a static
world model (``--background``) none on a run that asks no model (the leg MHT with the
arras people policy); ``--preset`` sets nothing of a tracker that follows no paper. The
rules are here, shared by the commands; a command only prints what they return.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from laserpeople.config import load_config, section_name

SHOWN_NAMES = 3
"""Recordings named in a batch's warning (the rest are counted)."""


def detector_options(detector: str, model: Path | None, config: Path | None) -> list[str]:
    """The options of a command line that choose or tune the leg detector
    (``--detector`` other than the default, ``--model``, a ``[leg_detector]`` section in
    ``config`` that sets a value other than the default: not the defaults a
    ``--print-config`` dump holds), as the user wrote them."""
    from laserpeople.detection.detector import LegDetectorParams

    asked = [f"--detector {detector}"] if detector != "adaboost" else []
    if model is not None:
        asked.append(f"--model {model}")
    if config is not None and load_config(LegDetectorParams, config) != LegDetectorParams():
        asked.append(f"[{section_name(LegDetectorParams)}] of {config}")
    return asked


def unused_detector_reason(tracker: str, runs: str = "this run") -> str:
    """Why leg detector options had no effect on ``runs`` of ``tracker``, and what to do."""
    return (
        f"{tracker} tracks foreground points and {runs} detected no legs (the static world "
        "model narrows the foreground to points near legs only with --background auto and "
        "where [leg_foreground] use says so: by default once the laser moves); drop the "
        'option, or set [leg_foreground] use = "always"'
    )


def unused_detector_warning(tracker: str, asked: list[str], used: bool) -> str | None:
    """What to tell a user whose leg detector options (``asked``, from
    :func:`detector_options`) had no effect because the run never detected legs (``used``
    False: a tracker of points on a still laser, or another static world model than
    ``auto``); None when there is nothing to say."""
    if used or not asked:
        return None
    return f"{' and '.join(asked)} had no effect: {unused_detector_reason(tracker)}"


def background_options(background: str) -> list[str]:
    """The ``--background`` option as the user wrote it, when it asks a model (not the
    default ``auto`` nor ``none``); empty otherwise."""
    return [] if background in ("auto", "none") else [f"--background {background}"]


def unused_background_reason(tracker: str) -> str:
    """Why ``tracker``'s run asked no static world model."""
    if tracker == "leg-mht":
        return (
            "leg-mht with the arras people policy asks no static world model "
            "(--people-policy tracks does)"
        )
    return f"{tracker} asks no static world model with static_tracks.hide = false"


def unused_background_warning(tracker: str, background: str, used: bool) -> str | None:
    """What to tell a user whose ``--background`` had no effect because the run held no
    static world model (``used`` False); None when there is nothing to say."""
    asked = background_options(background)
    if used or not asked:
        return None
    return f"{asked[0]} had no effect: {unused_background_reason(tracker)}"


def never_used(runs: Iterable[tuple[str, bool | None]]) -> tuple[list[str], int]:
    """The recordings on which an option had no effect, from ``runs`` (recording name,
    whether the run used the option, None when unknown: failed, empty, or done by a
    version that did not record it; a recording may have several runs, one per laser).

    Returns the names of the recordings none of whose known runs used the option (in
    order of first appearance) and the number of recordings with a known run."""
    used: dict[str, bool] = {}
    for name, flag in runs:
        if flag is None:
            continue
        used[name] = used.get(name, False) or flag
    return [name for name, flag in used.items() if not flag], len(used)


def fleet_warning(asked: list[str], names: list[str], judged: int, reason: str) -> str | None:
    """One line for a batch: the options ``asked`` had no effect on the recordings
    ``names`` (the first :data:`SHOWN_NAMES` named, the rest counted) of ``judged``
    tracked, and why (``reason``); None when there is nothing to say."""
    if not asked or not names:
        return None
    shown = ", ".join(names[:SHOWN_NAMES])
    if len(names) > SHOWN_NAMES:
        shown += f" and {len(names) - SHOWN_NAMES} more"
    return (
        f"{' and '.join(asked)} had no effect on {len(names)} of {judged} "
        f"recording{'' if judged == 1 else 's'} ({shown}): {reason}"
    )


def preset_note(tracker: str, params_cls: type, preset: str | None) -> str | None:
    """What to tell a user whose ``--preset`` sets nothing of the tracker's own section
    (a tracker without ``paper_preset`` values: ``nn``, a baseline of no paper); None when
    there is nothing to say."""
    if preset is None or getattr(params_cls, "paper_preset", None):
        return None
    return (
        f"--preset {preset} sets nothing of [{section_name(params_cls)}]: {tracker} follows no "
        "paper (the preset sets the leg detector's, the static world model's and "
        "re-identification's sections only)"
    )


__all__ = [
    "SHOWN_NAMES",
    "background_options",
    "detector_options",
    "fleet_warning",
    "never_used",
    "preset_note",
    "unused_background_reason",
    "unused_background_warning",
    "unused_detector_reason",
    "unused_detector_warning",
]
