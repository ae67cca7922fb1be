"""The leg MHT on the one-command demo scene (real pipeline: simulator, AdaBoost detector)."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.mark.slow
def test_demo_people_tracked_well_and_better_than_nn(tmp_path: Path) -> None:
    """Walking pair, loner and standing person: the person tracks are close to the leg
    mid-points (MOTP), most person frames are covered (MOTA) and no worse than the
    nearest-neighbour baseline with the same person layer; few identity switches."""
    from laserpeople.demo import run_demo

    result = run_demo(tmp_path, seed=0, gif=False)
    scores = {s.name: s.summary for s in result.scores}
    mht, nn = scores["leg-mht"], scores["nn"]
    assert mht["mota"] is not None and nn["mota"] is not None and mht["motp_m"] is not None
    assert float(mht["mota"]) > 0.6
    assert float(mht["motp_m"]) < 0.16
    assert float(mht["mota"]) >= float(nn["mota"])
    assert int(mht["id_switches"] or 0) <= 5
