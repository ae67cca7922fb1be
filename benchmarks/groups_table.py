"""The group tracker of 000 Sec. 4 on the simulated entrance hall: clustering error vs d_P
for the tracker and for memory-less single linkage (000 Fig. 17 left/middle), group-size
error (Sec. 4.6.3), split/merge events, and cycle time vs people in view for the group
tracker and the people-only tracker (Fig. 17 right).

Frames come straight from the simulator (foreground = the beams its labels put on people).
The defaults were chosen on entrance-hall seed 0 (30 s); the table uses other seeds.

    PYTHONPATH=src python benchmarks/groups_table.py [--seeds 1 2] [--seconds 60]
        [--d-p 0.7 1.0 1.3 1.6 2.0] [--plot docs/groups_fig17.png] [--set NAME=VALUE ...]

    e.g. --set observation_area=0 (000's V of eqs. 36-37: the area the lasers saw),
    --set mht.min_ratio=1e-3 (the group tracker's ratio pruning before session 9; the
    default is GROUP_MIN_RATIO, 3e-3); --preset paper: 000's group tracker exactly
    (docs/papers.md)
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from laserpeople.config import load_config
from laserpeople.evaluation.groups import GroupRunResult, run_groups
from laserpeople.sim.scenarios import run_scenario
from laserpeople.tracking.groups import GroupTrackerParams


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--scenario", default="entrance-hall")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--d-p", type=float, nargs="+", default=[0.7, 1.0, 1.3, 1.6, 2.0])
    ap.add_argument("--plot", default="")
    ap.add_argument(
        "--set",
        nargs="*",
        default=[],
        metavar="NAME=VALUE",
        help="tracker parameters to change, e.g. observation_area=0 (000's V, eqs. 36-37)",
    )
    ap.add_argument("--preset", default=None, help="paper: 000's group tracker (docs/papers.md)")
    ap.add_argument(
        "--quick", action="store_true", help="only the tracker (no 000 size or people-only runs)"
    )
    args = ap.parse_args()
    base = _with(load_config(GroupTrackerParams, None, args.preset), args.set)
    print(f"preset {args.preset}; parameters changed: {args.set or 'none'}")
    sweep: dict[float, list[GroupRunResult]] = {d: [] for d in args.d_p}
    people_only: list[GroupRunResult] = []
    paper_size: list[GroupRunResult] = []
    paper = replace(base, cluster_distance=1.3, size_count="blobs", eps_n=0.1, size_std=0.5)
    for seed in args.seeds:
        scans = run_scenario(args.scenario, seconds=args.seconds, seed=seed).scans
        for d in args.d_p:
            r = run_groups(scans, replace(base, cluster_distance=d))
            sweep[d].append(r)
            print(
                f"seed {seed} d_P {d:.1f}: tracker {r.clustering.error:.3f} "
                f"(under {r.clustering.under_rate:.3f}, over {r.clustering.over_rate:.3f}), "
                f"memory-less {r.memoryless.error:.3f} (under {r.memoryless.under_rate:.3f}, "
                f"over {r.memoryless.over_rate:.3f}); size error {r.size.mean_error:.2f} "
                f"+- {r.size.std_error:.2f}, exact {100 * r.size.exact_share:.1f} %, within one "
                f"{100 * r.size.within_one_share:.1f} %; under distinct tracker "
                f"{r.tracker_under.distinct}, memory-less {r.memoryless_under.distinct}; "
                f"splits {r.splits}, merges {r.merges}; "
                f"{r.median_ms:.2f} ms/scan",
                flush=True,
            )
        if args.quick:
            continue
        r = run_groups(scans, paper)
        paper_size.append(r)
        print(
            f"seed {seed} d_P 1.3, 000's size counting (blobs at d_hs 0.3 m, eps_n 0.1, size "
            f"std 0.5): size error {r.size.mean_error:.2f}, exact {100 * r.size.exact_share:.1f} %",
            flush=True,
        )
        r = run_groups(scans, GroupTrackerParams.people_only())
        people_only.append(r)
        print(
            f"seed {seed} people-only (d_P 0.5): {r.median_ms:.2f} ms/scan median, "
            f"clustering error vs groups {r.clustering.error:.3f}",
            flush=True,
        )

    print(f"\n{args.scenario}, seeds {args.seeds}, {args.seconds:g} s each (pooled over seeds)\n")
    print("| d_P [m] | tracker error | under | over | memory-less error | under | over |")
    print("|---|---|---|---|---|---|---|")
    for d, runs in sweep.items():
        t = _pool([r.clustering for r in runs])
        m = _pool([r.memoryless for r in runs])
        print(
            f"| {d:.1f} | {t[0]:.3f} | {t[1]:.3f} | {t[2]:.3f} | {m[0]:.3f} | {m[1]:.3f} | "
            f"{m[2]:.3f} |"
        )
    if args.quick:
        at = sweep.get(base.cluster_distance) or next(iter(sweep.values()))
        _print_size(base.cluster_distance, at)
        return
    print("\nUnder-segmentation by cause (per true group; transition = the people are one true")
    print("group within 3 s, distinct = groups that are not, e.g. parties passing):\n")
    print(
        "| d_P [m] | tracker transition | tracker distinct | memory-less transition | "
        "memory-less distinct | over: tracker | over: memory-less |"
    )
    print("|---|---|---|---|---|---|---|")
    for d, runs in sweep.items():
        groups = sum(r.clustering.true_groups for r in runs)
        tt = sum(r.tracker_under.transition for r in runs) / groups
        td = sum(r.tracker_under.distinct for r in runs) / groups
        mt = sum(r.memoryless_under.transition for r in runs) / groups
        md = sum(r.memoryless_under.distinct for r in runs) / groups
        to = _pool([r.clustering for r in runs])[2]
        mo = _pool([r.memoryless for r in runs])[2]
        print(f"| {d:.1f} | {tt:.3f} | {td:.3f} | {mt:.3f} | {md:.3f} | {to:.3f} | {mo:.3f} |")
    ref = sweep.get(base.cluster_distance) or next(iter(sweep.values()))
    _print_size(base.cluster_distance, ref)
    counts = [r.size.count for r in paper_size]
    print(
        f"  000's counting (size_count blobs, d_hs 0.3 m, eps_n 0.1, size std 0.5): mean error "
        f"{_wmean([r.size.mean_error for r in paper_size], counts):.2f} people, exact "
        f"{100 * _wmean([r.size.exact_share for r in paper_size], counts):.1f} %, within one "
        f"{100 * _wmean([r.size.within_one_share for r in paper_size], counts):.1f} %"
    )
    print(f"Split / merge events: {sum(r.splits for r in ref)} / {sum(r.merges for r in ref)}")
    print("\n| people in view | group tracker ms/scan (median) | people-only ms/scan | frames |")
    print("|---|---|---|---|")
    g_ms = np.concatenate([r.frame_ms for r in ref])
    g_n = np.concatenate([r.frame_people for r in ref])
    p_ms = np.concatenate([r.frame_ms for r in people_only])
    p_n = np.concatenate([r.frame_people for r in people_only])
    for lo, hi in ((0, 4), (5, 9), (10, 14), (15, 20)):
        gs = g_ms[(g_n >= lo) & (g_n <= hi)]
        ps = p_ms[(p_n >= lo) & (p_n <= hi)]
        if gs.size:
            print(f"| {lo}-{hi} | {np.median(gs):.2f} | {np.median(ps):.2f} | {gs.size} |")
    if args.plot:
        _plot(args.plot, sweep, g_ms, g_n, p_ms, p_n)


def _print_size(d_p: float, ref: list[GroupRunResult]) -> None:
    """The group-size line (000 Sec. 4.6.3) of the runs at the settings' d_P [m], pooled."""
    counts = [r.size.count for r in ref]
    mean_err = _wmean([r.size.mean_error for r in ref], counts)
    exact = _wmean([r.size.exact_share for r in ref], counts)
    within = _wmean([r.size.within_one_share for r in ref], counts)
    print(
        f"\nGroup size at d_P = {d_p:.1f} m: mean error {mean_err:.2f} people, exact "
        f"{100 * exact:.1f} %, within one {100 * within:.1f} %"
    )


