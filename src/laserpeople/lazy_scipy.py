"""SciPy's KD-tree and assignment solver, imported on first use.

``scipy.spatial`` and ``scipy.optimize`` each cost a start-up of 0.25-0.6 s, paid by every
command that imports a module naming them, even ``--help`` or a run that never calls them
(the tracker registry imports every tracker's parameters). Modules import the names from
here instead: the same functions (mypy sees SciPy's own signatures), whose SciPy module is
imported by the first call.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from scipy.optimize import linear_sum_assignment as linear_sum_assignment
    from scipy.spatial import cKDTree as cKDTree
else:

    def cKDTree(*args: Any, **kwargs: Any) -> Any:  # noqa: N802 (SciPy's name)
        """:class:`scipy.spatial.cKDTree` (see the module doc)."""
        from scipy.spatial import cKDTree as KDTree

        return KDTree(*args, **kwargs)

    def linear_sum_assignment(*args: Any, **kwargs: Any) -> Any:
        """:func:`scipy.optimize.linear_sum_assignment` (see the module doc)."""
        from scipy.optimize import linear_sum_assignment as solve

        return solve(*args, **kwargs)
