"""Side by side with a textbook tracker: Stone Soup's GNN and JPDA against ours, same scenes,
same leg detections, same scorer.

Stone Soup (the ``peers`` extra: ``pip install -e .[peers]``) gets the shipped AdaBoost
leg detector's detections of every scan paired into people: repeatedly the closest two
legs under 0.75 m apart become one person detection at their midpoint (each leg used once;
legs without a partner are dropped). Both Stone Soup trackers use a constant-velocity
Kalman filter per person in the tracking frame (world, or odometry on a moving robot), a
track is born from 2 associated detections (MultiMeasurementInitiator) and deleted after
``--delete-after`` scans without an update. GNN: Mahalanobis distance hypotheses and 2D
assignment. JPDA: PDA hypotheses (clutter density, detection probability) and a Gaussian
mixture reduced to one state per track. Their tracks (Stone Soup's own UUID ids) go to a
tracks CSV with the project's header, are read back by the project's reader and scored by
the same code as ours (laserpeople.evaluation.suite). CPU ms per scan: pairing plus
Stone Soup's association, update, initiation and deletion (``time.process_time``), leg
detection excluded for everyone.

Scenes: those of benchmarks/people_suite.py (held-back randomised seeds 100-119, the
furniture-only variant, crossing-3, narrow-corridor, entrance-hall seed 0). The Stone Soup
parameters below were set on crossing-3 seed 1 and randomised tuning seeds 0-3 (15 s), one
at a time from a first guess (delete_after 10 -> 20 and min_points 3 -> 2 helped GNN there),
never on the scenes scored here.

    PYTHONPATH=src .venv/bin/python benchmarks/peers.py [--tracker leg-mht] [--seconds 30]
        [--seeds 100-119] [--json out.json] [--baseline-config earlier.toml]
"""

from __future__ import annotations

import argparse
import csv
import datetime as dt
import json
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from laserpeople.evaluation.suite import (
    PreparedScene,
    SceneScore,
    format_table,
    score_tracks,
    summarise,
    track_scene,
)
from laserpeople.io.tracks_csv import HEADER, iter_tracks_csv
from laserpeople.tracking.frames import in_frame, tracking_frame
from laserpeople.tracks import Detections, Track, Tracks
from people_suite import make_factory, parse_seeds, run, suite_scenes, to_json

PAIR_DISTANCE = 0.75
"""Legs closer than this [m] may be paired into a person (issue 10)."""


def pair_legs(positions: np.ndarray, max_distance: float = PAIR_DISTANCE) -> np.ndarray:
    """Person positions (P, 2): greedily the closest remaining pair of legs under
    ``max_distance`` [m], at its midpoint; each leg is used once."""
    n = positions.shape[0]
    if n < 2:
        return np.empty((0, 2))
    d = np.hypot(*(positions[:, None, :] - positions[None, :, :]).transpose(2, 0, 1))
    iu, ju = np.triu_indices(n, 1)
    dist = d[iu, ju]
    order = np.argsort(dist, kind="stable")
    used = np.zeros(n, dtype=bool)
    out = []
    for k in order[dist[order] < max_distance]:
        i, j = iu[k], ju[k]
        if not (used[i] or used[j]):
            used[i] = used[j] = True
            out.append(0.5 * (positions[i] + positions[j]))
    return np.array(out).reshape(-1, 2)


@dataclass(frozen=True)
class StoneSoupParams:
    """The few parameters of the Stone Soup trackers (set on tuning scenes, see above)."""

    process_noise: float = 0.5  # m^2/s^3, constant-velocity acceleration spectral density
    measurement_sigma: float = 0.1  # m, person position from a leg pair
    gate_mahalanobis: float = 3.0  # GNN: missed distance
    delete_after: int = 20  # scans without an update
    min_points: int = 2  # detections to confirm a new track
    prob_detect: float = 0.8  # JPDA
    clutter_density: float = 0.02  # JPDA: false person detections per m^2 per scan
    prob_gate: float = 0.999  # JPDA


