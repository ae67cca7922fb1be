"""What 004's adapted MOTP (eqs. 10-11) of the feet tracker (``track --tracker feet-pf``)
on the randomised group scenes at feet height (``random-groups``, as ``feet_random.py``)
is made of: its loss 1 - MOTP cut into parts that add up exactly.

eq. 11 divides the summed matching values of the matched (track, person) trajectories by
the sum over scans of max(tracks, people). So, as shares of that denominator D::

    1 - MOTP = extra tracks + sum over person-scans of (1 - m of the person's matched track)

- *extra tracks*: per scan, the tracks beyond the number of people, max(0, T - G);
- per person-scan, under the trajectory matching of eq. 11 (``evaluate``'s):
  - *off*: the matched track is there, 0.2-0.75 m away (1 - m);
  - *elsewhere*: the matched track is there, more than 0.75 m away (on another person or
    on clutter: a track that changed people);
  - *another's track*: the matched track is absent and the nearest track within 0.4 m is
    matched to another person (one track on two people);
  - *fragment*: the nearest track within 0.4 m is matched to no one;
  - no track within 0.4 m: *before start*, *gap* or *after end* of the matched track, or
    *no track* when the person has none.

Each part is also split by whether the laser *shows* the person (a return within 0.15 m of
a leg centre, as ``feet_ceiling.py``) and by whether another person is *close* (within
0.45 m) now or was within the last 3 s (the parties of the scenes walk 0.75 m apart and
people of different parties step aside to 0.6 m, so *close* is rare; on scenes made with
``pass_distance`` 0 people of different parties pass through each other).

    PYTHONPATH=src python benchmarks/feet_motp_parts.py [--seeds 0-19] [--keep DIR]
        [--config params.toml] [--jobs 2]

With ``--keep DIR`` the recordings and tracks of ``feet_random.py --keep DIR`` are reused.
**Seeds 100-119 are held back**: measure there, never tune there.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

from feet_ceiling import scene_shown  # type: ignore[import-not-found]
from feet_random import feet_scene_parser, tracked_feet_scenes  # type: ignore[import-not-found]
from laserpeople.evaluation.matching import FramePoints, frame_points
from laserpeople.evaluation.recordings import track_frames, truth_frames
from laserpeople.evaluation.schenk_motp import SchenkMotp, matching_value

OFF = 0.75
"""A matched track farther than this is elsewhere [m]."""
NEAR = 0.4
"""Another track this close covers an absent matched track's person [m] (eq. 10: m = 0.125)."""
CLOSE = 0.45
"""Another person this close is close [m]."""
AFTER_CLOSE = 3.0
"""A person counts as after a close encounter for this long [s]."""
PARTS = (
    "extra tracks",
    "off",
    "elsewhere",
    "another's track",
    "fragment",
    "before start",
    "gap",
    "after end",
    "no track",
)


def _frames(npz: Path, csv: Path) -> tuple[list[FramePoints], dict[int, int]]:
    """Every scored scan's people and tracks, and eq. 11's matching (person -> track)."""
    tracks = {t.scan_index: t for t in track_frames(csv, "person", truth=npz)}
    motp = SchenkMotp(keep_frames=False)
    frames = []
    for truth in truth_frames(npz):
        motp.accumulate(truth, tracks.get(truth.scan_index))
        frames.append(frame_points(truth, tracks.get(truth.scan_index), "person"))
    return frames, {person: track for track, person in motp.result().matched}


def motp_parts(npz: Path, csv: Path) -> dict[str, float]:
    """The parts of 1 - MOTP of one scene, unnormalised (divide by ``D``); also ``D``,
    ``matched`` (the numerator), and per part the ``part|shown``/``part|close`` shares."""
    frames, partner = _frames(npz, csv)
    shown = {
        scan: dict(zip(ids.tolist(), mask.tolist(), strict=True))
        for scan, _, ids, _, mask in scene_shown(npz)
    }
    span: dict[int, tuple[int, int]] = {}
    for fp in frames:
        for tid in fp.track_ids.tolist():
            first, _ = span.get(tid, (fp.scan_index, fp.scan_index))
            span[tid] = (first, fp.scan_index)
    matched_tracks = set(partner.values())
    last_close: dict[int, float] = {}
    out: dict[str, float] = defaultdict(float)
    for fp in frames:
        n_t, n_g = len(fp.track_ids), len(fp.truth_ids)
        out["D"] += max(n_t, n_g)
        out["extra tracks"] += max(0, n_t - n_g)
        dist = fp.distances  # (G, T)
        gaps = np.hypot(*(fp.truth_xy[:, None] - fp.truth_xy[None]).transpose(2, 0, 1))
        np.fill_diagonal(gaps, np.inf)
        tids = fp.track_ids.tolist()
        for j, pid in enumerate(fp.truth_ids.tolist()):
            if n_g > 1 and gaps[j].min() <= CLOSE:
                last_close[pid] = fp.stamp
            close = pid in last_close and fp.stamp - last_close[pid] <= AFTER_CLOSE
            track = partner.get(pid)
            loss, part = 0.0, ""
            if track in tids:
                d = float(dist[j, tids.index(track)])
                value = float(matching_value(np.array(d)))
                out["matched"] += value
                loss, part = 1.0 - value, ("off" if d <= OFF else "elsewhere")
            elif n_t and dist[j].min() <= NEAR:
                other = tids[int(np.argmin(dist[j]))]
                loss, part = 1.0, ("another's track" if other in matched_tracks else "fragment")
            elif track is None:
                loss, part = 1.0, "no track"
            else:
                first, last = span[track]
                part = (
                    "before start"
                    if fp.scan_index < first
                    else ("after end" if fp.scan_index > last else "gap")
                )
                loss = 1.0
            if part and loss > 0.0:
                out[part] += loss
                if shown.get(fp.scan_index, {}).get(pid, False):
                    out[f"{part}|shown"] += loss
                if close:
                    out[f"{part}|close"] += loss
    lost = sum(out[p] for p in PARTS)
    if abs(out["matched"] + lost - out["D"]) > 1e-6 * max(1.0, out["D"]):
        raise RuntimeError(f"{csv}: the parts ({lost}) and the matched sum do not add up to D")
    return out


def main() -> None:
    args = feet_scene_parser(__doc__).parse_args()
    groups: dict[str, Counter[str]] = {}
    with tracked_feet_scenes(args) as scenes:
        for seed, (moving, stem) in scenes.items():
            parts = motp_parts(stem.with_suffix(".npz"), stem.with_suffix(".csv"))
            shares = ", ".join(f"{p} {parts[p] / parts['D']:.3f}" for p in PARTS)
            print(f"seed {seed}: MOTP {parts['matched'] / parts['D']:.3f}; {shares}", flush=True)
            for name in ("all", "moving" if moving else "still"):
                groups.setdefault(name, Counter()).update(parts)
    print(f"\nfeet-pf on random-groups at feet height, seeds {args.seeds}: parts of 1 - MOTP")
    print("(shares of eq. 11's denominator, scenes pooled; in brackets: shown, close)")
    print("| scenes | MOTP (pooled) | " + " | ".join(PARTS) + " |")
    print("|---|---:|" + "---:|" * len(PARTS))
    for name, c in groups.items():
        cells = []
        for p in PARTS:
            text = f"{c[p] / c['D']:.3f}"
            if p != "extra tracks":
                text += f" ({c[p + '|shown'] / c['D']:.3f}, {c[p + '|close'] / c['D']:.3f})"
            cells.append(text)
        print(f"| {name} | {c['matched'] / c['D']:.3f} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
