"""Learning the group tracker's model priors by counting events (000 Sec. 4.6: "counting
the related events in the ground truth and dividing by the total number of these
events"), on a labelled sequence whose splits and merges are known by construction."""

from __future__ import annotations

import numpy as np
import pytest

from laserpeople.fitting.data import LabelledRecording
from laserpeople.fitting.groups import GroupFitParams, GroupModelFitter
from laserpeople.scan import Scan
from laserpeople.truth import BeamLabels

# per scan, the group id of persons 0..3 (-1: walking alone)
SEQUENCE = [
    [10, 10, 11, 11],
    [10, 10, 11, 11],
    [12, 12, 12, 12],  # merge: 10 + 11 -> 12
    [12, 12, 12, 12],
    [-1, 12, 12, 12],  # split: person 0 leaves 12
    [-1, 12, 12, 12],
    [-1, -1, 12, 12],  # split: person 1 leaves 12
    [-1, -1, 12, 12],
    [-1, -1, 12, 12],
]
SPLITS, MERGES = 2, 1


def _recording() -> LabelledRecording:
    scans = []
    for k, groups in enumerate(SEQUENCE):
        labels = BeamLabels(
            person=np.arange(4, dtype=np.int32),
            leg=np.zeros(4, dtype=np.int32),
            group=np.array(groups, dtype=np.int32),
            obj=np.full(4, -1, dtype=np.int32),
        )
        scans.append(Scan(0.1 * k, 0.0, 0.1, np.ones(4), index=k, labels=labels))
    n = len(scans)
    return LabelledRecording("hand", tuple(scans), ((),) * n, {}, False, np.ones(n))


def test_split_and_merge_priors_are_their_event_shares() -> None:
    fitter = GroupModelFitter(settings=GroupFitParams(min_events=1)).fit([_recording()])
    p = fitter.params_
    assert (fitter.counts_.split, fitter.counts_.merged) == (SPLITS, MERGES)
    # the Jeffreys estimate (k + 1/2) / (n + 3/2) of each of the three model events
    total = fitter.counts_.continued + SPLITS + MERGES + 1.5
    assert p.p_s == pytest.approx((SPLITS + 0.5) / total, rel=1e-12)
    assert p.p_g == pytest.approx((MERGES + 0.5) / total, rel=1e-12)
    assert p.p_c == pytest.approx((fitter.counts_.continued + 0.5) / total, rel=1e-12)
