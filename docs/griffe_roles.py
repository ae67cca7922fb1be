"""A griffe extension for the API pages: the package's docstrings use Sphinx roles
(``:class:`~a.b.C```), RST literal blocks (``::``) and doctest examples; Markdown shows
them as inline code, code blocks and Python blocks.

Loaded by mkdocstrings through ``mkdocs.yml`` (``extensions: [docs/griffe_roles.py]``).
"""

from __future__ import annotations

import re
from typing import Any

import griffe

ROLE = re.compile(r":(?:py:)?(?:class|func|mod|meth|attr|data|exc|obj|const):`(~?)([^`]+)`")
DOCTEST_FLAG = re.compile(r"\s*#\s*doctest:.*$")


def _role(match: re.Match[str]) -> str:
    short, target = match.group(1), match.group(2).lstrip(".")
    return f"`{target.rsplit('.', 1)[-1] if short else target}`"


def markdown(text: str) -> str:
    """The docstring ``text`` with roles as inline code, ``::`` blocks as plain colons and
    doctest lines (``>>>``, ``...``) fenced as Python."""
    text = ROLE.sub(_role, text)
    text = re.sub(r"::\n", ":\n", text)
    out: list[str] = []
    fence: str | None = None  # the indentation of an open doctest fence
    for line in text.splitlines():
        stripped = line.lstrip()
        indent = line[: len(line) - len(stripped)]
        is_doctest = stripped.startswith((">>> ", "... ")) or stripped in (">>>", "...")
        if is_doctest and fence is None:
            fence = indent
            out.append(f"{indent}```python")
        elif not is_doctest and fence is not None:
            out.append(f"{fence}```")
            fence = None
        if is_doctest:
            code = DOCTEST_FLAG.sub("", stripped[4:] if len(stripped) > 3 else "")
            out.append(f"{indent}{code}")
        else:
            out.append(line)
    if fence is not None:
        out.append(f"{fence}```")
    return "\n".join(out)


class SphinxToMarkdown(griffe.Extension):
    """Rewrites every docstring once, when its object is loaded."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        """Convert ``obj``'s docstring."""
        if obj.docstring is not None:
            obj.docstring.value = markdown(obj.docstring.value)
