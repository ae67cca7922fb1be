"""The papers behind the defaults, and how a user reads their names.

Source code and parameter metadata cite the papers by their short codes (``000 Table 10``);
text a user reads (``--help``, ``--print-config``, reports) names the authors instead.
"""

from __future__ import annotations

import re

PAPERS: dict[str, str] = {
    "000": "Arras et al. 2008",
    "002": "Kräußling et al.",
    "004": "Schenk et al. 2011",
}
"""Paper code -> how it is cited to a user."""

_CODE = re.compile(r"(?<![\w.,])(00[024])(?!\w|[.,]\d)")


def cite(text: str) -> str:
    """``text`` with every paper code replaced by the authors: ``"000 Table 10"`` ->
    ``"Arras et al. 2008 Table 10"``, ``"004's MOTP"`` -> ``"Schenk et al. 2011's MOTP"``.
    Numbers such as ``1,000`` or ``0.004`` are left alone."""
    return _CODE.sub(lambda m: PAPERS[m.group(1)], text)
