"""The true groups of a truth frame, as the truth that group tracks are scored against
(``evaluate --kind group``, :func:`laserpeople.evaluation.evaluate` with
``EvaluationParams(kind="group")``, and the group benchmarks)."""

from __future__ import annotations

import numpy as np

from laserpeople.truth import TruthFrame

ALONE_ID = 1_000_000
"""Truth id of a person walking alone, as a group of one: this plus the person id."""


def group_truth(frame: TruthFrame) -> TruthFrame:
    """The true groups of a truth frame as a truth frame whose "people" are the groups: ids
    the truth's group ids (a person alone: :data:`ALONE_ID` + person id), positions the
    mean of the members' positions [m], in the frame's coordinate frame. A truth without
    group ids (every person alone) gives each person as a group of one."""
    groups = frame.groups()
    ids = np.array([g if g >= 0 else ALONE_ID - g - 1 for g in groups], dtype=np.int64)
    centres = [
        frame.positions[np.isin(frame.person_ids, people)].mean(axis=0)
        for people in groups.values()
    ]
    pos = np.asarray(centres, dtype=np.float64).reshape(-1, 2)
    return TruthFrame.from_positions(frame.stamp, frame.scan_index, ids, pos, frame=frame.frame)
