"""`laserpeople detect`: detect legs in a recording and write a detections CSV."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from laserpeople.cli.common import (
    OnErrorOption,
    console,
    ignored_sections,
    progress,
    report_damage,
    say,
)
from laserpeople.cli.track import make_detector, tracker_param_classes
from laserpeople.config import check_sections
from laserpeople.detection.report import Confusion, error_table
from laserpeople.errors import ConfigError


def register(app: typer.Typer) -> None:
    """Add the `detect` command to ``app``."""

    @app.command(
        "detect",
        short_help="Detect legs in a recording and write one CSV row per leg.",
        help=(
            "Detect legs in a recording (000 Sec. 2) and write one CSV row per leg: "
            "scan,stamp,x,y,score in the sensor frame. --all-segments writes every segment "
            "with its 14 features; --report compares AdaBoost and the heuristic against "
            "per-beam ground truth (simulated .npz)."
        ),
    )
    def _command(
        recording: Annotated[
            Path, typer.Argument(help="Recording (.bag, .mcap, .db3, .npz, CARMEN .log).")
        ],
        output: Annotated[Path, typer.Option("-o", "--output", help="Detections CSV to write.")],
        topic: Annotated[
            list[str] | None,
            typer.Option("--topic", "-t", help="Laser topic(s) to read (default: all)."),
        ] = None,
        model: Annotated[
            Path | None,
            typer.Option("--model", "-m", help="Model JSON from `laserpeople train`."),
        ] = None,
        detector_name: Annotated[
            str, typer.Option("--detector", help="adaboost or heuristic (000 Sec. 2.3.3).")
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
        from laserpeople.detection.detector import (
            AdaBoostLegDetector,
            HeuristicLegDetector,
            LegDetectorParams,
            ScanClassification,
        )
        from laserpeople.detection.training import beam_truth_labeller
        from laserpeople.io import open_recording
        from laserpeople.io.damage import check_on_error
        from laserpeople.io.detections_csv import DetectionsCsvWriter
        from laserpeople.io.paths import check_outputs

        topic = topic or []
        ignored_sections(
            config, check_sections(config, [LegDetectorParams], tracker_param_classes())
        )
        det = make_detector(detector_name, model, config)
        assert isinstance(det, AdaBoostLegDetector | HeuristicLegDetector)
        # the baseline must see the same segments and distance limits as the detector
        baseline = (
            HeuristicLegDetector(segmentation=det.segmenter.params, params=det.params)
            if report
            else None
        )
        check_outputs({"-o": output}, [recording, model, config])
        rec = open_recording(recording, on_error=check_on_error(on_error))
        counts = {"scans": 0, "segments": 0, "legs": 0, "small": 0, "invalid": 0}
        truth_ada: list[Confusion] = []
        truth_heur: list[Confusion] = []
        try:
            total = sum(t.count for t in rec.topics() if not topic or t.name in topic)
            with DetectionsCsvWriter(output, all_segments=all_segments) as writer:
                for scan in progress(rec.scans(topic or None), total=total):
                    result: ScanClassification = det.classify(scan)
                    counts["scans"] += 1
                    counts["segments"] += len(result.table)
                    counts["legs"] += int(result.is_leg.sum())
                    counts["small"] += int((~result.features.classifiable).sum())
                    counts["invalid"] += result.table.n_invalid
                    if all_segments:
                        t = result.table
                        writer.write_segments(
                            scan,
                            result.features.centres,
                            t.beams[t.offsets[:-1]] if len(t) else np.empty(0),
                            t.sizes,
                            result.is_leg,
                            result.scores,
                            result.features.values,
                        )
                    else:
                        writer.write(det.detections_from(scan, result))
                    if baseline is not None:
                        other = baseline.classify(scan)
                        if scan.labels is None:
                            continue
                        ok = result.features.classifiable
                        truth = beam_truth_labeller(scan, result.table, result.features)[ok]
                        truth_ada.append(Confusion.of(np.where(result.is_leg[ok], 1, -1), truth))
                        truth_heur.append(Confusion.of(np.where(other.is_leg[ok], 1, -1), truth))
        finally:
            report_damage(rec)
            rec.close()
        say(
            f"{counts['scans']} scans, {counts['segments']} segments "
            f"({counts['small']} with fewer than 3 points not classified), "
            f"{counts['legs']} legs detected, {counts['invalid']} invalid beams skipped; "
            f"wrote {output}"
        )
        if report:
            if not truth_ada:
                raise ConfigError(
                    "--report needs per-beam ground truth, which this recording lacks",
                    path=recording,
                    hint="use a simulated .npz, or `laserpeople train --report` with bags",
                )
            ada = _sum(truth_ada)
            heur = _sum(truth_heur)
            console.print(ada.table("Confusion matrix, AdaBoost (layout of 000 Tables 2-5)"))
            console.print(heur.table("\nConfusion matrix, heuristic (000 Sec. 2.3.3)"))
            console.print(
                error_table(
                    {"Heuristic Approach": heur, "AdaBoost": ada},
                    "\nComparison with the heuristic approach (000 Table 7)",
                )
            )


def _sum(parts: list[Confusion]) -> Confusion:
    tp = fn = fp = tn = 0
    for c in parts:
        tp, fn, fp, tn = tp + c.tp, fn + c.fn, fp + c.fp, tn + c.tn
    return Confusion(tp, fn, fp, tn)
