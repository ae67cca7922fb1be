"""The known names closest to a misspelt one, for error messages (``leg_mht`` ->
``leg-mht``, ``[leg_trackr]`` -> ``[leg_tracker]``, ``gate_probabilty`` ->
``people.gate_probability``).

Example:
    >>> did_you_mean("leg_mht", ["csa", "leg-mht", "group-mht"])
    "did you mean 'leg-mht'?"
    >>> did_you_mean("kalman.gate_probabilty", ["kalman.gate_probability", "person"])
    "did you mean 'kalman.gate_probability'?"
    >>> did_you_mean("zzz", ["csa"])
    ''
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

CUTOFF = 0.8
"""Least ``difflib`` similarity ratio (0-1) of a suggestion to the name as written (its
leaf, after the last dot, for dotted names): ``leg_trackr`` / ``leg_tracker`` is 0.95,
``adaboot`` / ``adaboost`` 0.93, ``csa2`` / ``csa`` 0.86, ``p_det`` / ``p_t`` 0.75 (not
offered), ``nn`` / ``csa`` 0.4."""


def _plain(name: str) -> str:
    """``name`` as compared: lower case, ``_`` and ``-`` alike."""
    return name.strip().lower().replace("_", "-")


def closest(name: str, known: Iterable[str], n: int = 3) -> list[str]:
    """Up to ``n`` names of ``known`` closest to ``name``, best first: those equal to it but
    for case, ``_`` for ``-`` and the dotted prefix; then those it starts or ends (at a
    ``_``: ``p_det_free``, ``score_threshold``); then those at least :data:`CUTOFF` alike,
    as whole names or by their last dotted part."""
    want = _plain(name)
    leaf = want.rsplit(".", 1)[-1]
    scored: list[tuple[float, str]] = []
    for k in dict.fromkeys(known):
        whole = _plain(k)
        last = whole.rsplit(".", 1)[-1]
        if whole == want or last == leaf:
            scored.append((2.0, k))
            continue
        if last.startswith(f"{leaf}-") or last.endswith(f"-{leaf}"):  # p_det -> p_det_free
            scored.append((1.0, k))
            continue
        ratio = max(
            difflib.SequenceMatcher(None, want, whole).ratio(),
            difflib.SequenceMatcher(None, leaf, last).ratio(),
        )
        if ratio >= CUTOFF:
            scored.append((ratio, k))
    scored.sort(key=lambda s: -s[0])
    return [k for _, k in scored[:n]]


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """``did you mean 'x'?`` (or ``'x' or 'y'``) for the names of ``known`` closest to
    ``name`` (see :func:`closest`); empty when none is close."""
    names = closest(name, known)
    if not names:
        return ""
    quoted = [repr(k) for k in names]
    listed = quoted[0] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"
    return f"did you mean {listed}?"


__all__ = ["CUTOFF", "closest", "did_you_mean"]