class StoneSoupTracker:
    """One Stone Soup multi-target tracker driven scan by scan."""

    def __init__(self, kind: str, p: StoneSoupParams) -> None:
        from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
        from stonesoup.dataassociator.probability import JPDA
        from stonesoup.deleter.time import UpdateTimeStepsDeleter
        from stonesoup.hypothesiser.distance import DistanceHypothesiser
        from stonesoup.hypothesiser.probability import PDAHypothesiser
        from stonesoup.initiator.simple import MultiMeasurementInitiator
        from stonesoup.measures import Mahalanobis
        from stonesoup.models.measurement.linear import LinearGaussian
        from stonesoup.models.transition.linear import (
            CombinedLinearGaussianTransitionModel,
            ConstantVelocity,
        )
        from stonesoup.predictor.kalman import KalmanPredictor
        from stonesoup.types.state import GaussianState
        from stonesoup.updater.kalman import KalmanUpdater

        self.kind = kind
        transition = CombinedLinearGaussianTransitionModel(
            [ConstantVelocity(p.process_noise), ConstantVelocity(p.process_noise)]
        )
        self.measurement_model = LinearGaussian(
            ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2) * p.measurement_sigma**2
        )
        predictor = KalmanPredictor(transition)
        self.updater = KalmanUpdater(self.measurement_model)
        gnn = GNNWith2DAssignment(
            DistanceHypothesiser(
                predictor, self.updater, measure=Mahalanobis(), missed_distance=p.gate_mahalanobis
            )
        )
        if kind == "gnn":
            self.associator: Any = gnn
        else:
            self.associator = JPDA(
                PDAHypothesiser(
                    predictor,
                    self.updater,
                    clutter_spatial_density=p.clutter_density,
                    prob_detect=p.prob_detect,
                    prob_gate=p.prob_gate,
                )
            )
        self.deleter = UpdateTimeStepsDeleter(p.delete_after)
        prior = GaussianState(np.zeros((4, 1)), np.diag([0.3, 1.0, 0.3, 1.0]) ** 2)
        self.initiator = MultiMeasurementInitiator(
            prior,
            UpdateTimeStepsDeleter(2),
            gnn,
            self.updater,
            self.measurement_model,
            min_points=p.min_points,
        )
        self.tracks: set[Any] = set()
        self._epoch = dt.datetime(2000, 1, 1)

    def step(self, people: np.ndarray, stamp: float) -> list[tuple[str, np.ndarray, np.ndarray]]:
        """One scan of person detections (P, 2); returns (uuid, state (4,), covar (4, 4)) of
        every live track."""
        from stonesoup.types.detection import Detection

        when = self._epoch + dt.timedelta(seconds=stamp)
        detections = {
            Detection(
                np.array([[x], [y]]), timestamp=when, measurement_model=self.measurement_model
            )
            for x, y in people
        }
        hypotheses = self.associator.associate(self.tracks, detections, when)
        used = set()
        for track in self.tracks:
            h = hypotheses[track]
            if self.kind == "gnn":
                if h:
                    track.append(self.updater.update(h))
                    used.add(h.measurement)
                else:
                    track.append(h.prediction)
            else:
                track.append(self._mixture(h))
                used |= {x.measurement for x in h if x}
        self.tracks -= self.deleter.delete_tracks(self.tracks)
        self.tracks |= self.initiator.initiate(detections - used, when)
        return [
            (str(t.id), np.asarray(t.state_vector, float).ravel(), np.asarray(t.covar, float))
            for t in self.tracks
        ]

    def _mixture(self, multihypothesis: Any) -> Any:
        from stonesoup.functions import gm_reduce_single
        from stonesoup.types.array import StateVectors
        from stonesoup.types.update import GaussianStateUpdate

        states, weights = [], []
        for h in multihypothesis:
            states.append(self.updater.update(h) if h else h.prediction)
            weights.append(float(h.probability))
        means = StateVectors([s.state_vector for s in states])
        covars = np.stack([s.covar for s in states], axis=2)
        mean, covar = gm_reduce_single(means, covars, np.asarray(weights))
        return GaussianStateUpdate(
            mean, covar, multihypothesis, multihypothesis[0].prediction.timestamp
        )


def run_peer(prepared: PreparedScene, kind: str, p: StoneSoupParams, workdir: Path) -> SceneScore:
    """Track one scene with Stone Soup, write the tracks CSV (UUID ids), read it back with
    the project's reader and score it."""
    outs, cpu = peer_tracks(prepared, kind, p, workdir)
    return score_tracks(prepared, outs, f"stonesoup-{kind}", cpu)


