"""Speed of the leg detector on 720-beam scans (segmentation + 14 features + AdaBoost).

Run: ``.venv/bin/python benchmarks/bench_detect.py`` — prints the median time per scan and
scans/s on one core for the real neko7055 scans (720 beams, 360 degrees), and for synthetic
720-beam scans when the shared data are absent. Target: >= 2000 scans/s.
"""

from __future__ import annotations

import math
import statistics
import time
from pathlib import Path

import numpy as np

from laserpeople.detection.detector import AdaBoostLegDetector
from laserpeople.detection.features import compute_features
from laserpeople.scan import Scan
from laserpeople.segmentation import JumpDistanceSegmenter

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "neko7055"


def synthetic_scans(n: int = 120, beams: int = 720) -> list[Scan]:
    """A room with a few moving leg-sized blobs, 360 degrees at 0.5 degrees."""
    rng = np.random.default_rng(0)
    angles = -math.pi + np.arange(beams) * 2 * math.pi / beams
    scans = []
    for i in range(n):
        r = 4.0 + 1.5 * np.abs(np.sin(2 * angles)) + rng.normal(0, 0.01, beams)
        for k in range(6):
            c = -2.5 + k * 0.9 + 0.02 * i
            r[(angles > c) & (angles < c + 0.06)] = 1.5 + 0.3 * k
        r[rng.random(beams) < 0.02] = np.nan
        scans.append(Scan(i * 0.1, -math.pi, 2 * math.pi / beams, r, index=i))
    return scans


def median_time(fn, scans: list[Scan], repeats: int = 7) -> float:
    """Median over ``repeats`` passes of the mean time per scan [s]."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for s in scans:
            fn(s)
        times.append((time.perf_counter() - t0) / len(scans))
    return statistics.median(times)


def main() -> None:
    if (DATA / "xy_data.txt").exists():
        from laserpeople.io.neko import read_neko_scans

        scans = read_neko_scans(DATA / "xy_data.txt")
        what = f"neko7055 real scans ({len(scans)} x {scans[0].n_beams} beams)"
    else:
        scans = synthetic_scans()
        what = f"synthetic scans ({len(scans)} x 720 beams)"
    _bench(scans, what, full_circle=True)
    lt = DATA.parent / "leg_tracker/rosbags/training_scans_res=0.33/positive_4_extracted.bag"
    if lt.exists():
        from laserpeople.io import open_recording

        rec = open_recording(lt)
        more = list(rec.scans())
        rec.close()
        _bench(more, f"leg_tracker positive_4 ({len(more)} x {more[0].n_beams} beams)", False)


def _bench(scans: list[Scan], what: str, full_circle: bool) -> None:
    detector = AdaBoostLegDetector.default()
    segmenter = JumpDistanceSegmenter(detector.segmenter.params)
    prev: dict[str, Scan] = {}

    def features_only(s: Scan) -> None:
        compute_features(segmenter(s), s, prev.get(s.sensor), full_circle=full_circle)
        prev[s.sensor] = s

    n_seg = np.mean([len(segmenter(s)) for s in scans])
    print(f"{what}, {n_seg:.1f} segments per scan on average")
    for name, fn in (
        ("segmentation", segmenter),
        ("segmentation + 14 features", features_only),
        ("detect (segmentation + features + AdaBoost + Detections)", detector.detect),
    ):
        t = median_time(fn, scans)
        print(f"{name:60s} median {t * 1e6:8.1f} us/scan  {1.0 / t:8.0f} scans/s")


if __name__ == "__main__":
    main()
