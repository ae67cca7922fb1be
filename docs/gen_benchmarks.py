"""Generate ``docs/benchmarks.md``: every benchmark script, the command that reproduces it,
how long it runs, the current figures, and the output of its last run here.

The figures are kept in :data:`BENCHMARKS` next to the command that measured them; a run
(``--run``) executes the commands and stores each one's output under
``benchmarks/results/KEY.txt`` (with the date, the commit and the wall time), which the page
then shows beside the figures. So the page is reproducible: ``--run all`` redoes every
measurement on your machine (about 3.5 hours on 2 cores, most of it in ``schenk`` and
``suite``; ``--run quick`` took 6 minutes at a load of 16 on 2 cores), and the page says
when each output was made.

Usage::

    python docs/gen_benchmarks.py                  # rewrite docs/benchmarks.md
    python docs/gen_benchmarks.py --check          # exit 1 when the page is out of date
    python docs/gen_benchmarks.py --run quick      # run the quick benchmarks, then rewrite
    python docs/gen_benchmarks.py --run detect io  # run the named ones
    python docs/gen_benchmarks.py --run all        # everything (hours)
    python docs/gen_benchmarks.py --list           # keys, minutes, commands
"""

from __future__ import annotations

import argparse
import datetime
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PAGE = REPO / "docs" / "benchmarks.md"
RESULTS = REPO / "benchmarks" / "results"
TAIL_LINES = 40
"""Lines of a stored output shown on the page (the summary is at the end)."""


@dataclass(frozen=True)
class Benchmark:
    """One benchmark: how to run it and what it measured.

    Attributes:
        key: Short name for ``--run`` and the stored output's file name.
        title: What is measured.
        command: Arguments after ``python`` (run from the repository root).
        minutes: Wall time of one run on the 2-core project machine [min].
        figures: The current figures (markdown).
        page: The results page with the details (relative link), or "".
        needs_data: True when it reads the real recordings (``../shared/data``).
    """

    key: str
    title: str
    command: tuple[str, ...]
    minutes: float
    figures: str
    page: str = ""
    needs_data: bool = False

    @property
    def quick(self) -> bool:
        """Short enough for ``--run quick``."""
        return self.minutes <= 1.0


HEADLINE = ("detect", "track", "followed", "moving-people", "suite")
"""Keys of the benchmarks whose figures open the page."""

