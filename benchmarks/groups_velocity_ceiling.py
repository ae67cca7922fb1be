"""How far velocities alone take the clustering of the simulated entrance hall (000 Sec.
4.6.1): memory-less single linkage at d_P against the same linkage with the links between
two people cut when their true velocities (from the simulator, optionally with normal
noise per component and scan) differ by ``v`` or more. This is the ceiling of the walkers
extension (taken out in issue 33; its finding is in docs/papers.md).

    PYTHONPATH=src python benchmarks/groups_velocity_ceiling.py [--seeds 0 1] [--seconds 60]
        [--v 0.4 0.6 0.8] [--noise 0 0.1 0.2 0.3]
"""

from __future__ import annotations

import argparse

import numpy as np

from laserpeople.clustering import single_linkage
from laserpeople.evaluation.clustering import ClusteringError
from laserpeople.evaluation.groups import frames_from_scans
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups.observations import close_pairs, component_labels


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--d-p", type=float, default=1.3)
    ap.add_argument("--v", type=float, nargs="+", default=[0.4, 0.6, 0.8], help="m/s")
    ap.add_argument("--noise", type=float, nargs="+", default=[0.0], help="m/s per component")
    args = ap.parse_args()
    for seed in args.seeds:
        result = run_scenario("entrance-hall", seconds=args.seconds, seed=seed)
        truth = {t.scan_index: t for t in result.truth}
        frames = list(frames_from_scans(result.scans))
        memoryless = ClusteringError()
        for lf in frames:
            fg = np.asarray(lf.frame.foreground)
            assert lf.frame.points is not None
            pts = lf.frame.points.points[fg]
            memoryless.accumulate_labels(
                lf.true_group[fg], single_linkage(pts, args.d_p), lf.frame.stamp
            )
        ml = memoryless.result()
        print(f"seed {seed}: memory-less {ml.error:.3f} (under {ml.under_rate:.3f})", flush=True)
        for noise in args.noise:
            rng = np.random.default_rng(seed)
            cut = {v: ClusteringError() for v in args.v}
            for lf in frames:
                fg = np.asarray(lf.frame.foreground)
                assert lf.frame.points is not None
                pts = lf.frame.points.points[fg]
                person = lf.true_person[fg]
                t = truth[lf.frame.index]
                velocity = {int(p): t.velocities[i] for i, p in enumerate(t.person_ids)}
                seen = {int(p): rng.normal(0.0, noise, 2) for p in np.unique(person)}
                v_point = np.array([velocity[int(p)] + seen[int(p)] for p in person]).reshape(-1, 2)
                pairs, length = close_pairs(pts, args.d_p)
                links = pairs[length < args.d_p]
                dv = np.hypot(*(v_point[links[:, 0]] - v_point[links[:, 1]]).T)
                for v, err in cut.items():
                    labels = component_labels(len(pts), links[dv < v])
                    err.accumulate_labels(lf.true_group[fg], labels, lf.frame.stamp)
            for v, err in cut.items():
                r = err.result()
                print(
                    f"  noise {noise:.2f} m/s, cut at {v:.2f} m/s: {r.error:.3f} "
                    f"(under {r.under_rate:.3f}, over {r.over_rate:.3f})",
                    flush=True,
                )


if __name__ == "__main__":
    main()
