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
from collections.abc import Callable, Iterable

CUTOFF = 0.8
"""Least ``difflib`` similarity ratio (0-1) of a suggestion to the name as written (its
leaf, after the last dot, for dotted names): ``leg_trackr`` / ``leg_tracker`` is 0.95,
``adaboot`` / ``adaboost`` 0.93, ``csa2`` / ``csa`` 0.86, ``p_det`` / ``p_t`` 0.75 (not
offered), ``nn`` / ``csa`` 0.4."""

PREFIX = 3
"""Least number of characters of a name, written as the start of a known one, that
suggest it whatever their similarity (``pap`` -> ``paper``; ``p`` suggests nothing)."""


def _plain(name: str) -> str:
    """``name`` as compared: lower case, ``_`` and ``-`` alike."""
    return name.strip().lower().replace("_", "-")


def _swapped(a: str, b: str) -> bool:
    """Whether ``a`` is ``b`` with two neighbouring characters swapped."""
    if len(a) != len(b) or a == b:
        return False
    differ = [i for i, (x, y) in enumerate(zip(a, b, strict=True)) if x != y]
    return (
        len(differ) == 2
        and differ[1] == differ[0] + 1
        and a[differ[0]] == b[differ[1]]
        and (a[differ[1]] == b[differ[0]])
    )


def closest(
    name: str, known: Iterable[str], n: int = 3, key: Callable[[str], str] | None = None
) -> list[str]:
    """Up to ``n`` names of ``known`` closest to ``name``, best first: those equal to it but
    for case, ``_`` for ``-`` and the dotted prefix; then those it starts or ends (at a
    ``_``: ``p_det_free``, ``score_threshold``; ``crossing`` -> ``crossing-3`` before
    ``crossing-3-swap``); then those it starts with at least :data:`PREFIX` characters
    (``entr`` -> ``entrance-hall``), those at least :data:`CUTOFF` alike, as whole
    names or by their last dotted part, and those it spells with two neighbouring letters
    swapped (``.pgn`` -> ``.png``). Among the names it starts or ends, the shorter
    come first (they add less to what was written). ``key``: the form in which names are
    compared (e.g. without a leading ``/``), applied to ``name`` and every known name."""
    if key is not None:
        name = key(name)
    want = _plain(name)
    leaf = want.rsplit(".", 1)[-1]
    scored: list[tuple[float, str]] = []
    for k in dict.fromkeys(known):
        whole = _plain(k if key is None else key(k))
        last = whole.rsplit(".", 1)[-1]
        if whole == want or last == leaf:
            scored.append((2.0, k))
            continue
        ratio = max(
            difflib.SequenceMatcher(None, want, whole).ratio(),
            difflib.SequenceMatcher(None, leaf, last).ratio(),
        )
        if last.startswith(f"{leaf}-") or last.endswith(f"-{leaf}"):  # p_det -> p_det_free
            scored.append((1.0 + 0.1 * ratio, k))
        elif len(leaf) >= PREFIX and last.startswith(leaf):  # entr -> entrance-hall
            scored.append((max(ratio, CUTOFF), k))
        elif ratio >= CUTOFF:
            scored.append((ratio, k))
        elif _swapped(leaf, last):  # pgn -> png, odmo -> odom (difflib rates them low)
            scored.append((CUTOFF, k))
    scored.sort(key=lambda s: -s[0])
    return [k for _, k in scored[:n]]


def did_you_mean(
    name: str, known: Iterable[str], key: Callable[[str], str] | None = None, lead: str = ""
) -> str:
    """``did you mean 'x'?`` (or ``'x' or 'y'``) for the names of ``known`` closest to
    ``name`` (see :func:`closest`, also for ``key``), after ``lead`` (``"; "`` to append it
    to a message); empty when none is close."""
    names = closest(name, known, key=key)
    if not names:
        return ""
    quoted = [repr(k) for k in names]
    listed = quoted[0] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"
    return f"{lead}did you mean {listed}?"


__all__ = ["CUTOFF", "PREFIX", "closest", "did_you_mean"]