BENCHMARKS: tuple[Benchmark, ...] = (
    Benchmark(
        "detect",
        "Leg detection speed, 720-beam scans",
        ("benchmarks/bench_detect.py",),
        0.3,
        "about 2,800 scans/s (median, one core)",
        "leg-detection.md",
    ),
    Benchmark(
        "io",
        "Reading a 768-beam ROS 1 bag",
        ("benchmarks/bench_io.py", "--runs", "3"),
        0.5,
        "8,000–22,000 scans/s, 2 MiB Python heap",
        needs_data=True,
    ),
    Benchmark(
        "prelearn",
        "The pass over the whole recording before tracking: a still laser's histogram, a "
        "moving robot's map",
        ("benchmarks/bench_prelearn.py", "--runs", "5"),
        0.5,
        "lobby (moving): 2.3 plain reads, the counting 0.73 ms per frame, 23 MB heap; demo "
        "(still): 3.2 plain reads, 0.09 s for 1,265 frames; the grid asks the map dilated "
        "once, 0.017 against 0.644 ms a frame for a window around every point "
        "(benchmarks/bench_prior_lookup.py, speed.md#the-pass-over-the-whole-recording)",
        "recording.md",
        needs_data=True,
    ),
    Benchmark(
        "sim",
        "Ray-cast simulation, 720 beams, 10 people",
        ("benchmarks/bench_sim.py",),
        0.3,
        "about 4,000 scans/s",
    ),
    Benchmark(
        "startup",
        "Start-up of the command line",
        ("benchmarks/bench_startup.py", "--repeat", "5"),
        0.8,
        "`laserpeople --help` 9.1× and `track --help` 7.3× a bare `python -c pass` (median "
        "CPU, loaded machine); `import typer` alone is about 6–7×",
        "speed.md#start-up",
    ),
    Benchmark(
        "pipeline",
        "Pipeline overhead against the bare read → detect → track loop",
        ("benchmarks/bench_pipeline.py", "--scans", "200", "--repeat", "3"),
        0.8,
        "20–46 µs per frame (0.3–1.4 %)",
    ),
    Benchmark(
        "track",
        "Leg MHT cycle time, 4 and 20 simulated walkers",
        ("benchmarks/bench_track.py", "--seconds", "15"),
        1.0,
        "1.10 ms and 2.70 ms per scan (median CPU, quiet machine; Arras et al. 2008: "
        "44.5 ms for 4 people)",
        "people-benchmarks.md",
    ),
    Benchmark(
        "particle",
        "Particle filters, 5 people, 500 particles each",
        ("benchmarks/bench_particle.py",),
        2.0,
        "feet 144–152 scans/s, upper body 594–606 scans/s (median over the frames with 5 "
        "filters, two runs on a loaded machine); against another version side by side on "
        "real recordings: benchmarks/bench_particle_ab.py (speed.md#the-particle-filters)",
        "schenk-tables.md",
    ),
    Benchmark(
        "groups",
        "Group tracker CPU by people in view",
        ("benchmarks/bench_groups.py",),
        3.0,
        "3.3–3.5 ms per scan with 15–20 people (quiet machine), real demo bag 2.2–2.9 ms",
        "groups.md",
    ),
    Benchmark(
        "detector-tables",
        "Leg detection error, Arras et al. 2008 Tables 2–8",
        ("benchmarks/detector_tables.py",),
        6.0,
        "real neko7055 3.4 % (T = 10), 1.1 % (T = 100); simulated corridor 0.07 %; real "
        "leg_tracker 21.9 % (T = 10), 11 % (T = 1000) against the paper's 2.63 %",
        "leg-detection.md",
        needs_data=True,
    ),
    Benchmark(
        "detector-transfer",
        "Leg detection across scanners (train on one, test on the other)",
        ("benchmarks/detector_transfer.py",),
        10.0,
        "neko7055 0.5° → leg_tracker 0.35°, recall / precision / false-alarm rate 0.489 / "
        "0.103 / 0.222, with `train --augment` 0.750 / 0.151 / 0.219",
        "leg-detection.md#across-scanners",
        needs_data=True,
    ),
    Benchmark(
        "followed",
        "Followed person, real person-following recording",
        ("benchmarks/followed_person.py",),
        0.5,
        "leg MHT identity recall 0.979, recall 0.985, 2 ids (re-identification off 0.658; "
        "`arras` 0.176, 0.740, 9 ids)",
        "people-benchmarks.md",
        needs_data=True,
    ),
    Benchmark(
        "real-people",
        "Person tracks on static places, real bags",
        ("benchmarks/real_people.py", "--trackers", "nn", "csa", "feet-pf", "upper-body-pf"),
        20.0,
        "demo bag feet-pf 21 s, upper-body-pf 33.8 s; MiR front nn 11.3 s, both lasers "
        "13.2 s; no hidden person-second near a leg-MHT person",
        "people-benchmarks.md",
        needs_data=True,
    ),
    Benchmark(
        "peers",
        "Leg MHT against Stone Soup GNN, held-back randomised scenes",
        ("benchmarks/peers.py", "--tracker", "leg-mht", "--peer", "gnn", "--family", "randomised"),
        1.0,
        "randomised 100–119 MOTA / IDF1 0.377 / 0.440 against 0.284 / 0.364 at 0.60× GNN's "
        "CPU; crossing-3 100–119 0.923 / 0.893 against 0.786 / 0.782 at 0.43×; narrow "
        "corridor 100–119 0.399 / 0.420 against 0.344 / 0.389 at 0.50×; entrance hall "
        "100–109 0.462 / 0.451 against 0.351 / 0.377 at 0.28×; moving robot 100–119 (scored "
        "while in view) 0.702 / 0.728 against 0.614 / 0.706 at 1.02× (load average 2-5; "
        "needs the `peers` extra)",
        "people-benchmarks.md",
    ),
    Benchmark(
        "suite",
        "People trackers on held-back simulated scenes",
        ("benchmarks/people_suite.py", "--tracker", "leg-mht", "--tracker", "nn"),
        40.0,
        "randomised MOTA leg MHT 0.34, `arras` 0.27, nn 0.22; crossing-3 0.93 / 0.68 / 0.64; "
        "person-track-seconds on static objects 7.6 / 7.0 / 3.1 per 30 s scene (before the "
        "moving-robot rules; the leg MHT's current randomised MOTA / IDF1 are 0.377 / 0.440 "
        "with 11.9 person-seconds per scene, 6.5 on furniture-only, moving robot 0.702 / "
        "0.728: [People trackers](people-benchmarks.md))",
        "people-benchmarks.md",
    ),
    Benchmark(
        "policies",
        "The demo scene, seeds 0–4, both people policies",
        ("benchmarks/people_policies.py",),
        5.0,
        "default MOTA 0.84 with the static world model (0.90 without), `arras` 0.79",
        "people-benchmarks.md",
    ),
    Benchmark(
        "fit",
        "Parameters learned by `fit` against the defaults",
        ("benchmarks/fit_params.py",),
        20.0,
        "not better: held-back MOTA −0.067 → −0.236 (leg MHT alone; only `p_*` and "
        "`lambda_*` learned: −0.018); real recording "
        "identity recall 0.987 → "
        "0.987; groups clustering error 0.252 → 0.507",
        "fit.md",
        needs_data=True,
    ),
    Benchmark(
        "csa-crossings",
        "Colour re-identification after crossings (8 variants × 5 seeds, 135 people)",
        ("benchmarks/csa_crossings.py",),
        10.0,
        "people right after the crossing: CSA 81 → 135 with colour, leg MHT 85 → 135",
        "csa.md",
    ),
    Benchmark(
        "csa-random",
        "Cluster Sorting where people meet and part, randomised scenes, held-back seeds 100–119",
        (
            "benchmarks/people_suite.py",
            "--tracker",
            "csa",
            "--family",
            "random-groups",
            "--seeds",
            "100-119",
        ),
        20.0,
        "person MOTA 0.594, IDF1 0.523 (goal 0.5; moving lasers 0.502, still 0.686); ID "
        "switches 24.6 per scene, 3.5 s per scene on static objects",
        "csa.md",
    ),
    Benchmark(
        "feet-random",
        "Feet particle filter on the randomised group scenes at feet height, held-back seeds "
        "100–119",
        ("benchmarks/feet_random.py", "--seeds", "100-119", "--jobs", "2"),
        1.0,
        "adapted MOTP 0.465 (goal 0.80), MOTA 0.633, IDF1 0.642 (before the map's hit reach: "
        "0.479, 0.613, 0.646; before the map of what a moving robot drives past: 0.491, "
        "0.599, 0.657; over three draws of the filters 0.483, 0.487 and 0.486); per scene as "
        "the page's table",
        "schenk-tables.md",
    ),
    Benchmark(
        "feet-ceiling",
        "What the randomised group scenes at feet height allow: oracles and the other "
        "trackers, held-back seeds 100–119",
        (
            "benchmarks/feet_ceiling.py",
            "--seeds",
            "100-119",
            "--trackers",
            "default",
            "csa",
            "stonesoup-gnn",
        ),
        20.0,
        "adapted MOTP of a track on every person the laser shows 0.882 (coasting 1 s 0.959); "
        "leg MHT 0.393, csa 0.368. On the scenes before people stepped aside: 0.884 (0.964); "
        "leg MHT 0.291, csa 0.269, Stone Soup GNN 0.248 (feet-pf 0.362 before report_offset); "
        "the best tracker per scene 0.394",
        "schenk-tables.md",
    ),
    Benchmark(
        "groups-table",
        "Group tracker, simulated entrance hall, held-out seeds 2–4 (Fig. 17 analogue)",
        ("benchmarks/groups_table.py", "--seeds", "2", "3", "4", "--plot", "docs/groups_fig17.png"),
        25.0,
        "clustering error 0.201 against 0.210 memory-less at the default d_P = 1.0 m, 0.223 "
        "against 0.238 at 000's 1.3 m (paper 3.1 % against 7.0 %); group size within 0.09 "
        "people, 91.5 % exact (at 1.3 m 0.10, 90.8 %; 91.0 % without the range of counts, "
        "stride_near = stride_far = 0)",
        "groups.md",
    ),
    Benchmark(
        "groups-random",
        "Group tracker on the randomised group scenes, held-back seeds 100–119",
        ("benchmarks/groups_random.py", "--seeds", "100-119", "--seconds", "40"),
        20.0,
        "group MOTA 0.786, proxemic 0.817 (goal 0.80); group size within 0.06 people, "
        "93.8 % exact, at feet height 92.1 %. At 000's d_P of 1.3 m: 0.754, 0.810 (a perfect "
        "grouping by 000's definition 0.896); 93.4 %, 91.6 %. At 1.3 m on the scenes before "
        "people stepped aside: 0.759, "
        "0.810 (a perfect grouping by 000's definition 0.897); 90.9 %, 88.9 % (without "
        "coasting among another group's points, merged_coast_time = 0: 0.755, 0.809; 89.6 %, "
        "87.0 % without the range of counts as well; 88.9 % with torso_pairs true too; "
        "without vanished groups reported "
        "for 1 s: 0.739, 0.802; without ids handed over as well: 0.728, 0.789; without groups "
        "in the shadow kept as well: 0.718, 0.781; with 000's Kalman velocity in the merges as "
        "well: 0.699, 0.767)",
        "groups.md#results-on-the-randomised-group-scenes",
    ),
    Benchmark(
        "moving-people",
        "People from a robot driving among them, real leg_tracker lobby recording (labelled part)",
        ("benchmarks/moving_people.py",),
        0.5,
        "MOTA −0.123, recall 0.351 (20 of 57 labels), 27 false positives, 4 ids; "
        "recall of the 43 detected labels 0.442 (young_credit; without it: −0.123, 0.316, "
        "25, 0.395)",
        "moving-robot.md",
        needs_data=True,
    ),
    Benchmark(
        "memory",
        "Memory of `track`: the real demo bag and 10 minutes of a hall with 20 people",
        ("benchmarks/bench_memory.py",),
        25.0,
        "demo bag peak resident set 62–63 MB, Python's allocations 37 MB at peak; the hall's "
        "own memory 43.8 / 44.8 / 47.4 MB at 10 / 50 / 90 % of 24,000 scans: no growth "
        "with the run's length",
        "speed.md#memory",
        needs_data=True,
    ),
    Benchmark(
        "scaling",
        "Detect + leg MHT + people in a hall at 1–40 people, and `track` on the demo bag",
        ("benchmarks/bench_scaling.py",),
        8.0,
        "0.67 / 1.23 / 1.86 / 2.92 / 3.73 ms CPU per scan at 1 / 4 / 10 / 20 / 40 people "
        "(load about 1.5, every compiled part); log-log slope of cost against people 0.50 "
        "(4–40 people); the demo bag's loop 0.82 ms per scan; whole `track` on the demo "
        "bag 1.29 s CPU, about 980 scans per CPU second; the compiled Kalman steps and "
        "static world model since the previous release: 1.23 / 1.20 / 1.16 / 1.14 / 1.13 "
        "times as fast side by side, the demo bag's loop 1.35, its whole process 1.23",
        "speed.md#cost-against-people-in-view",
        needs_data=True,
    ),
    Benchmark(
        "live",
        "`laserpeople live` over Zenoh on loopback: latency from publishing a scan to "
        "receiving its people",
        ("benchmarks/bench_live.py", "--seconds", "10"),
        2.0,
        "40 Hz, loaded machine: median / p99 28.7 / 121.6 ms with 4 people, 54.1 / 141.8 ms "
        "with 17; at 4× the sustainable rate the queue stays at one scan, p99 155 ms",
        "live.md",
    ),
    Benchmark(
        "live-output",
        "`laserpeople live --record`: per frame, encoding the tracks once, publishing them and "
        "recording them with the scans",
        ("benchmarks/bench_live_output.py", "--frames", "200", "--passes", "3"),
        1.5,
        "per frame, median / p90: 2.64 / 4.18 ms on the MiR bag (13 tracks a frame, two "
        "lasers, world frame), 1.13 / 1.99 ms on the demo bag (6 tracks, one laser)",
        "live.md#measured",
        needs_data=True,
    ),
    Benchmark(
        "batch",
        "`laserpeople batch` on a local Dask cluster: 40 recordings, 3 of them broken on purpose",
        ("benchmarks/bench_batch.py", "--recordings", "40", "--seconds", "3", "--kill", "--resume"),
        1.5,
        "1.13–1.31× with 2 workers on 2 cores at a load average of about 4 (21.3 → 16.2 s); "
        "every good recording tracked "
        "and every broken one reported; a killed worker's "
        "recording redone (attempts 2); a killed run resumed with only the unfinished ones",
        "batch.md",
        needs_data=True,
    ),
    Benchmark(
        "mutants",
        "Mutation run over the equations of 000, 002 and 004, without the real recordings",
        ("benchmarks/mutants.py", "--jobs", "2"),
        30.0,
        "453 of 453 mutants killed: near misses of the papers' equations, the "
        "trackers' departures from them, the compiled paths, the readers' decoding, the "
        "scorers, the checks of the commands' input and the live run's frame choice and "
        "grouping",
        "papers.md",
    ),
    Benchmark(
        "schenk",
        "Feet and upper-body particle filters, Schenk et al. 2011 Tables 1–6",
        ("benchmarks/schenk_tables.py", "--jobs", "2", "--results", "benchmarks/schenk_runs.jsonl"),
        35.0,
        "adapted MOTP upper body 0.94–0.98, feet 0.77–0.98, leg MHT on the feet lasers 0.67–0.93",
        "schenk-tables.md",
    ),
    Benchmark(
        "soak",
        "Long runs: 60-s entrance-hall scenes back to back",
        ("benchmarks/soak.py", "--scans", "30000", "--every", "2000"),
        30.0,
        "default people: leg families ≤ 34 (slope 0.0 per 100k scans), 9–15 ms per scan "
        "(slope −5.9 ms per 100k), 143.5 MB peak RSS",
    ),
    Benchmark(
        "fuzz",
        "Hostile files: mutated recordings, models, configs and CSVs",
        ("benchmarks/fuzz_readers.py", "--cases", "10000"),
        25.0,
        "10,000 cases: 0 tracebacks, hangs or memory blow-ups",
    ),
    Benchmark(
        "viz",
        "GIF memory, 640×480",
        ("benchmarks/bench_viz.py", "--memory", "1000,10000"),
        8.0,
        "10,000 scans 127 MB peak, 1,000 scans 83 MB",
    ),
)

