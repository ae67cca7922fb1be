"""What a group tracker that follows 000's definition of a group can reach on the randomised
group scenes: the true people grouped by 000's rules (an oracle, no tracker) and scored
with group MOTA against the scenes' own groups, as ``groups_random.py`` scores the tracker.

000 Sec. 4.2 defines a group from range data by body spacing (people closer than d_P are
one group) and motion (Fig. 18: a person passing a group at another velocity is not in it).
The scenes' groups are the script's parties, which stand and walk within d_P of each
other without being one group. Oracles, each from the truth frames alone (every person the
scanner saw within the last 2 s, as the tracker is scored):

- *proxemic*: the scene's groups joined while a leg of one is within d_P of a leg of the
  other and they move alike (:func:`laserpeople.evaluation.groups.proxemic_truth`, what
  ``groups_random.py``'s proxemic MOTA scores against);
- *000 clustering*: the true people by single linkage of their legs at d_P, links between
  people whose velocities differ by ``PROXEMIC_SPEED`` or more cut; this also splits a
  scene group whose members are more than d_P apart or move apart (a party that has begun
  to leave but is one group in the truth until 0.3 s later).

Every oracle group is reported at the mean of its people (a group that joins two scene
groups lies between them and often matches neither within the 1 m gate), with the id of
the scene group most of its people belong to (a piece of a split group that is not its
largest: an id of its own). The misses of the *proxemic* oracle are split by what the joined
groups were doing (standing or walking, mean speed of the members 0.3 m/s), and a lower
bound of the cost (each join of k scene groups costs k - 1 misses, as if the tracker
reported the join at its largest group's centre) is given too.

    PYTHONPATH=src python benchmarks/groups_truth_bound.py [--seeds 0-19] [--seconds 40]
        [--d-p 1.3] [--jobs 2]
"""

from __future__ import annotations

import argparse
from collections import Counter
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from numpy.typing import NDArray

from groups_random import parse_seeds  # type: ignore[import-not-found]
from laserpeople.evaluation.clear_mot import ClearMot, ClearMotResult
from laserpeople.evaluation.groups import (
    ALONE_ID,
    GROUP_GATE,
    group_truth,
    near_and_alike,
    proxemic_groups,
)
from laserpeople.evaluation.params import EvaluationParams
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupTrackerParams
from laserpeople.tracks import Track, Tracks
from laserpeople.truth import TruthFrame

WALKING = 0.3
"""Mean speed of a group's members above which it walks [m/s]."""
PIECE_ID = 3_000_000
"""Id of a piece of a scene group that is not its largest piece: this plus its first person."""


def scene_group_id(frame: TruthFrame, row: int) -> int:
    """The :func:`group_truth` id of the person at ``row`` of ``frame``."""
    g = int(frame.group_ids[row])
    return g if g >= 0 else ALONE_ID + int(frame.person_ids[row])


def as_tracks(frame: TruthFrame, groups: list[NDArray[np.int64]]) -> Tracks:
    """Oracle groups (rows of ``frame``) reported as group tracks at the mean of their
    people, with the id of the scene group most of their people belong to (the largest
    piece of a scene group keeps its id, the others :data:`PIECE_ID` + first person)."""
    owner: dict[int, tuple[int, int]] = {}  # scene group -> (people in its largest piece, k)
    major: list[int] = []
    for k, rows in enumerate(groups):
        ids = Counter(scene_group_id(frame, int(r)) for r in rows)
        gid, count = max(ids.items(), key=lambda kv: (kv[1], -kv[0]))
        major.append(gid)
        if gid not in owner or owner[gid][0] < count:
            owner[gid] = (count, k)
    tracks = []
    for k, rows in enumerate(groups):
        gid = major[k]
        tid = gid if owner[gid][1] == k else PIECE_ID + int(frame.person_ids[rows].min())
        tracks.append(
            Track(
                track_id=tid,
                kind="group",
                position=frame.positions[rows].mean(axis=0).astype(np.float64),
                velocity=np.zeros(2),
                covariance=np.eye(2),
                size=int(rows.size),
            )
        )
    return Tracks(frame.stamp, frame.scan_index, tuple(tracks))


def clustering_000(frame: TruthFrame, d_p: float) -> list[NDArray[np.int64]]:
    """The people of ``frame`` (rows) by single linkage of their legs at ``d_p`` [m], links
    between people moving :data:`PROXEMIC_SPEED` or more apart cut."""
    n = len(frame)
    rows = np.arange(n, dtype=np.int64)
    near, alike = near_and_alike(frame, rows, rows, d_p)
    link = near & alike
    label = np.full(n, -1, dtype=np.int64)
    for start in range(n):
        if label[start] >= 0:
            continue
        label[start] = start
        stack = [start]
        while stack:
            i = stack.pop()
            for j in np.flatnonzero(link[i] & (label < 0)):
                label[j] = start
                stack.append(int(j))
    return [rows[label == lab] for lab in np.unique(label)]


