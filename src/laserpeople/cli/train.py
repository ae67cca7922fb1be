"""`laserpeople train`: train the AdaBoost leg detector (Arras et al. 2008) and report on it."""

from __future__ import annotations

import datetime
import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from laserpeople.cli.common import OnErrorOption, console, progress, report_damage, say, warn
from laserpeople.errors import ConfigError, RecordingError

MAX_ROUNDS = 1000
"""Most boosting rounds ``train -T`` accepts (100 times the paper's 10)."""
MIN_EXAMPLES = 20
"""Fewest legs, and fewest non-legs, ``laserpeople train`` fits a model on (``--min-examples``
lowers it). Below it AdaBoost's stumps fit the few examples rather than legs: trained on 5
legs (and 50 non-legs) drawn at random from neko7055 frames 0-59, 20 models found 77 % of
the legs of frames 60-119 on average and 35 % at worst; on 20 legs, 95 % and 88 % at worst
(109 legs: 97 %)."""
MAX_JUMP_DISTANCE = 10.0
"""Largest ``--jump-distance`` [m] (a leg segment is a few decimetres wide)."""

if TYPE_CHECKING:
    from laserpeople.detection.training import LabelledSegments, Unlabelled
    from laserpeople.segmentation import JumpDistanceParams


def _show(table: str) -> None:
    """Print a report table as plain text: its headers hold brackets ("distance [m]") that
    rich would take for markup and drop."""
    console.print(table, markup=False, highlight=False)


def _frames(text: str | None) -> list[int] | None:
    if text is None:
        return None
    try:
        return parse_frames(text)
    except ValueError as exc:
        raise ConfigError(f"bad frame list {text!r}: {exc}", hint="write e.g. 0-59") from exc


def parse_frames(text: str) -> list[int]:
    """``"0-59"`` or ``"0,3,5-9"`` -> frame numbers."""
    out: list[int] = []
    for part in text.split(","):
        part = part.strip()
        if "-" in part:
            a, b = (int(x) for x in part.split("-", 1))
            if b < a:
                raise ValueError(f"{part} goes backwards (write the first frame first)")
            out.extend(range(a, b + 1))
        elif part:
            out.append(int(part))
    return out


def load_labelled(
    recordings: list[Path],
    positives: list[Path],
    negatives: list[Path],
    neko: Path | None,
    neko_frames: str | None,
    unlabelled: Unlabelled,
    segmentation: JumpDistanceParams,
    what: str = "recordings",
    augment: bool = False,
    on_error: str = "stop",
) -> LabelledSegments:
    """Labelled segments from every kind of labelled input the command accepts (with
    ``augment``, each as the scanners of :data:`~laserpeople.detection.augment.TRANSFER_VARIANTS`
    would see it, see :func:`~laserpeople.detection.training.augmented_input`);
    ``on_error`` is the readers' policy for damaged scans (skipped ones are warned of; with
    ``augment`` a damaged input stops the command)."""
    from laserpeople.detection.training import (
        InputKind,
        LabelledSegments,
        all_negative,
        augmented_input,
        leg_tracker_positive,
        neko_segments,
        truth_segments,
    )
    from laserpeople.io import open_recording
    from laserpeople.io.damage import check_on_error

    jobs: list[tuple[InputKind, Path]] = (
        [("truth", p) for p in recordings]
        + [("positive", p) for p in positives]
        + [("negative", p) for p in negatives]
    )
    policy = check_on_error(on_error)
    parts: list[LabelledSegments] = []
    for kind, path in progress(jobs, total=len(jobs), description=what):
        damage: list[str] = []
        if augment:
            part = augmented_input(kind, path, segmentation, unlabelled)
        elif kind == "truth":
            rec = open_recording(path, on_error=policy)
            try:
                part = truth_segments(rec.scans(), path.name, segmentation)
            finally:
                report_damage(rec)
                rec.close()
        elif kind == "positive":
            part = leg_tracker_positive(
                path,
                unlabelled=unlabelled,
                segmentation=segmentation,
                on_error=policy,
                damage=damage,
            )
        else:
            part = all_negative(path, segmentation=segmentation, on_error=policy, damage=damage)
        for text in damage:
            warn(text)
        say(f"{path.name}: {part.summary()}")
        parts.append(part)
    if neko is not None:
        part = (
            augmented_input("neko", neko, segmentation, unlabelled, _frames(neko_frames))
            if augment
            else neko_segments(neko, _frames(neko_frames))
        )
        say(f"{neko.name} (neko7055, frames {neko_frames or 'all'}): {part.summary()}")
        parts.append(part)
    return LabelledSegments.concat(parts)


