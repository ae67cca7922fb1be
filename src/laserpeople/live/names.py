"""Names a live run puts on the wire, checked before a session opens.

- **ROS 2 topic names** (``--topic``, ``--tf-topic``, ``--tf-static-topic``,
  ``--odom-topic``, ``--output-prefix``): ``/``-separated tokens of ASCII letters, digits
  and underscores; no token starts with a digit; no empty token (``//``) and no ``__``
  (the rules of the ROS 2 design article "Topic and Service name mapping to DDS", as
  ``rcl_validate_topic_name`` and ``rmw_validate_full_topic_name`` check them). A leading
  and a trailing ``/`` are allowed: they are stripped when the Zenoh key is formed
  (:func:`laserpeople.live.keys.strip_topic`). The private namespace ``~`` and ``{}``
  substitutions are not expanded here, so they are refused too. A name that passes forms a
  valid Zenoh key under either transport.
- **Zenoh key prefix** (``--key-prefix``): ``/``-separated non-empty chunks without the
  characters Zenoh reserves for key expressions (``*``, ``$``, ``?``, ``#``; Zenoh's
  "Abstractions" manual); leading and trailing ``/`` are stripped as for topics.
"""

from __future__ import annotations

import re

from laserpeople.errors import ConfigError

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
"""One token of a ROS 2 name: starts with a letter or underscore."""

ZENOH_RESERVED = "*$?#"
"""Characters a Zenoh key may not contain (wildcards and reserved)."""


def topic_problem(name: str, *, empty_ok: bool = False) -> str | None:
    """Why ``name`` is not a ROS 2 topic name this program can publish or subscribe to
    (see the module notes), or None when it is one. ``empty_ok``: an empty name (or ``/``)
    is allowed (a prefix that puts nothing in front)."""
    inner = name[1:] if name.startswith("/") else name
    inner = inner[:-1] if inner.endswith("/") else inner
    if not inner:
        return None if empty_ok else "it is empty"
    for char in inner:
        if not (char.isascii() and (char.isalnum() or char in "_/")):
            return f"it holds {char!r} (ASCII letters, digits, '_' and '/' only)"
    for token in inner.split("/"):
        if not token:
            return "it has an empty part ('//')"
        if not _TOKEN.fullmatch(token):
            return f"its part {token!r} starts with a digit"
        if "__" in token:
            return f"its part {token!r} holds '__'"
    return None


def check_topic(option: str, name: str, *, empty_ok: bool = False) -> None:
    """Refuse a topic option whose value is not a ROS 2 topic name (:func:`topic_problem`).

    Raises:
        ConfigError: Naming the option, the value and what is wrong.
    """
    problem = topic_problem(name, empty_ok=empty_ok)
    if problem is not None:
        raise ConfigError(
            f"{option} {name!r} is not a ROS 2 topic name: {problem}",
            hint="e.g. /scan or /robot1/people: '/'-separated parts of letters, digits and "
            "'_', none starting with a digit",
        )


def check_key_prefix(prefix: str) -> None:
    """Refuse a ``--key-prefix`` that cannot start a Zenoh key (module notes).

    Raises:
        ConfigError: Naming the value and what is wrong.
    """
    inner = prefix.strip("/")
    if not inner:
        return
    problem = None
    reserved = sorted({c for c in inner if c in ZENOH_RESERVED})
    if reserved:
        problem = f"it holds {', '.join(repr(c) for c in reserved)}, reserved in Zenoh keys"
    elif any(not chunk for chunk in inner.split("/")):
        problem = "it has an empty part ('//')"
    if problem is not None:
        raise ConfigError(
            f"--key-prefix {prefix!r} cannot start a Zenoh key: {problem}",
            hint="give the prefix the bridge routes under, e.g. --key-prefix robot1",
        )


__all__ = ["ZENOH_RESERVED", "check_key_prefix", "check_topic", "topic_problem"]
