"""A command stopped by SIGTERM ends as on Ctrl-C: outputs closed, what they hold said.

``kill PID``, ``timeout``, a service manager or a batch system stops a process with
SIGTERM, whose default action ends it at once without a word: a tracks CSV is whole up to
its last scan (it is written scan by scan) but nobody is told how far it got, and ``batch``
leaves its workers' semaphores to the resource tracker's warning. :func:`stop_on_sigterm`
makes SIGTERM raise :class:`Terminated`, a :class:`KeyboardInterrupt`, so every command
stops on it as on Ctrl-C (the commands' Ctrl-C paths close their outputs and say what they
hold), named as SIGTERM, with exit status 143 (128 + 15, the shell's status of a process
ended by SIGTERM) in place of Ctrl-C's 130. ``live`` stops on SIGTERM its own way (it
finishes its frame and prints its summary).
"""

from __future__ import annotations

import signal
import threading
from typing import Any

CTRL_C_STATUS = 130
"""Exit status of a command stopped by Ctrl-C (128 + SIGINT's 2)."""

SIGTERM_STATUS = 143
"""Exit status of a command stopped by SIGTERM (128 + SIGTERM's 15)."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread where the process was when it came."""


def _raise_terminated(signum: int, frame: Any) -> None:
    raise Terminated


def stop_on_sigterm() -> bool:
    """Make SIGTERM raise :class:`Terminated` in the main thread; whether it was set (not
    off the main thread, where Python cannot set handlers, nor where SIGTERM is ignored or
    handled already: a parent that asked for it to be ignored keeps that)."""
    if threading.current_thread() is not threading.main_thread():
        return False
    if signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL:
        return False
    signal.signal(signal.SIGTERM, _raise_terminated)
    return True


def stop_status(exc: BaseException) -> int:
    """The exit status of a command stopped by ``exc``: :data:`SIGTERM_STATUS` for
    :class:`Terminated`, :data:`CTRL_C_STATUS` otherwise."""
    return SIGTERM_STATUS if isinstance(exc, Terminated) else CTRL_C_STATUS


def stop_name(status: int) -> str:
    """What stopped a command that ends with exit ``status``, for its message:
    ``SIGTERM`` or ``Ctrl-C``."""
    return "SIGTERM" if status == SIGTERM_STATUS else "Ctrl-C"


__all__ = [
    "CTRL_C_STATUS",
    "SIGTERM_STATUS",
    "Terminated",
    "stop_name",
    "stop_on_sigterm",
    "stop_status",
]