def register(app: typer.Typer) -> None:
    """Add the `train` command to ``app``."""

    @app.command(
        "train",
        short_help="Train the AdaBoost leg detector from labelled scans.",
        help=(
            "Train the AdaBoost leg detector (Arras et al. 2008 Table 1) from labelled segments: "
            "recordings "
            "with per-beam ground truth (.npz from the simulator), leg_tracker-style "
            "--positives bags (scans + /leg_cluster_positions), --negatives recordings "
            "(every segment is not a leg) and the neko7055 data (--neko)."
        ),
    )
    def _command(
        output: Annotated[Path, typer.Option("-o", "--output", help="Model JSON to write.")],
        recordings: Annotated[
            list[Path] | None,
            typer.Argument(help="Recordings with per-beam ground truth (e.g. simulated .npz)."),
        ] = None,
        rounds: Annotated[
            int, typer.Option("--rounds", "-T", help="Boosting rounds T (Arras et al. 2008: 10).")
        ] = 10,
        features: Annotated[
            str, typer.Option("--features", help="Features: 1-13 (geometry) or 1-14 (+ motion).")
        ] = "1-13",
        positives: Annotated[
            list[Path] | None,
            typer.Option("--positives", help="Bags with /training_scan + /leg_cluster_positions."),
        ] = None,
        negatives: Annotated[
            list[Path] | None,
            typer.Option("--negatives", help="Recordings in which no segment is a leg."),
        ] = None,
        neko: Annotated[
            Path | None,
            typer.Option("--neko", help="neko7055 directory (xy_data.txt + labels json)."),
        ] = None,
        neko_frames: Annotated[
            str | None,
            typer.Option("--neko-frames", help="neko7055 frames to use, e.g. 0-59 (default all)."),
        ] = None,
        unlabelled: Annotated[
            str,
            typer.Option(
                "--unlabelled",
                help=(
                    "Unlabelled segments of --positives bags far from any label: drop "
                    "(default; those scans contain unlabelled people) or negative."
                ),
            ),
        ] = "drop",
        jump_distance: Annotated[
            float,
            typer.Option(
                "--jump-distance",
                help="Segmentation threshold [m] (0.13: the leg_tracker label rule).",
            ),
        ] = 0.13,
        augment: Annotated[
            bool,
            typer.Option(
                "--augment",
                help=(
                    "Train on every training scan resampled to 0.25-1 deg and in a world "
                    "scaled by 0.7-2 (for a model that must work on another scanner; see "
                    "docs/leg-detection.md). Test sets stay as recorded."
                ),
            ),
        ] = False,
        report: Annotated[
            bool,
            typer.Option(
                "--report", help="Print confusion matrices (Arras et al. 2008 Tables 2-8)."
            ),
        ] = False,
        test: Annotated[
            list[Path] | None, typer.Option("--test", help="Held-out labelled recordings.")
        ] = None,
        test_positives: Annotated[
            list[Path] | None, typer.Option("--test-positives", help="Held-out positive bags.")
        ] = None,
        test_negatives: Annotated[
            list[Path] | None, typer.Option("--test-negatives", help="Held-out negative bags.")
        ] = None,
        test_neko_frames: Annotated[
            str | None,
            typer.Option("--test-neko-frames", help="Held-out neko7055 frames, e.g. 60-119."),
        ] = None,
        min_examples: Annotated[
            int,
            typer.Option(
                "--min-examples",
                min=1,
                help=f"Fewest legs and fewest non-legs to train on (default {MIN_EXAMPLES}; "
                "fewer give a model that misses most legs).",
            ),
        ] = MIN_EXAMPLES,
        on_error: OnErrorOption = "stop",
    ) -> None:
        from laserpeople.detection.model_file import parse_feature_set
        from laserpeople.detection.report import (
            Confusion,
            best_features,
            error_table,
            errors_by_distance,
            heuristic_predictions,
            predict,
            train_model,
        )
        from laserpeople.detection.training import too_few_examples
        from laserpeople.segmentation import JumpDistanceParams

        positives, negatives = positives or [], negatives or []
        test, test_positives, test_negatives = (
            test or [],
            test_positives or [],
            test_negatives or [],
        )
        try:
            feature_set = parse_feature_set(features)
        except ValueError as exc:
            raise ConfigError(str(exc), hint="use --features 1-13 or 1-14") from exc
        if not 1 <= rounds <= MAX_ROUNDS:
            raise ConfigError(
                f"--rounds must be 1-{MAX_ROUNDS:,}, got {rounds}",
                hint="Arras et al. 2008 use 10 boosting rounds",
            )
        if not (math.isfinite(jump_distance) and 0.0 < jump_distance <= MAX_JUMP_DISTANCE):
            raise ConfigError(
                f"--jump-distance must be a distance in (0, {MAX_JUMP_DISTANCE:g}] m, "
                f"got {jump_distance}",
                hint="0.13 is the leg_tracker label rule, 0.1 the neko7055 one",
            )
        if unlabelled not in ("negative", "drop"):
            raise ConfigError(f"--unlabelled must be negative or drop, got {unlabelled!r}")
        mode: Unlabelled = "negative" if unlabelled == "negative" else "drop"
        from laserpeople.io.neko import NEKO_LABELS, NEKO_XY
        from laserpeople.io.paths import check_output_format, check_outputs

        check_outputs(
            {"-o": output},
            [
                *(recordings or []),
                *positives,
                *negatives,
                neko,
                # (the folder's files: `-o NEKO/leg_segment_labels.json` would replace them)
                *((neko / NEKO_XY, neko / NEKO_LABELS) if neko is not None else ()),
                *test,
                *test_positives,
                *test_negatives,
            ],
        )
        check_output_format("-o", output, ".json", "a model JSON")
        seg = JumpDistanceParams(threshold=jump_distance)
        data = load_labelled(
            list(recordings or []),
            positives,
            negatives,
            neko,
            neko_frames,
            mode,
            seg,
            augment=augment,
            on_error=on_error,
        )
        say(f"training on {data.summary()}")
        lacking = too_few_examples(data, min_examples)
        why = (
            f"at least {MIN_EXAMPLES} of each are needed for a model that finds legs: trained "
            "on 5 of neko7055's legs, models found as few as 35 % of its held-out legs, "
            "on 20 at least 88 % (docs/leg-detection.md)"
        )
        recorded = " as recorded" if augment else ""
        if lacking is not None:
            raise RecordingError(
                f"too few examples to train on: {lacking}{recorded}; "
                + (why if min_examples == MIN_EXAMPLES else f"--min-examples is {min_examples}"),
                hint="add labelled data (recordings with truth, --positives, --negatives, "
                "--neko), or lower --min-examples to train anyway",
            )
        lacking = too_few_examples(data, MIN_EXAMPLES)
        if lacking is not None:
            warn(f"training on only {lacking}{recorded} (--min-examples {min_examples}): {why}")
        provenance = {
            "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "data": [str(p) for p in [*(recordings or []), *positives, *negatives]]
            + ([f"{neko} frames {neko_frames or 'all'}"] if neko else []),
            "unlabelled_in_positives": mode,
        }
        if augment:
            from laserpeople.detection.augment import TRANSFER_VARIANTS

            provenance["augmentation"] = [v.name for v in TRANSFER_VARIANTS]
        model = train_model(data, feature_set, rounds, jump_distance, provenance)
        model.save(output)
        say(f"wrote {output} ({len(model.classifier.stumps)} weak classifiers)")
        if not report:
            return
        sets = [("training set", data)]
        if test or test_positives or test_negatives or test_neko_frames:
            held = load_labelled(
                list(test),
                test_positives,
                test_negatives,
                neko if test_neko_frames else None,
                test_neko_frames,
                mode,
                seg,
                what="test recordings",
                on_error=on_error,
            )
            sets.append(("test set", held))
        other = tuple(range(1, 14)) if 14 in feature_set else (*feature_set, 14)
        other_model = train_model(data, other, rounds, jump_distance)
        for name, part in sets:
            if len(part) == 0:
                continue
            decisions = {"Heuristic": heuristic_predictions(part), "AdaBoost": predict(model, part)}
            ada = Confusion.of(decisions["AdaBoost"], part.labels)
            heur = Confusion.of(decisions["Heuristic"], part.labels)
            alt = Confusion.of(predict(other_model, part), part.labels)
            _show(ada.table(f"\nConfusion matrix, {name} (layout of Arras et al. 2008 Tables 2-5)"))
            _show(
                error_table(
                    {"Heuristic Approach": heur, "AdaBoost": ada},
                    f"\nComparison with the heuristic approach, {name} (Arras et al. 2008 Table 7)",
                )
            )
            _show(
                errors_by_distance(
                    decisions, part, title=f"\nErrors by distance from the sensor, {name}"
                )
            )
            c_with, c_without = (ada, alt) if 14 in feature_set else (alt, ada)
            _show(
                error_table(
                    {"Without Motion Feature": c_without, "With Motion Feature": c_with},
                    f"\nEffect of the motion feature #14, {name} (Arras et al. 2008 Table 8)",
                )
            )
        console.print(
            "\nFive best features (Arras et al. 2008 Table 6): "
            + ", ".join(map(str, best_features(model)))
        )
