"""Which way the feet tracker's particles walk (``track --tracker feet-pf`` on a randomised
group scene at feet height, ``random-groups``): per scan and filter on a walking person
(the nearest labelled person within 0.5 m of the filter's feet midpoint, walking faster
than 0.3 m/s), the share of the particle weight whose direction alpha lies within 90 deg
of the person's true heading (*forward*), and how it changes in each part of a scan:

- *predict*: from the end of the last scan to before the weighting (the walking model and
  its noise, and the refreshes from the filter's cell);
- *weigh*: the weighting of eqs. 3-7 and the repelling term (before resampling);
- *resample, steps, deaths*: from after the weighting to the end of the scan (resampling,
  the refreshes from detected steps, merged filters);
- *refresh (step)*, *refresh (cell)*: each refresh alone (a step or the filter's cell
  restarting ``refresh_share`` of its particles), inside the parts above.

It also splits how far the reported body lies ahead of the person along their heading into
the filter's feet midpoint against the true legs' midpoint, the true legs' midpoint against
the true body, and the model's body offset (:func:`body_offset`).

It also prints the filter's mean model speed 2 s / T and its reported speed along the
person's heading against the person's speed, split by the forward share, and the forward
share by the filter's age.

    PYTHONPATH=src python benchmarks/feet_directions.py recording.npz [--config params.toml]
        [--log per_scan.csv]
"""

from __future__ import annotations

import argparse
import csv
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.evaluation.recordings import truth_frames
from laserpeople.frame import Frame
from laserpeople.pipeline import build
from laserpeople.tracking import registry
from laserpeople.tracking.particle.feet import ALPHA, GAMMA, XL, XR, YL, YR, S, T, body_offset
from laserpeople.tracks import Tracks

NEAR = 0.5
"""A filter this close to a person is on them [m]."""
WALKING = 0.3
"""A person this fast walks [m/s]."""


