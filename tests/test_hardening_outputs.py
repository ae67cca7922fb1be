"""No command writes over its input (issue 36, cause 8).

The commands' file options are discovered from the command line itself: every option or
argument typed ``Path`` must be classified below as an input or an output, so a new
command's output option cannot be forgotten. Then every command runs with each of its
output options pointing at each of its inputs; it must refuse before touching the file.
"""

from __future__ import annotations

import shutil
import typing
from pathlib import Path

import pytest
import typer
from typer.testing import CliRunner

from laserpeople.cli import app
from laserpeople.errors import ConfigError

INPUTS = {
    ("info", "recording"),
    ("detect", "recording"),
    ("detect", "model"),
    ("detect", "config"),
    ("train", "recordings"),
    ("train", "positives"),
    ("train", "negatives"),
    ("train", "neko"),
    ("train", "test"),
    ("train", "test_positives"),
    ("train", "test_negatives"),
    ("track", "recording"),
    ("track", "config"),
    ("track", "model"),
    ("track", "map_path"),
    ("track", "mounts"),
    ("evaluate", "tracks_args"),
    ("fit", "recordings"),
    ("fit", "config"),
    ("bench", "recording"),
    ("view", "recording"),
    ("view", "tracks"),
    ("align", "recording"),
    ("batch", "config"),
    ("batch", "map_path"),
    ("batch", "model"),
    ("batch", "sweep"),
    ("live", "config"),
    ("live", "map_path"),
    ("live", "model"),
}
"""Every ``Path`` parameter a command reads."""

TEXT_INPUTS = {
    ("evaluate", "truth"),
    ("fit", "truth"),
    ("view", "truth"),
    ("batch", "recordings"),
}
"""File inputs given as text (``BAG[:TOPIC]``, or ``recording``)."""

OUTPUTS = {
    ("simulate", "output"),
    ("detect", "output"),
    ("train", "output"),
    ("track", "output"),
    ("track", "bag"),
    ("track", "plot"),
    ("track", "animate"),
    ("evaluate", "per_frame"),
    ("fit", "output"),
    ("view", "output"),
    ("demo", "out_dir"),
    ("align", "output"),
    ("batch", "out"),
    ("live", "record"),
}
"""Every ``Path`` parameter a command writes."""

BASE: dict[str, list[str]] = {
    "detect": ["{recording}", "-o", "{output}", "--model", "{model}", "--config", "{config}"],
    "train": [
        "{recordings}",
        "-o",
        "{output}",
        "--positives",
        "{positives}",
        "--negatives",
        "{negatives}",
        "--neko",
        "{neko}",
        "--test",
        "{test}",
        "--test-positives",
        "{test_positives}",
        "--test-negatives",
        "{test_negatives}",
    ],
    "track": [
        "{recording}",
        "-o",
        "{output}",
        "--config",
        "{config}",
        "--model",
        "{model}",
        "--map",
        "{map_path}",
        "--mounts",
        "{mounts}",
    ],
    "evaluate": ["{tracks_args}", "--truth", "{truth}", "--per-frame", "{per_frame}"],
    "fit": ["{recordings}", "--truth", "{truth}", "-o", "{output}", "--config", "{config}"],
    "view": ["{recording}", "-o", "{output}", "--tracks", "{tracks}", "--truth", "{truth}"],
    "align": ["{recording}", "-o", "{output}"],
    "batch": [
        "{recordings}",
        "--out",
        "{output}",
        "--config",
        "{config}",
        "--model",
        "{model}",
        "--map",
        "{map_path}",
        "--sweep",
        "{sweep}",
    ],
    "live": ["--config", "{config}", "--model", "{model}", "--map", "{map_path}"],
}
"""A command line of each command with inputs, every file named by its parameter."""