PLOTS: tuple[tuple[str, str, str], ...] = (
    (
        "groups_fig17.png",
        "Clustering error against d_P, group tracker and memory-less clustering "
        "(Arras et al. 2008 Fig. 17 analogue)",
        "groups-table",
    ),
    ("figures/csa_hue_limit.png", "Colour re-identification against hue difference", "csa"),
    (
        "img/static-mir-none-vs-auto.png",
        "Person tracks on the real MiR bag without and with the static world model",
        "real-people",
    ),
)


def stored_output(key: str) -> str | None:
    """The stored output of ``key``'s last run, or None."""
    path = RESULTS / f"{key}.txt"
    return path.read_text(encoding="utf-8") if path.exists() else None


def render() -> str:
    """The whole page."""
    by_key = {b.key: b for b in BENCHMARKS}
    lines = [
        "# Benchmarks",
        "",
        "Every speed and accuracy figure of these pages comes from a script in `benchmarks/`.",
        "This page lists them with their current figures, the command that reproduces each",
        "and the output of its last stored run.",
        "",
        "**When to use it.** To check a figure on your own machine, or to measure a change",
        "before and after: run the command under the figure. The results pages linked under",
        "each figure say what it means and how it compares.",
        "",
        "```bash",
        ".venv/bin/python docs/gen_benchmarks.py --list        # keys, minutes, commands",
        ".venv/bin/python docs/gen_benchmarks.py --run quick   # the quick ones; rewrites it",
        "```",
        "",
        "| measured | figures | where |",
        "|---|---|---|",
        *(
            f"| {by_key[key].title} | {by_key[key].figures} | [{key}](#{key}) |"
            for key in HEADLINE
            if key in by_key
        ),
        "",
        "Generated by `.venv/bin/python docs/gen_benchmarks.py` from the list in that script",
        "and the outputs of the last runs in `benchmarks/results/`; do not edit by hand.",
        "`.venv/bin/python docs/gen_benchmarks.py --run quick` reruns the quick ones (6 minutes",
        "on the project's 2-core machine under heavy load), `--run KEY` one of them, `--run all`",
        "everything (about 3.5 hours). Run them from the repository root; those that need",
        "the real recordings find them in `../shared/data` beside the repository, or in",
        "`LASERPEOPLE_SHARED_DATA`.",
        "",
        "CPU times are process CPU time (`time.process_time`) on a machine whose 2 cores were",
        "shared with other jobs: compare ratios measured in one run, not absolute times",
        "across runs. Each stored output names the machine's load average while it ran; a",
        "load above the core count slows every figure, so store runs from a quiet machine.",
        "Accuracy figures on simulated scenes are on seeds never used for tuning.",
        "",
        "## Figures",
        "",
    ]
    for b in BENCHMARKS:
        more = f" [Details]({b.page})." if b.page else ""
        data = " Needs the real recordings." if b.needs_data else ""
        lines += [
            f"### {b.title} {{ #{b.key} }}",
            "",
            f"{b.figures[:1].upper()}{b.figures[1:]}.{more}",
            "",
            "```bash",
            ".venv/bin/python " + " ".join(b.command),
            "```",
            "",
            f"About {b.minutes:g} min on the project's 2-core machine.{data}",
            "",
        ]
    lines += ["## Plots", ""]
    for path, caption, key in PLOTS:
        lines += [f"![{caption}]({path})", "", f"*{caption}* (`{key}`).", ""]
    lines += ["## Outputs of the last runs", ""]
    shown = 0
    for b in BENCHMARKS:
        text = stored_output(b.key)
        if text is None:
            continue
        shown += 1
        tail = text.rstrip("\n").splitlines()
        head, body = tail[0], tail[1:][-TAIL_LINES:]
        lines += [f'??? note "{b.key}: {head}"', "", "    ```text"]
        lines += [f"    {line}".rstrip() for line in body]
        lines += ["    ```", ""]
    if not shown:
        lines += ["No run stored yet: `.venv/bin/python docs/gen_benchmarks.py --run quick`.", ""]
    return "\n".join(lines)


