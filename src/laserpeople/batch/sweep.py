"""Parameter sweeps: a grid of settings over labelled recordings, ranked, checked on held-out ones.

A sweep file (TOML)::

    metric = "hota"                 # hota, deta, assa, mota or idf1 (higher is better)
    held_out = ["*seed-1[0-9][0-9].npz"]   # file-name globs: not used to choose
    best = 3                        # settings scored on the held-out recordings

    [grid.leg_tracker]              # a --config section: every key a list of values
    p_occ_approved = [0.7, 0.79]
    [grid.leg_detector]
    threshold = [0.0, 0.5]

The grid is the Cartesian product of every listed value (here 4 settings), each set over the
``--config`` file. Every setting tracks the tuning recordings (those not held out) with
:func:`~laserpeople.batch.run.run_batch` into ``OUT/settings-NNN/`` (with its complete
``config.toml``, usable as ``track --config``); each tracks file is scored against the
recording's truth found by name (:func:`~laserpeople.evaluation.recordings.find_truth`),
pooled over the tuning recordings, and the settings are ranked by ``metric``. The ``best``
first settings then track and score the held-out recordings, whose pooled scores say how
well the choice carries over to recordings it was not made on. ``OUT/sweep.csv`` holds the
ranking.
"""

from __future__ import annotations

import csv
import fnmatch
import io
import itertools
import math
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from laserpeople.batch.options import TrackOptions, resolve
from laserpeople.batch.run import BatchResult, ClusterSpec, open_client, run_batch
from laserpeople.batch.task import TopicRow
from laserpeople.batch.unused import unused_warnings
from laserpeople.errors import ConfigError
from laserpeople.io.paths import make_folder, write_text_file

METRICS = ("hota", "deta", "assa", "mota", "idf1")
"""Metrics a sweep can rank by (pooled over recordings; higher is better)."""


@dataclass(frozen=True)
class SweepSpec:
    """A sweep file (see the module docstring).

    Attributes:
        grid: ``{section: {key: (values...)}}``.
        metric: The ranking metric.
        held_out: Name globs of the held-out recordings.
        best: Settings scored on the held-out recordings.
        path: The sweep file (named by errors of its grid values).
    """

    grid: Mapping[str, Mapping[str, tuple[Any, ...]]]
    metric: str = "hota"
    held_out: tuple[str, ...] = ()
    best: int = 3
    path: Path | None = None

    def settings(self) -> list[dict[str, dict[str, Any]]]:
        """Every setting of the grid, as ``{section: {key: value}}``, in grid order."""
        axes = [(s, k, v) for s, keys in self.grid.items() for k, v in keys.items()]
        out = []
        for values in itertools.product(*(v for _, _, v in axes)):
            setting: dict[str, dict[str, Any]] = {}
            for (section, key, _), value in zip(axes, values, strict=True):
                setting.setdefault(section, {})[key] = value
            out.append(setting)
        return out


def load_sweep(path: str | Path) -> SweepSpec:
    """Read a sweep file.

    Raises:
        ConfigError: Not TOML, an unknown top-level key or metric, an empty grid, or a
            grid key whose value is not a non-empty list.
    """
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError("sweep file not found", path=p) from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ConfigError(f"cannot read the sweep file: {exc}", path=p) from None
    unknown = sorted(set(data) - {"grid", "metric", "held_out", "best"})
    if unknown:
        raise ConfigError(
            f"unknown key(s) {', '.join(unknown)}",
            path=p,
            hint="a sweep file has metric, held_out, best and [grid.SECTION] tables",
        )
    metric = data.get("metric", "hota")
    if metric not in METRICS:
        raise ConfigError(f"metric {metric!r} is not one of {', '.join(METRICS)}", path=p)
    grid: dict[str, dict[str, tuple[Any, ...]]] = {}
    for section, keys in dict(data.get("grid", {})).items():
        if not isinstance(keys, dict):
            raise ConfigError(f"[grid.{section}] must be a table of lists", path=p)
        for key, values in keys.items():
            if not isinstance(values, list) or not values:
                raise ConfigError(
                    f"grid.{section}.{key} must be a non-empty list of values", path=p
                )
            grid.setdefault(section, {})[key] = tuple(values)
    if not grid:
        raise ConfigError("the sweep has no [grid.SECTION] table", path=p)
    held = data.get("held_out", [])
    if isinstance(held, str):
        held = [held]
    best = data.get("best", 3)
    if not isinstance(best, int) or best < 1:
        raise ConfigError(f"best must be a positive integer, not {best!r}", path=p)
    return SweepSpec(grid, metric, tuple(str(h) for h in held), best, p)


@dataclass
class SettingScore:
    """One setting's scores.

    Attributes:
        index: Its number in the grid (the ``settings-NNN`` folder).
        setting: ``{section: {key: value}}``.
        tune: Pooled scores on the tuning recordings (``hota``, ``deta``, ``assa``,
            ``mota``, ``idf1``; NaN when nothing was scored).
        held_out: The same on the held-out recordings (empty when not run).
        failed: Recordings that failed to track or score.
    """

    index: int
    setting: dict[str, dict[str, Any]]
    tune: dict[str, float] = field(default_factory=dict)
    held_out: dict[str, float] = field(default_factory=dict)
    failed: int = 0

    @property
    def label(self) -> str:
        """``section.key=value`` pairs, for tables."""
        return " ".join(f"{s}.{k}={v}" for s, kv in self.setting.items() for k, v in kv.items())


@dataclass
class SweepResult:
    """A sweep's settings, best first (by the tuning score of ``metric``), and the
    options that had no effect on some recordings in every setting's runs (``unused``, one
    line each, as :attr:`~laserpeople.batch.run.BatchResult.unused`)."""

    metric: str
    ranked: list[SettingScore]
    tune: list[str]
    held_out: list[str]
    unused: list[str] = field(default_factory=list)


