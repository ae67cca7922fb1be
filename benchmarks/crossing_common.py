"""Shared by benchmarks/csa_crossings.py and benchmarks/csa_hue_limit.py: run 002's
crossing scenarios through the CSA and the leg MHT, add colour re-identification, and
score the identities after every crossing.

Identity after a crossing (002 Sec. 3, Figs. 7, 9, 11, 12): the first id each true person
is matched to (Hungarian, 0.5 m gate) is the person's reference (002 indexes people in the
order they appear; the leg MHT confirms people standing still 4.9 m away only once they
walk, sometimes inside the first cluster, so the reference may be taken as late as the
first split); 1.8 s after everyone has arrived at the end positions of a crossing (before the next
crossing starts) the person is *correct* when matched to the same id again.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.evaluation import evaluate
from laserpeople.frame import Frame
from laserpeople.identity.reid import ColourReidentifier, ReidParams
from laserpeople.sim.camera import CameraParams, SimulatedCamera, simulated_frames
from laserpeople.sim.scenarios import run_scenario
from laserpeople.sim.simulator import SimResult
from laserpeople.tracking.csa import ClusterSortingTracker, CSAParams
from laserpeople.tracking.legs import LegMHTTracker
from laserpeople.tracks import Tracks
from laserpeople.truth import TruthFrame

CHECK_DELAY = 1.8
"""Seconds after the last person's arrival at which identities are checked."""

_DETECTOR: AdaBoostLegDetector | None = None


@dataclass
class Case:
    """One simulated crossing run through the laser trackers (colour-independent).

    Attributes:
        scenario: Scenario name.
        seed: Simulation seed.
        result: The simulation.
        frames: Frames without appearance.
        tracks: Tracker name ("csa", "leg-mht") -> tracks per frame.
    """

    scenario: str
    seed: int
    result: SimResult
    frames: list[Frame]
    tracks: dict[str, list[Tracks]]

    @property
    def reference_time(self) -> float:
        notes = self.result.meta["notes"]
        splits = np.ravel(notes.get("split_times_s", notes.get("split_time_s")))
        return float(splits.min())

    @property
    def check_times(self) -> list[float]:
        arrivals = np.ravel(self.result.meta["notes"]["arrival_s"])
        return [float(a) + CHECK_DELAY for a in arrivals]


def laser_runs(
    scenario: str,
    seed: int,
    trackers: Sequence[str] = ("csa", "leg-mht"),
    csa_params: CSAParams | None = None,
) -> Case:
    """Simulate and run the laser-only trackers once (the CSA with ``csa_params``)."""
    global _DETECTOR
    result = run_scenario(scenario, seed=seed)
    frames = simulated_frames(result)
    tracks: dict[str, list[Tracks]] = {}
    if "csa" in trackers:
        csa = ClusterSortingTracker(csa_params)
        tracks["csa"] = [csa.update(f) for f in frames]
    if "leg-mht" in trackers:
        if _DETECTOR is None:
            _DETECTOR = AdaBoostLegDetector.default()
        mht = LegMHTTracker()
        first = result.meta["sensors"][0]["name"]
        out = []
        for f in frames:
            scan = next(s for s in f.scans if s.sensor == first)
            out.append(mht.update(_DETECTOR.detect(scan)))
        tracks["leg-mht"] = out
    return Case(scenario, seed, result, frames, tracks)


def reidentify(
    case: Case,
    tracker: str,
    camera: CameraParams | None = None,
    hues_deg: dict[int, float] | None = None,
    params: ReidParams | None = None,
    camera_seed: int | None = None,
) -> list[Tracks]:
    """The tracker's output after the colour re-identification stage."""
    cam = SimulatedCamera(camera, seed=case.seed if camera_seed is None else camera_seed)
    frames = simulated_frames(case.result, cam, hues_deg)
    reid = ColourReidentifier(params)
    return [reid.update(t, f) for t, f in zip(case.tracks[tracker], frames, strict=True)]


def _ids_at(truth: TruthFrame, tracks: Tracks, gate: float = 0.5) -> dict[int, int]:
    persons = tracks.of_kind("person")
    if not persons or not len(truth):
        return {}
    tp = np.array([t.position for t in persons])
    d = np.linalg.norm(truth.positions[:, None] - tp[None], axis=-1)
    rows, cols = linear_sum_assignment(np.where(d <= gate, d, 1e6))
    return {
        int(truth.person_ids[r]): persons[c].track_id
        for r, c in zip(rows, cols, strict=True)
        if d[r, c] <= gate
    }


def _frame_at(case: Case, t: float) -> int:
    stamps = np.array([tr.stamp for tr in case.result.truth])
    return int(np.argmin(np.abs(stamps - t)))


@dataclass(frozen=True)
class CrossingScore:
    """Identities after the crossings of one run.

    Attributes:
        correct: Per crossing, how many people kept their identity (0-3).
        people: People per crossing.
        id_switches: CLEAR MOT identity switches over the whole run (persons, 0.5 m).
        mota: CLEAR MOT accuracy over the whole run.
    """

    correct: tuple[int, ...]
    people: int
    id_switches: int
    mota: float


def score(case: Case, tracks: list[Tracks]) -> CrossingScore:
    """Identities after every crossing, and CLEAR MOT over the run."""
    last = _frame_at(case, case.reference_time)
    ref: dict[int, int] = {}
    for k in range(last + 1):
        for person, ident in _ids_at(case.result.truth[k], tracks[k]).items():
            ref.setdefault(person, ident)
    ref_k = last
    correct = []
    for t in case.check_times:
        k = _frame_at(case, t)
        now = _ids_at(case.result.truth[k], tracks[k])
        correct.append(sum(1 for p, i in ref.items() if now.get(p) == i))
    summary = evaluate(case.result.truth, tracks).result().summary()
    return CrossingScore(
        tuple(correct),
        len(case.result.truth[ref_k]),
        int(summary["id_switches"] or 0),
        float(summary["mota"] or float("nan")),
    )