def commit() -> str:
    """The checked-out commit (short), or 'unknown'."""
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return out.stdout.strip()


def run(bench: Benchmark) -> int:
    """Run one benchmark and store its output; returns its exit status."""
    RESULTS.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO / "src") + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("COLUMNS", "120")
    print(f"running {bench.key}: python {' '.join(bench.command)}", file=sys.stderr)
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, *bench.command],
        cwd=REPO,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.monotonic() - start
    date = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]  # a loaded machine slows every figure: say how loaded
    head = (
        f"{date}, commit {commit()}, {wall:.0f} s wall, load {load:.1f} on "
        f"{os.cpu_count()} cores, exit {proc.returncode}"
    )
    (RESULTS / f"{bench.key}.txt").write_text(
        head + "\n" + proc.stdout + proc.stderr, encoding="utf-8"
    )
    print(f"  {head}", file=sys.stderr)
    return proc.returncode


def main(argv: list[str] | None = None) -> int:
    """Command-line entry; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="fail when the page is stale")
    parser.add_argument("--list", action="store_true", help="list the benchmarks")
    parser.add_argument("--run", nargs="+", metavar="KEY", help="quick, all, or keys")
    args = parser.parse_args(argv)
    keys = {b.key: b for b in BENCHMARKS}
    if args.list:
        for b in BENCHMARKS:
            print(f"{b.key:18} {b.minutes:5g} min  python {' '.join(b.command)}")
        return 0
    failed = 0
    if args.run:
        if args.run == ["quick"]:
            chosen = [b for b in BENCHMARKS if b.quick]
        elif args.run == ["all"]:
            chosen = list(BENCHMARKS)
        else:
            unknown = [k for k in args.run if k not in keys]
            if unknown:
                parser.error(f"unknown benchmark(s) {', '.join(unknown)}; see --list")
            chosen = [keys[k] for k in args.run]
        failed = sum(run(b) != 0 for b in chosen)
    text = render()
    if args.check:
        current = PAGE.read_text(encoding="utf-8") if PAGE.exists() else ""
        if current != text:
            print(f"{PAGE} is out of date: run python docs/gen_benchmarks.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(text, encoding="utf-8")
    print(f"wrote {PAGE}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