def split_held_out(
    recordings: Sequence[Path], patterns: Sequence[str]
) -> tuple[list[Path], list[Path]]:
    """Tuning and held-out recordings: held out when the file name matches a pattern."""
    held = [r for r in recordings if any(fnmatch.fnmatch(r.name, p) for p in patterns)]
    return [r for r in recordings if r not in held], held


def run_sweep(
    recordings: Sequence[str | Path],
    out: str | Path,
    options: TrackOptions,
    spec: SweepSpec,
    cluster: ClusterSpec | None = None,
    *,
    force: bool = False,
    on_setting: Callable[[SettingScore], None] | None = None,
) -> SweepResult:
    """Run the sweep (see the module docstring); ``on_setting`` is called per setting done.

    Raises:
        ConfigError: No tuning recording, or a grid section or key the run does not read.
    """
    from laserpeople.config import to_toml

    folder = Path(out)
    tune, held = split_held_out([Path(r) for r in recordings], spec.held_out)
    if not tune:
        raise ConfigError(
            "every recording is held out", hint="held_out must leave recordings to tune on"
        )
    settings = spec.settings()
    try:  # every setting checked before any runs
        resolved = [resolve(options, s) for s in settings]
    except ConfigError as exc:  # one naming no file (the --config's name theirs): the grid's
        if spec.path is not None:
            raise exc.located(spec.path) from None
        raise
    scores = [SettingScore(k, s) for k, s in enumerate(settings)]
    rows: list[TopicRow] = []  # every run's rows, for what its options did not do
    with open_client(cluster or ClusterSpec()) as client:
        for score, res in zip(scores, resolved, strict=True):
            sub = folder / f"settings-{score.index:03d}"
            make_folder(sub, "--out")
            params = [res.tracker_params, res.detector_params, res.grouping, res.leg_fusion]
            static = [getattr(res.static_world, n) for n in res.static_world.__dataclass_fields__]
            text = "\n".join(dict.fromkeys(to_toml(p) for p in [*params, *static]))
            (sub / "config.toml").write_text(text, encoding="utf-8")
            result = run_batch(tune, sub / "tune", res, force=force, client=client)
            rows += result.rows
            score.tune, score.failed = _scored(client, result, sub / "tune")
            if on_setting is not None:
                on_setting(score)
        ranked = sorted(scores, key=lambda s: _rank_key(s.tune.get(spec.metric, math.nan)))
        for score in ranked[: spec.best] if held else []:
            sub = folder / f"settings-{score.index:03d}"
            result = run_batch(
                held, sub / "held_out", resolved[score.index], force=force, client=client
            )
            rows += result.rows
            score.held_out, failed = _scored(client, result, sub / "held_out")
            score.failed += failed
    write_sweep(ranked, folder / "sweep.csv")
    return SweepResult(
        spec.metric,
        ranked,
        [str(t) for t in tune],
        [str(h) for h in held],
        unused_warnings(rows, options),
    )


def _rank_key(value: float) -> float:
    return -value if math.isfinite(value) else math.inf


def _scored(client: Any, result: BatchResult, out: Path) -> tuple[dict[str, float], int]:
    """Score every tracked row of a batch folder against its truth on the cluster; returns
    the pooled scores and the number of failed rows (tracking or scoring)."""
    from laserpeople.evaluation.recordings import batch_pairs, pool, score_recording

    pairs = batch_pairs(out)
    missing = [name for name, _, truth, _ in pairs if truth is None]
    if missing:
        raise ConfigError(
            f"no truth for {', '.join(missing[:3])}",
            hint="a sweep needs labelled recordings: X.people.csv beside X.bag, or .npz",
        )
    futures = [
        client.submit(score_recording, name, tracks, truth, laser_topic=topic, pure=False)
        for name, tracks, truth, topic in pairs
    ]
    scores = client.gather(futures)
    failed = sum(r.status == "failed" for r in result.rows) + sum(bool(s.error) for s in scores)
    pooled = pool(scores)
    if pooled is None:
        return dict.fromkeys(METRICS, math.nan), failed
    h = pooled.hota
    return {
        "hota": h.hota,
        "deta": h.deta,
        "assa": h.assa,
        "mota": pooled.mota,
        "idf1": pooled.idf1,
    }, failed


SWEEP_COLUMNS = (
    "rank",
    "setting",
    "settings",
    *(f"tune_{m}" for m in METRICS),
    *(f"held_out_{m}" for m in METRICS),
    "failed",
)


def write_sweep(ranked: Sequence[SettingScore], path: Path) -> None:
    """The ranking as CSV (:data:`SWEEP_COLUMNS`; held-out columns empty where not run),
    written whole (a failed write leaves the older file as it was)."""
    f = io.StringIO()
    writer = csv.writer(f)
    writer.writerow(SWEEP_COLUMNS)
    for rank, s in enumerate(ranked, start=1):
        writer.writerow(
            [
                rank,
                f"settings-{s.index:03d}",
                s.label,
                *(s.tune.get(m, "") for m in METRICS),
                *(s.held_out.get(m, "") for m in METRICS),
                s.failed,
            ]
        )
    write_text_file(
        path, f.getvalue(), "sweep ranking", hint="free disk space, or give --out a writable folder"
    )


__all__ = [
    "METRICS",
    "SWEEP_COLUMNS",
    "SettingScore",
    "SweepResult",
    "SweepSpec",
    "load_sweep",
    "run_sweep",
    "split_held_out",
    "write_sweep",
]
