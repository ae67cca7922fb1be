"""`laserpeople detect`: detect legs in a recording and write a detections CSV."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from laserpeople.cli.common import (
    MountOption,
    OnErrorOption,
    WorldFrameOption,
    console,
    ignored_sections,
    no_scan_read,
    progress,
    report_damage,
    say,
    warn,
)
from laserpeople.cli.stopping import stop_name, stop_status
from laserpeople.cli.track import TopicsOption, make_detector, topics_from, tracker_param_classes
from laserpeople.config import check_sections, load_config
from laserpeople.errors import ConfigError

if TYPE_CHECKING:
    from laserpeople.detection.report import Confusion


def register(app: typer.Typer) -> None:
    """Add the `detect` command to ``app``."""

    @app.command(
        "detect",
        short_help="Detect legs in a recording and write one CSV row per leg.",
        help=(
            "Detect legs in a recording (Arras et al. 2008 Sec. 2) and write one CSV row per leg: "
            "scan,stamp,x,y,score in the sensor frame, and the topic. --fuse groups several "
            "lasers into frames and writes their legs in the world frame (topic 'fused'). "
            "--all-segments writes every segment with its 14 features; --report compares "
            "AdaBoost and the heuristic against per-beam ground truth (simulated .npz)."
        ),
    )
    def _command(
        recording: Annotated[
            Path, typer.Argument(help="Recording (.bag, .mcap, .db3, .npz, CARMEN .log).")
        ],
        output: Annotated[Path, typer.Option("-o", "--output", help="Detections CSV to write.")],
        topic: Annotated[
            list[str] | None,
            typer.Option("--topic", "-t", help="Laser topic (repeatable; default: all)."),
        ] = None,
        topics: TopicsOption = None,
        fuse: Annotated[
            bool,
            typer.Option(
                "--fuse",
                help="Group the lasers into frames by time and write their legs in one frame "
                "(world; needs poses, e.g. --mount) with topic 'fused'.",
            ),
        ] = False,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        model: Annotated[
            Path | None,
            typer.Option("--model", "-m", help="Model JSON from `laserpeople train`."),
        ] = None,
        detector_name: Annotated[
            str,
            typer.Option(
                "--detector", help="adaboost or heuristic (Arras et al. 2008 Sec. 2.3.3)."
            ),
        ] = "adaboost",
        all_segments: Annotated[
            bool,
            typer.Option("--all-segments", help="Write every segment with features and score."),
        ] = False,
        report: Annotated[
            bool,
            typer.Option("--report", help="Print confusion matrices against beam ground truth."),
        ] = False,
        config: Annotated[
            Path | None,
            typer.Option("--config", help="TOML file with [leg_detector] parameters."),
        ] = None,
        on_error: OnErrorOption = "stop",
    ) -> None:
        import numpy as np

        from laserpeople.detection.detector import (
            AdaBoostLegDetector,
            HeuristicLegDetector,
            LegDetectorParams,
        )
        from laserpeople.detection.features import FEATURE_NAMES
        from laserpeople.detection.report import Confusion, error_table
        from laserpeople.detection.training import beam_truth_labeller
        from laserpeople.errors import LaserPeopleError
        from laserpeople.io.detections_csv import DetectionsCsvWriter
        from laserpeople.io.paths import check_output_format, check_outputs
        from laserpeople.pipeline import (
            DetectionsCsvSink,
            DetectLegs,
            FrameChooser,
            GroupingParams,
            LegFusionParams,
            Pipeline,
            RecordingFrames,
            laser_frames,
            open_source,
            resolve_topics,
        )
        from laserpeople.pipeline.sinks import left_as_it_was

        wanted = topics_from(topic, topics)
        ignored_sections(
            config,
            check_sections(
                config,
                [LegDetectorParams, GroupingParams, LegFusionParams],
                tracker_param_classes() if config is not None else (),
            ),
        )
        if fuse and (all_segments or report):
            raise ConfigError("--fuse writes the legs of the fused frames only", hint=(
                "drop --all-segments/--report, or --fuse"
            ))  # fmt: skip
        det = make_detector(detector_name, model, config)
        assert isinstance(det, AdaBoostLegDetector | HeuristicLegDetector)
        # the baseline must see the same segments and distance limits as the detector
        baseline = (
            HeuristicLegDetector(segmentation=det.segmenter.params, params=det.params)
            if report
            else None
        )
        check_outputs({"-o": output}, [recording, model, config])
        check_output_format("-o", output, ".csv", "a detections CSV")
        rec = open_source(recording, world_frame, mount or [], on_error)
        if report and not rec.has_truth:  # (before the run, not after it)
            rec.close()
            raise _no_beam_truth(recording)
        names = resolve_topics(rec, wanted or ["all"])
        total = sum(t.count for t in rec.topics() if t.name in names)
        stage = DetectLegs(det, load_config(LegFusionParams, config), keep_classification=True)
        if fuse:
            frames: Any = RecordingFrames(rec, names, grouping=load_config(GroupingParams, config))
            total = frames.total
        else:  # every laser in its own sensor frame, rows named by topic
            frames = FrameChooser("sensor")(laser_frames(rec.scans(names)))
        sink = DetectionsCsvSink(output, per_laser=not fuse, stage=stage)
        if all_segments:
            sink.abandon()  # (unused: the file is left to the writer of the segments)
            segments = DetectionsCsvWriter(
                output,
                segment_columns=tuple(f"f{i + 1}_{n}" for i, n in enumerate(FEATURE_NAMES)),
                topic="",
            )
        pipe = Pipeline(frames, observe=[stage], sinks=[] if all_segments else [sink])
        from laserpeople.pipeline.empty_scans import EmptyScanCheck

        counts = {"scans": 0, "segments": 0, "legs": 0, "small": 0, "invalid": 0}
        beams = EmptyScanCheck()
        truth_ada: list[Confusion] = []
        truth_heur: list[Confusion] = []
        interrupted = 0  # the exit status of a stop by Ctrl-C or SIGTERM
        left: str | None = None  # what an interrupt before the first scan left as it was
        try:
            for step in progress(pipe, total=total):
                for scan, result in zip(step.frame.scans, stage.classifications, strict=True):
                    counts["scans"] += 1
                    counts["segments"] += len(result.table)
                    counts["legs"] += int(result.is_leg.sum())
                    counts["small"] += int((~result.features.classifiable).sum())
                    counts["invalid"] += result.table.n_invalid
                    beams.count(scan)
                    if all_segments:
                        t = result.table
                        segments.write_segments(
                            scan,
                            result.features.centres,
                            t.beams[t.offsets[:-1]] if len(t) else np.empty(0),
                            t.sizes,
                            result.is_leg,
                            result.scores,
                            result.features.values,
                        )
                    if baseline is not None:
                        other = baseline.classify(scan)
                        if scan.labels is None:
                            continue
                        ok = result.features.classifiable
                        truth = beam_truth_labeller(scan, result.table, result.features)[ok]
                        truth_ada.append(Confusion.of(np.where(result.is_leg[ok], 1, -1), truth))
                        truth_heur.append(Confusion.of(np.where(other.is_leg[ok], 1, -1), truth))
        except KeyboardInterrupt as exc:  # Ctrl-C, SIGTERM: close the CSV with the scans done
            interrupted = stop_status(exc)
            pipe.close(failed=exc)  # (as a failed run: a CSV no scan came to stays as it was)
            left = sink.left if not all_segments else None
            if all_segments:
                existed = not segments.created
                if segments.abandon():
                    left = left_as_it_was("detections CSV", output, existed)
        except BaseException as exc:
            existed = all_segments and not segments.created
            if all_segments and segments.abandon() and isinstance(exc, LaserPeopleError):
                exc.noted(left_as_it_was("detections CSV", output, existed))
            raise
        finally:
            if all_segments:
                segments.close()
            report_damage(rec)
            rec.close()
        if fuse:
            for line in frames.summary():
                say(line)
            if stage.duplicates:
                say(f"{stage.duplicates} detections dropped as another laser's view of a leg")
        if left is not None:  # stopped before the first scan: the CSV was not written
            warn(f"interrupted ({stop_name(interrupted)}) before the first scan: {left}")
            raise typer.Exit(interrupted)
        say(
            f"{counts['scans']} scans, {counts['segments']} segments "
            f"({counts['small']} with fewer than 3 points not classified), "
            f"{counts['legs']} legs detected, {counts['invalid']:,} invalid beams skipped"
            + (f" ({beams.kinds_text()})" if counts["invalid"] else "")
            + f"; wrote {output}"
        )
        if interrupted:
            written = counts["scans"] if all_segments else sink.scans
            warn(
                f"interrupted ({stop_name(interrupted)}) after {written} scans: {output} holds "
                "the legs of those scans and is a complete CSV"
            )
            raise typer.Exit(interrupted)
        if not counts["scans"]:
            raise no_scan_read(recording, output)
        if report:
            if not truth_ada:
                raise _no_beam_truth(recording)
            ada = _sum(truth_ada)
            heur = _sum(truth_heur)
            console.print(
                ada.table("Confusion matrix, AdaBoost (layout of Arras et al. 2008 Tables 2-5)")
            )
            console.print(
                heur.table("\nConfusion matrix, heuristic (Arras et al. 2008 Sec. 2.3.3)")
            )
            console.print(
                error_table(
                    {"Heuristic Approach": heur, "AdaBoost": ada},
                    "\nComparison with the heuristic approach (Arras et al. 2008 Table 7)",
                )
            )


def _no_beam_truth(recording: Path) -> ConfigError:
    """The error of ``--report`` on a recording without per-beam ground truth."""
    return ConfigError(
        "--report needs per-beam ground truth, which this recording lacks",
        path=recording,
        hint="use a simulated .npz, or `laserpeople train --report` with bags",
    )


def _sum(parts: list[Confusion]) -> Confusion:
    from laserpeople.detection.report import Confusion

    tp = fn = fp = tn = 0
    for c in parts:
        tp, fn, fp, tn = tp + c.tp, fn + c.fn, fp + c.fp, tn + c.tn
    return Confusion(tp, fn, fp, tn)