def peer_tracks(
    prepared: PreparedScene, kind: str, p: StoneSoupParams, workdir: Path
) -> tuple[list[Tracks], float]:
    """Track one scene with Stone Soup, write the tracks CSV (UUID ids) and read it back with
    the project's reader: one Tracks per scan and the CPU time [s]."""
    tracker = StoneSoupTracker(kind, p)
    path = workdir / f"{prepared.scene.scenario}-{prepared.scene.seed}-{kind}.csv"
    cpu = 0.0
    frames: dict[int, tuple[str, Any]] = {}
    with open(path, "w", newline="", encoding="utf-8") as fh:
        out = csv.writer(fh, lineterminator="\n")
        out.writerow(HEADER)
        for dets in prepared.detections:
            frame = tracking_frame(dets)
            t0 = time.process_time()
            d: Detections = in_frame(dets, frame)
            people = pair_legs(d.positions)
            live = tracker.step(people, d.stamp)
            cpu += time.process_time() - t0
            frames[d.scan_index] = (frame, d.sensor_pose)
            for uid, x, c in live:
                out.writerow(
                    (
                        d.scan_index,
                        f"{d.stamp:.6f}",
                        uid,
                        "person",
                        f"{x[0]:.4f}",
                        f"{x[2]:.4f}",
                        f"{x[1]:.4f}",
                        f"{x[3]:.4f}",
                        f"{c[0, 0]:.6g}",
                        f"{c[0, 2]:.6g}",
                        f"{c[2, 2]:.6g}",
                        1,
                        "",
                    )
                )
    by_scan = {t.scan_index: t for t in iter_tracks_csv(path)}
    outs = []
    for dets in prepared.detections:
        frame, pose = frames[dets.scan_index]
        got = by_scan.get(dets.scan_index)
        tracks: tuple[Track, ...] = got.tracks if got is not None else ()
        outs.append(Tracks(dets.stamp, dets.scan_index, tracks, frame, pose))
    return outs, cpu


def stonesoup_missing() -> str:
    """Why the Stone Soup peers cannot run here, for the user ("" when they can)."""
    try:
        import stonesoup  # noqa: F401
    except ImportError:
        return (
            "Stone Soup is not installed: pip install 'laserpeople[peers]' (stonesoup==1.9.1; "
            "from a checkout: pip install -e '.[peers]')"
        )
    return ""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--tracker", action="append", help="our registered trackers to run too")
    ap.add_argument("--peer", action="append", choices=("gnn", "jpda"), help="default: both")
    ap.add_argument("--config", type=Path, help="TOML for our trackers and the detector")
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--seeds", default="100-119")
    ap.add_argument("--named-seeds", default="0")
    ap.add_argument("--family", action="append")
    ap.add_argument("--json", type=Path)
    ap.add_argument("--keep-csv", type=Path, help="keep the Stone Soup tracks CSVs here")
    ap.add_argument(
        "--baseline-config",
        type=Path,
        help="also run leg-mht with this TOML, labelled leg-mht[baseline] (e.g. the settings "
        "of an earlier default, side by side in the same run)",
    )
    args = ap.parse_args()
    if missing := stonesoup_missing():
        ap.error(missing)  # before any scene is tracked, not a traceback after the first
    p = StoneSoupParams()
    scenes = suite_scenes(
        parse_seeds(args.seeds), args.seconds, parse_seeds(args.named_seeds), args.family
    )
    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.keep_csv or Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        extra = {
            f"stonesoup-{k}": (lambda prep, k=k: run_peer(prep, k, p, workdir))
            for k in (args.peer or ["gnn", "jpda"])
        }
        if args.baseline_config is not None:
            baseline = make_factory("leg-mht", args.baseline_config)
            extra["leg-mht[baseline]"] = lambda prep: track_scene(
                prep, baseline, "leg-mht[baseline]"
            )[0]
        scores = run(args.tracker or ["leg-mht"], args.config, scenes, extra)
    print(format_table(summarise(scores)))
    if args.json:
        args.json.write_text(json.dumps(to_json(scores), indent=1))


if __name__ == "__main__":
    main()