def _forward(states: NDArray[np.float64], theta: float, heading: float) -> NDArray[np.bool_]:
    """(P,) particles of one filter whose direction (in the world, the sensor turned by
    ``theta``) lies within 90 deg of ``heading`` [rad]."""
    return np.asarray(np.cos(states[:, ALPHA] + theta - heading) > 0.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("recording", type=Path)
    ap.add_argument("--config", default=None, help="TOML of [feet_pf] parameters")
    ap.add_argument("--log", type=Path, default=None, help="per scan and filter rows (CSV)")
    args = ap.parse_args()
    params = None
    if args.config is not None:
        from laserpeople.config import load_config
        from laserpeople.tracking.particle.feet import FeetParams

        params = load_config(FeetParams, args.config)
    truth = {t.scan_index: t for t in truth_frames(args.recording)}
    guarded: Any = registry.get("feet-pf").make(params)
    tracker: Any = getattr(guarded, "tracker", guarded)  # the FeetTracker inside the guard
    bank = tracker.bank
    now: dict[str, Any] = {}
    last: dict[int, float] = {}  # filter id -> forward share at the end of its last scan
    rows: list[dict[str, float]] = []
    moves: dict[str, list[float]] = defaultdict(list)

    def person(mid: NDArray[np.float64]) -> tuple[float, float, float] | None:
        """The heading [rad], speed [m/s] and distance [m] of the walking person nearest
        the world point ``mid``, if within ``NEAR``."""
        tf = truth.get(now["index"])
        if tf is None or len(tf.positions) == 0:
            return None
        d = np.hypot(*(tf.positions - mid).T)
        k = int(np.argmin(d))
        v = tf.velocities[k]
        speed = float(np.hypot(*v))
        if d[k] > NEAR or speed < WALKING:
            return None
        return float(np.arctan2(v[1], v[0])), speed, float(d[k])

    def world(xy: NDArray[np.float64]) -> NDArray[np.float64]:
        pose = now["pose"]
        return xy if pose is None else np.asarray(pose.transform_points(xy), dtype=np.float64)

    def shares(weights: NDArray[np.float64]) -> dict[int, tuple[float, float, float]]:
        """Per filter on a walking person: forward share of ``weights``, heading, speed."""
        out: dict[int, tuple[float, float, float]] = {}
        st = bank.states
        for f in range(len(bank)):
            mid = np.einsum(
                "p,pc->c", weights[f], 0.5 * (st[f, :, XL : YL + 1] + st[f, :, XR : YR + 1])
            )
            who = person(world(mid[None])[0])
            if who is None:
                continue
            fwd = _forward(st[f], now["theta"], who[0])
            out[int(bank.ids[f])] = (float(weights[f] @ fwd), who[0], who[1])
        return out

    reweight = bank.reweight

    def logged_reweight(lik: NDArray[np.float64], rng: np.random.Generator, thr: float) -> None:
        before = shares(bank.weights)
        w = bank.weights * lik
        w = w / np.maximum(w.sum(axis=1, keepdims=True), 1e-300)
        after = shares(w)
        now["weighed"] = after
        for fid, (share, _, _) in before.items():
            if fid in last:
                moves["predict"].append(share - last[fid])
            if fid in after:
                moves["weigh"].append(after[fid][0] - share)
        reweight(lik, rng, thr)

    bank.reweight = logged_reweight
    refresh = tracker._refresh

    def logged_refresh(f: int, feet: NDArray[np.float64]) -> None:
        w0 = shares(bank.weights).get(int(bank.ids[f]))
        refresh(f, feet)
        w1 = shares(bank.weights).get(int(bank.ids[f]))
        if w0 is not None and w1 is not None:
            moves["refresh (cell)" if now.get("cell") else "refresh (step)"].append(w1[0] - w0[0])

    tracker._refresh = logged_refresh
    cell_refresh = tracker._cell_refresh

    def flagged_cell_refresh(*args: Any) -> None:
        now["cell"] = True
        cell_refresh(*args)
        now["cell"] = False

    tracker._cell_refresh = flagged_cell_refresh
    update = tracker.update

    def recording(frame: Frame) -> Tracks:
        pose = frame.sensor_pose if frame.frame == "sensor" else None
        now.update(index=frame.index, pose=pose, theta=0.0 if pose is None else pose.theta)
        now["weighed"] = {}
        out: Tracks = update(frame)
        st = bank.states
        for fid, (share, heading, speed) in shares(bank.weights).items():
            if fid in now["weighed"]:
                moves["resample, steps, deaths"].append(share - now["weighed"][fid][0])
            f = int(np.flatnonzero(bank.ids == fid)[0])
            w = bank.weights[f]
            last[fid] = share
            model = 2.0 * st[f, :, S] / st[f, :, T]
            a = st[f, :, ALPHA] + now["theta"]
            along = float(w @ (model * np.cos(a - heading)))
            mids = 0.5 * (st[f, :, XL : YL + 1] + st[f, :, XR : YR + 1])
            body = world((w @ (mids + body_offset(st[f])))[None])[0]
            tf = truth[frame.index]
            k = int(np.argmin(np.hypot(*(tf.positions - body).T)))
            off = body - tf.positions[k]
            u = np.array([np.cos(heading), np.sin(heading)])
            lag = float(off @ u)
            feet_mid = world((w @ mids)[None])[0]
            legs_mid = tf.leg_positions[k].mean(axis=0)
            parts = (
                float((feet_mid - legs_mid) @ u),  # the filter's feet against the legs
                float((legs_mid - tf.positions[k]) @ u),  # the legs against the body
                float((body - feet_mid) @ u),  # the model's body offset
            )
            rows.append(
                {
                    "scan": frame.index,
                    "filter": fid,
                    "age": frame.stamp - float(bank.born[f]),
                    "forward": share,
                    "speed": speed,
                    "model_speed": float(w @ model),
                    "along": along,
                    "ahead": lag,
                    "feet_vs_legs": parts[0],
                    "legs_vs_body": parts[1],
                    "body_offset": parts[2],
                    "stride": float(w @ st[f, :, S]),
                    "period": float(w @ st[f, :, T]),
                    "phase": float(w @ np.mod(st[f, :, GAMMA], 2 * np.pi)),
                    "feet_gap": float(
                        w @ np.hypot(st[f, :, XR] - st[f, :, XL], st[f, :, YR] - st[f, :, YL])
                    ),
                }
            )
        for fid in list(last):
            if fid not in set(bank.ids.tolist()):
                del last[fid]
        return out

    tracker.update = recording
    build(args.recording, tracker=guarded, outputs=[]).run()
    if not rows:
        print("no filter on a walking person")
        return
    fwd = np.array([r["forward"] for r in rows])
    speed = np.array([r["speed"] for r in rows])
    along = np.array([r["along"] for r in rows])
    model = np.array([r["model_speed"] for r in rows])
    age = np.array([r["age"] for r in rows])
    ahead = np.array([r["ahead"] for r in rows])
    print(f"{args.recording}: {len(rows)} filter-scans on walking people")
    print(
        f"forward share {fwd.mean():.3f}; person speed {speed.mean():.2f} m/s, model 2s/T "
        f"{model.mean():.2f}, along the heading {along.mean():.2f}"
    )
    print(
        f"reported body ahead of the person along the heading: mean {ahead.mean():+.3f} m ="
        + " + ".join(
            f" {np.mean([r[k] for r in rows]):+.3f} ({k})"
            for k in ("feet_vs_legs", "legs_vs_body", "body_offset")
        )
    )
    print("| part | scans | mean change of the forward share | up | down |")
    print("|---|---:|---:|---:|---:|")
    for k in ("predict", "weigh", "resample, steps, deaths", "refresh (step)", "refresh (cell)"):
        m = np.array(moves[k]) if moves[k] else np.zeros(1)
        print(
            f"| {k} | {len(moves[k])} | {m.mean():+.4f} | {(m > 0.01).mean():.2f} | "
            f"{(m < -0.01).mean():.2f} |"
        )
    print("| age [s] | filter-scans | forward share |")
    print("|---|---:|---:|")
    for lo, hi in ((0, 0.5), (0.5, 1), (1, 2), (2, 4), (4, 99)):
        sel = (age >= lo) & (age < hi)
        if sel.any():
            print(f"| {lo}-{hi} | {sel.sum()} | {fwd[sel].mean():.3f} |")
    if args.log is not None:
        with args.log.open("w", newline="") as fh:
            wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
            wr.writeheader()
            wr.writerows(rows)


if __name__ == "__main__":
    main()
