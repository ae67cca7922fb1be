"""`laserpeople bench`: how fast reading, leg detection and each tracker run on this machine."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from laserpeople.cli.common import (
    OnErrorOption,
    console,
    given_options,
    plain,
    progress,
    say,
    warn,
)
from laserpeople.errors import ConfigError, LaserPeopleError

if TYPE_CHECKING:
    from laserpeople.scan import Scan
    from laserpeople.tracking.registry import TrackerEntry


def register(app: typer.Typer) -> None:
    """Add the `bench` command to ``app``."""

    @app.command("bench")
    def bench(
        ctx: typer.Context,
        recording: Annotated[
            Path | None,
            typer.Argument(help="Recording to time on (default: a simulated scenario)."),
        ] = None,
        topic: Annotated[str | None, typer.Option("--topic", "-t", help="Laser topic.")] = None,
        scenario: Annotated[
            str, typer.Option(help="Scenario simulated when no recording is given.")
        ] = "demo",
        seconds: Annotated[
            float | None, typer.Option(help="Length of the simulated scenario [s].")
        ] = None,
        seed: Annotated[int, typer.Option(help="Seed of the simulated scenario.")] = 0,
        tracker: Annotated[
            list[str] | None,
            typer.Option("--tracker", help="Tracker to time (repeatable; default: all)."),
        ] = None,
        detector: Annotated[
            str, typer.Option(help="Leg detector: adaboost or heuristic.")
        ] = "adaboost",
        repeat: Annotated[
            int, typer.Option(min=1, max=1000, help="Passes over the scans per stage.")
        ] = 3,
        max_scans: Annotated[
            int, typer.Option(min=1, max=10**9, help="Time at most this many scans.")
        ] = 2000,
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
        on_error: OnErrorOption = "stop",
    ) -> None:
        """Time reading, leg detection and tracking: median and p95 ms per scan, scans/s
        (wall time), and the median process CPU time per scan with its scans/s (what the
        stage costs, apart from other work on the machine)."""
        from laserpeople.cli.track import make_detector
        from laserpeople.evaluation.speed import (
            StageTiming,
            peak_memory_mib,
            time_per_item,
            time_reading,
        )
        from laserpeople.tracking import registry

        if recording is not None:
            unused = given_options(ctx, ("scenario", "seconds", "seed"))
            if unused:
                warn(
                    f"{', '.join(unused)} set the simulated scenario, which is not run: the "
                    f"scans timed are those of {recording}"
                )
        names = tracker or list(registry.TRACKERS)
        entries = [registry.get(n) for n in names]
        timings: list[StageTiming] = []
        if recording is None:
            from laserpeople.sim import run_scenario

            say(f"simulating scenario {scenario!r} (seed {seed})")
            simulated = run_scenario(scenario, seconds=seconds, seed=seed).scans
            first = simulated[0].sensor
            scans = [s for s in simulated if s.sensor == first][:max_scans]
            source = f"scenario {scenario} ({first})"
        else:
            from laserpeople.io import open_recording
            from laserpeople.io.damage import check_on_error

            def stream() -> Iterator[Scan]:
                rec = open_recording(recording, on_error=check_on_error(on_error))
                try:
                    yield from itertools.islice(rec.scans([topic] if topic else None), max_scans)
                finally:
                    rec.close()

            scans = list(stream())
            if not scans:
                raise LaserPeopleError("no scans to time", path=recording)
            sensors = {s.sensor for s in scans}
            if len(sensors) > 1:
                raise ConfigError(
                    f"the recording has several laser topics ({', '.join(sorted(sensors))})",
                    path=recording,
                    hint="choose one with --topic",
                )
            timings.append(time_reading("read", stream, repeat))
            source = str(recording)
        say(f"timing {len(scans)} scans of {source}, {repeat} passes per stage")
        from laserpeople.pipeline import (
            FrameChooser,
            Pipeline,
            laser_frames,
            observe_stages_for,
        )

        # the frames the trackers see: the pipeline's, observed once for all of them
        consumes = frozenset().union(*(e.consumes for e in entries))
        preprocess, observe_stages = observe_stages_for(
            consumes, make_detector(detector, None, None)
        )
        chooser = FrameChooser()
        observe = Pipeline(
            chooser(laser_frames(scans)), preprocess=preprocess, observe=observe_stages
        )
        frames = [step.frame for step in observe]
        # the trackers are timed on the frames of that frame (without a pose, none in the world)
        say(f"trackers timed on {len(frames)} frames, {chooser.stats.summary()}")
        stages: list[tuple[str, Callable[[], Callable[[Any], object]], Sequence[Any]]] = [
            ("detect", lambda: make_detector(detector, None, None).detect, scans)
        ]
        stages += [(f"track {e.name}", _fresh_update(e), frames) for e in entries]
        for name, make_step, items in progress(stages, len(stages), "stages"):
            timings.append(time_per_item(name, make_step, items, repeat))
        memory = peak_memory_mib()
        from laserpeople.detection.compiled import IMPLEMENTATION as DETECTION
        from laserpeople.tracking.kalman import IMPLEMENTATION as KALMAN
        from laserpeople.tracking.mht.listing import IMPLEMENTATION as LISTING

        if as_json:
            import json  # (at use: not for every start-up)

            print(
                json.dumps(
                    {
                        "source": source,
                        "scans": len(scans),
                        "beams": scans[0].n_beams,
                        "stages": [t.as_dict() for t in timings],
                        "tracking_frame": chooser.stats.frame,
                        "tracked_frames": len(frames),
                        "peak_memory_mib": memory,
                        "mht_listing": LISTING,
                        "leg_detection": DETECTION,
                        "kalman_steps": KALMAN,
                    }
                )
            )
            return
        from rich.table import Table

        table = Table(title=plain(f"{source}: {len(scans)} scans, {scans[0].n_beams} beams"))
        columns = (
            "stage",
            "median ms/scan",
            "p95 ms/scan",
            "scans/s",
            "CPU ms/scan",
            "CPU scans/s",
        )
        for col in columns:
            table.add_column(col, justify="left" if col == "stage" else "right")
        for t in timings:
            table.add_row(
                t.stage,
                f"{t.median_ms:.3f}",
                f"{t.p95_ms:.3f}",
                f"{t.scans_per_s:,.0f}",
                f"{t.cpu_median_ms:.3f}",
                f"{t.cpu_scans_per_s:,.0f}",
            )
        console.print(table)
        say(f"leg MHT listing of the k best children: {LISTING}")
        say(f"segment features and AdaBoost margins of leg detection: {DETECTION}")
        say(f"Kalman steps of the tracks (prediction, gating, updates): {KALMAN}")
        console.print(f"peak memory {memory:.0f} MiB")


def _fresh_update(entry: TrackerEntry) -> Callable[[], Callable[[Any], object]]:
    """A maker of a new tracker's ``update(frame)`` with default parameters, one per timing
    pass; the leg MHT's people learn and ask their static world model (``auto``) in it, as
    in ``track``."""
    from laserpeople.pipeline.static_people import StaticFed, people_static_model, uses_static_model

    def make() -> Callable[[Any], object]:
        tracker = entry.make()
        model = people_static_model("auto") if uses_static_model(tracker) else None
        return StaticFed(tracker, model).update if model is not None else tracker.update

    return make