def _with(params: GroupTrackerParams, settings: list[str]) -> GroupTrackerParams:
    """``params`` with ``NAME=VALUE`` changes (values parsed as the field's type)."""
    changes: dict[str, object] = {}
    mht: dict[str, object] = {}
    for item in settings:
        name, _, value = item.partition("=")
        if name.startswith("mht."):  # the nested MHT table, e.g. mht.min_ratio=1e-3
            field = name.removeprefix("mht.")
            old_mht = getattr(params.mht, field)
            mht[field] = float(value) if old_mht is None else type(old_mht)(value)
            continue
        old = getattr(params, name)
        if isinstance(old, bool):
            changes[name] = value.lower() in ("1", "true", "yes")
        else:
            changes[name] = type(old)(value)
    if mht:
        changes["mht"] = replace(params.mht, **mht)  # type: ignore[arg-type]
    return replace(params, **changes)  # type: ignore[arg-type]


def _pool(results: list) -> tuple[float, float, float]:  # type: ignore[type-arg]
    groups = sum(r.true_groups for r in results)
    if groups == 0:
        return float("nan"), float("nan"), float("nan")
    under = sum(r.under_segmented for r in results) / groups
    over = sum(r.over_segmented for r in results) / groups
    return under + over, under, over


def _wmean(values: list[float], weights: list[int]) -> float:
    if sum(weights) == 0:
        return float("nan")
    return float(np.average(np.nan_to_num(values), weights=weights))


def _plot(path, sweep, g_ms, g_n, p_ms, p_n) -> None:  # type: ignore[no-untyped-def]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = list(sweep)
    t = [_pool([r.clustering for r in sweep[x]]) for x in d]
    m = [_pool([r.memoryless for r in sweep[x]]) for x in d]
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    ax[0].plot(d, [x[1] for x in t], "v-", label="under-segmentation")
    ax[0].plot(d, [x[2] for x in t], "^-", label="over-segmentation")
    ax[0].plot(d, [x[0] for x in t], "o-", label="sum")
    ax[0].axvline(1.2, color="grey", lw=0.8)
    ax[0].set(xlabel="d_P [m]", ylabel="error per true group", title="group tracker")
    ax[0].legend()
    ax[1].plot(d, [x[0] for x in t], "o-", label="group tracker")
    ax[1].plot(d, [x[0] for x in m], "s--", label="memory-less single linkage")
    ax[1].set(xlabel="d_P [m]", ylabel="clustering error", title="tracker vs memory-less")
    ax[1].legend()
    people = np.arange(0, 21)
    for ms, n, lab, sty in ((g_ms, g_n, "group tracker", "o-"), (p_ms, p_n, "people-only", "s--")):
        xs = [k for k in people if (n == k).sum() >= 5]
        ax[2].plot(xs, [np.mean(ms[n == k]) for k in xs], sty, label=lab)
    ax[2].set(xlabel="people in view", ylabel="ms per scan (CPU)", title="cycle time")
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
