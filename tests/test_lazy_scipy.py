"""The lazily imported SciPy functions are SciPy's own (issue 35: start-up)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment as public

from laserpeople import lazy_scipy


def test_assignment_solver_is_scipys() -> None:
    rng = np.random.default_rng(35)
    for shape in ((1, 1), (3, 3), (4, 7), (7, 4), (12, 12)):
        cost = rng.random(shape)
        rows, cols = lazy_scipy.linear_sum_assignment(cost)
        want_rows, want_cols = public(cost)
        # the same optimum (a cost within float rounding), one column per row
        assert cost[rows, cols].sum() == pytest.approx(cost[want_rows, want_cols].sum(), rel=1e-12)
        assert len(set(cols.tolist())) == len(cols) == min(shape)
    # a hand-checked optimum: rows to columns (1, 0) cost 2 + 0 = 2, (0, 1) cost 1 + 5 = 6
    rows, cols = lazy_scipy.linear_sum_assignment(np.array([[1.0, 2.0], [0.0, 5.0]]))
    assert rows.tolist() == [0, 1] and cols.tolist() == [1, 0]
    with pytest.raises(ValueError, match="infeasible"):
        lazy_scipy.linear_sum_assignment(np.array([[np.inf, 1.0], [np.inf, 2.0]]))


def test_extension_loads_without_scipy_optimize() -> None:
    """In a fresh interpreter the solver comes from the extension module alone (no
    ``scipy.optimize`` package import, not even ``scipy`` itself) and gives scipy's answer;
    importing scipy.optimize afterwards still works."""
    code = (
        "import sys, numpy as np\n"
        "from laserpeople.lazy_scipy import linear_sum_assignment as f\n"
        "r, c = f(np.array([[1.0, 2.0], [0.0, 5.0]]))\n"
        "assert c.tolist() == [1, 0], c\n"
        "assert 'scipy.optimize' not in sys.modules, 'scipy.optimize imported'\n"
        "assert 'scipy' not in sys.modules, 'scipy imported'\n"
        "import scipy.optimize\n"
        "assert scipy.optimize.linear_sum_assignment(np.eye(2))[1].tolist() == [1, 0]\n"
    )
    _in_a_fresh_interpreter(code)


def test_kdtree_is_scipys() -> None:
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.5]])
    d, j = lazy_scipy.cKDTree(pts).query(np.array([[0.1, 0.4]]), k=1)
    assert j.tolist() == [2]
    assert d[0] == pytest.approx(np.hypot(0.1, 0.1))


def test_kdtree_loads_without_scipy_spatial() -> None:
    """In a fresh interpreter the KD-tree comes from its extension module alone (no
    ``scipy.spatial`` package import) and is scipy's own class once scipy.spatial is
    imported afterwards."""
    code = (
        "import sys, numpy as np\n"
        "from laserpeople.lazy_scipy import cKDTree\n"
        "tree = cKDTree(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.5]]))\n"
        "assert tree.query_pairs(0.6, output_type='ndarray').tolist() == [[0, 2]]\n"
        "assert 'scipy.spatial' not in sys.modules, 'scipy.spatial imported'\n"
        "import scipy.spatial\n"
        "assert type(tree) is scipy.spatial.cKDTree\n"
    )
    _in_a_fresh_interpreter(code)


def _in_a_fresh_interpreter(code: str) -> None:
    """Run ``code`` in a new Python process; its assertions must hold."""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
