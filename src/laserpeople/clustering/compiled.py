"""Which clustering of 2D points runs: the compiled one (functions of the optional C
extension ``_clisting``, built by ``pip install -e .`` where a C compiler is) or the numpy
references beside it (:func:`~laserpeople.clustering.single_linkage.single_linkage_python`,
:func:`~laserpeople.clustering.mean_shift.mean_shift_python`,
:func:`~laserpeople.clustering.mean_shift.cluster_covariances_python`), which give the same
labels and the same floats within rounding (sums of the same points, some in another
order).

The choice is the MHT listing's (:func:`laserpeople.tracking.mht.compiled.load`): the
references run when ``LASERPEOPLE_PURE_PYTHON`` is set, when the extension is not built or
when it is stale. It is made at the first call (loading the extension imports the tracking
package, which imports this one).
"""

from __future__ import annotations

from types import ModuleType

_loaded: list[ModuleType | None] = []


def extension() -> ModuleType | None:
    """The C extension with the clustering functions, or None when the references run."""
    if not _loaded:
        from laserpeople.tracking.mht import compiled

        _loaded.append(compiled.load()[0])
    return _loaded[0]


__all__ = ["extension"]
