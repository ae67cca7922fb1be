"""SciPy's KD-tree and assignment solver, imported on first use.

``scipy.spatial`` and ``scipy.optimize`` each cost a start-up of 0.25-0.6 s, paid by every
command that imports a module naming them, even ``--help`` or a run that never calls them
(the tracker registry imports every tracker's parameters). Modules import the names from
here instead: the same functions (mypy sees SciPy's own signatures), whose SciPy module is
imported by the first call.

The assignment solver is SciPy's extension module ``scipy.optimize._lsap`` loaded on its
own: it needs nothing of ``scipy.optimize``, whose package import (linear programming,
``scipy.linalg``, ``scipy.sparse``) costs ten times as much. When that module cannot be
loaded so (another SciPy layout), the public ``scipy.optimize.linear_sum_assignment`` is
used; both are the same function. The KD-tree likewise comes from ``scipy.spatial._ckdtree``
alone (about half the CPU of importing ``scipy.spatial``, which also loads its distance
functions, ``qhull`` and ``scipy.linalg``); ``scipy.spatial.cKDTree`` is that module's class.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

LSAP_MODULE = "scipy.optimize._lsap"
"""SciPy's module of ``linear_sum_assignment`` (a C extension)."""

KDTREE_MODULE = "scipy.spatial._ckdtree"
"""SciPy's module of ``cKDTree`` (a C extension)."""

_solver: list[Callable[..., Any]] = []  # the solver, once loaded
_kdtree: list[Any] = []  # the KD-tree class, once loaded


def load_lsap() -> Callable[..., Any]:
    """SciPy's ``linear_sum_assignment``: from ``scipy.optimize`` when that is imported
    already, else from its extension module alone (see the module doc), else by the public
    import."""
    return _from_scipy("scipy.optimize", LSAP_MODULE, "linear_sum_assignment")


def load_kdtree() -> Any:
    """SciPy's ``cKDTree`` class: from ``scipy.spatial`` when that is imported already,
    else from its extension module alone (see the module doc), else by the public import."""
    return _from_scipy("scipy.spatial", KDTREE_MODULE, "cKDTree")


def _from_scipy(package: str, extension: str, name: str) -> Any:
    """``package.name``, taken from the loaded ``package``, or from ``extension`` (loaded
    alone if need be), or by importing ``package`` when the extension cannot be loaded so."""
    public = sys.modules.get(package)
    if public is not None:
        return getattr(public, name)
    module = sys.modules.get(extension)
    if module is None:
        try:
            module = _load_extension(extension)
        except (ImportError, OSError):
            import importlib

            return getattr(importlib.import_module(package), name)
    return getattr(module, name)


def _load_extension(name: str) -> Any:
    """The extension module ``name`` inside the installed scipy, loaded without importing
    its parent package (registered in ``sys.modules``, so that a later import of the
    package uses this one)."""
    import importlib.machinery
    import importlib.util

    folder = _package_folder(name.split(".")[0]).joinpath(*name.split(".")[1:-1])
    stem = name.rsplit(".", 1)[1]
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = folder / f"{stem}{suffix}"
        if path.is_file():
            loader = importlib.machinery.ExtensionFileLoader(name, str(path))
            spec = importlib.util.spec_from_file_location(name, path, loader=loader)
            if spec is None:
                break
            module = importlib.util.module_from_spec(spec)
            loader.exec_module(module)
            sys.modules[name] = module
            return module
    raise ImportError(f"no extension module {name} in {folder}")


def _package_folder(package: str) -> Any:
    """The folder (a :class:`~pathlib.Path`) of the installed ``package``, found without
    importing it (``import scipy`` alone costs some 0.05 s CPU, which the extension module
    does not need); ImportError when it is not installed."""
    import importlib.util
    from pathlib import Path

    module = sys.modules.get(package)
    where = getattr(module, "__file__", None)
    if where:
        return Path(where).parent
    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        raise ImportError(f"no package {package}")
    return Path(next(iter(spec.submodule_search_locations)))


if TYPE_CHECKING:
    from scipy.optimize import linear_sum_assignment as linear_sum_assignment
    from scipy.spatial import cKDTree as cKDTree
else:

    def cKDTree(*args: Any, **kwargs: Any) -> Any:  # noqa: N802 (SciPy's name)
        """:class:`scipy.spatial.cKDTree` (see the module doc)."""
        if not _kdtree:
            _kdtree.append(load_kdtree())
        return _kdtree[0](*args, **kwargs)

    def linear_sum_assignment(*args: Any, **kwargs: Any) -> Any:
        """:func:`scipy.optimize.linear_sum_assignment` (see the module doc)."""
        if not _solver:
            _solver.append(load_lsap())
        return _solver[0](*args, **kwargs)