def _path_params() -> set[tuple[str, str]]:
    group = typer.main.get_command(app)
    found = set()
    for name, command in group.commands.items():  # type: ignore[attr-defined]
        for param in command.params:
            annotation = param.type_descriptor.annotation
            if annotation is Path or Path in typing.get_args(annotation):
                found.add((name, param.name))
    return found


def _opts() -> dict[tuple[str, str], str]:
    group = typer.main.get_command(app)
    return {
        (name, p.name): p.opts[0]
        for name, command in group.commands.items()  # type: ignore[attr-defined]
        for p in command.params
    }


def test_every_file_parameter_is_an_input_or_an_output() -> None:
    found = _path_params()
    assert found, "no Path parameters discovered: the discovery is broken"
    unknown = found - INPUTS - OUTPUTS
    assert not unknown, f"classify these file parameters as input or output: {sorted(unknown)}"
    assert not (INPUTS | OUTPUTS) - found, "a classified parameter no longer exists"
    assert set(BASE) == {c for c, _ in OUTPUTS} & {c for c, _ in INPUTS | TEXT_INPUTS}


def _cases() -> list[tuple[str, str, str]]:
    return sorted(
        (command, out, src)
        for command, out in OUTPUTS
        for c, src in INPUTS | TEXT_INPUTS
        if c == command
    )


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """One file (or folder) for each input parameter, each its own."""
    from laserpeople.detection.detector import default_model
    from laserpeople.io.truth_csv import write_truth_csv

    here = Path(__file__).parent / "data" / "hostile"
    d = tmp_path_factory.mktemp("inputs")
    files: dict[str, Path] = {}
    for name in ("recording", "positives", "negatives", "test", "test_positives"):
        files[name] = d / f"{name}.npz"
        shutil.copy(here / "small.npz", files[name])
    files["recordings"] = files["recording"]
    files["test_negatives"] = d / "test_negatives.npz"
    shutil.copy(here / "small.npz", files["test_negatives"])
    files["model"] = d / "model.json"
    default_model().save(files["model"])
    files["config"] = d / "config.toml"
    files["config"].write_text("", encoding="utf-8")
    files["mounts"] = d / "mounts.toml"
    files["mounts"].write_text(
        '[mounts]\nlaser = { parent = "base", x = 0.1, y = 0.0, theta = 0.0 }\n', encoding="utf-8"
    )
    files["sweep"] = d / "sweep.toml"
    files["sweep"].write_text("", encoding="utf-8")
    shutil.copytree(here / "map_resolution", d / "map")
    files["map_path"] = d / "map" / "map.yaml"
    files["neko"] = d / "neko"
    shutil.copytree(here / "neko_infinity", files["neko"])
    files["tracks"] = d / "tracks.csv"
    shutil.copy(here / "tracks_stamps_differ.csv", files["tracks"])
    files["tracks_args"] = files["tracks"]
    files["truth"] = d / "truth.csv"
    write_truth_csv(files["truth"], [])
    return files


@pytest.mark.parametrize(("command", "output", "target"), _cases())
def test_no_output_option_writes_over_an_input(
    command: str, output: str, target: str, inputs: dict[str, Path], tmp_path: Path
) -> None:
    opts = _opts()
    values = {name: str(path) for name, path in inputs.items()}
    values["output"] = str(tmp_path / "out.bin")
    values["per_frame"] = str(tmp_path / "frames.csv")
    argv = [command, *(a.format(**values) for a in BASE[command])]
    victim = Path(values[target])
    flag = opts[(command, output)]
    if flag in argv:
        argv[argv.index(flag) + 1] = str(victim)
    else:
        argv += [flag, str(victim)]
    before = victim.read_bytes() if victim.is_file() else None
    run = CliRunner().invoke(app, argv)
    assert run.exit_code != 0, run.output
    assert isinstance(run.exception, ConfigError), run.output
    message = str(run.exception)
    # refused as an input, or (for outputs with a fixed kind) for the input's extension
    assert "would write over the input" in message or " writes a ." in message, message
    if before is not None:
        assert victim.read_bytes() == before