def join_cost(frame: TruthFrame, groups: list[NDArray[np.int64]]) -> Counter[str]:
    """For each oracle group that holds people of k > 1 scene groups, k - 1 lost
    group-frames, by whether those scene groups stand or walk (``stand``, ``walk`` or
    ``mixed``)."""
    out: Counter[str] = Counter()
    for rows in groups:
        gids = sorted({scene_group_id(frame, int(r)) for r in rows})
        if len(gids) < 2:
            continue
        moving = []
        for g in gids:
            mine = [int(r) for r in rows if scene_group_id(frame, int(r)) == g]
            speed = float(np.hypot(*frame.velocities[mine].mean(axis=0)))
            moving.append(speed > WALKING)
        key = "walk" if all(moving) else "stand" if not any(moving) else "mixed"
        out[key] += len(gids) - 1
    return out


def split_cost(frame: TruthFrame, groups: list[NDArray[np.int64]]) -> int:
    """Scene groups of ``frame`` whose people lie in two or more oracle groups."""
    where: dict[int, set[int]] = {}
    for k, rows in enumerate(groups):
        for r in rows.tolist():
            where.setdefault(scene_group_id(frame, r), set()).add(k)
    return sum(1 for ks in where.values() if len(ks) > 1)


def run_seed(seed: int, seconds: float, d_p: float) -> dict[str, object]:
    """One scene: the oracles' CLEAR MOT against the scene's groups and their join costs."""
    truth = run_scenario("random-groups", seconds=seconds, seed=seed).truth
    params = EvaluationParams(gate=GROUP_GATE, kind="group")
    mots = {name: ClearMot(params, keep_frames=False) for name in ("proxemic", "000")}
    joins: dict[str, Counter[str]] = {"proxemic": Counter(), "000": Counter()}
    splits = Counter[str]()
    for frame in truth:
        if not len(frame):
            continue
        scene = group_truth(frame)
        for name, groups in (
            ("proxemic", [rows for _, rows in proxemic_groups(frame, d_p)]),
            ("000", clustering_000(frame, d_p)),
        ):
            mots[name].accumulate(scene, as_tracks(frame, groups))
            joins[name] += join_cost(frame, groups)
            splits[name] += split_cost(frame, groups)
    return {"mot": {k: m.result() for k, m in mots.items()}, "joins": joins, "splits": splits}


def _mota(results: list[ClearMotResult]) -> tuple[float, int, int, int, int]:
    truth = sum(m.num_truth for m in results)
    miss = sum(m.misses for m in results)
    fp = sum(m.false_positives for m in results)
    ids = sum(m.id_switches for m in results)
    return 1.0 - (miss + fp + ids) / truth, miss, fp, ids, truth


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--seeds", default="0-19")
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument(
        "--d-p", type=float, default=GroupTrackerParams().cluster_distance, help="d_P [m]"
    )
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args()
    seeds = parse_seeds(args.seeds)
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        out = list(pool.map(run_seed, seeds, [args.seconds] * len(seeds), [args.d_p] * len(seeds)))
    for seed, r in zip(seeds, out, strict=True):
        mot = r["mot"]
        assert isinstance(mot, dict)
        print(
            f"seed {seed}: proxemic oracle {mot['proxemic'].mota:.3f}, "
            f"000 clustering oracle {mot['000'].mota:.3f}"
        )
    print(f"\nrandom-groups, seeds {args.seeds}, {args.seconds:g} s, d_P {args.d_p:g} m (pooled)\n")
    print("| oracle | group MOTA | misses | false positives | id switches | k - 1 bound |")
    print("|---|---|---|---|---|---|")
    for name in ("proxemic", "000"):
        mota, miss, fp, ids, truth = _mota([r["mot"][name] for r in out])  # type: ignore[index]
        joins: Counter[str] = sum((r["joins"][name] for r in out), Counter())  # type: ignore[index]
        splits = sum(r["splits"][name] for r in out)  # type: ignore[index]
        bound = 1.0 - sum(joins.values()) / truth
        print(
            f"| {name} | {mota:.3f} | {miss} | {fp} | {ids} | {bound:.3f} "
            f"(joins: stand {joins['stand']}, walk {joins['walk']}, mixed {joins['mixed']}; "
            f"split groups {splits}; of {truth} group-frames) |"
        )


if __name__ == "__main__":
    main()
