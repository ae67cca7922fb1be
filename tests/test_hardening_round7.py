"""What a demanding user meets, seventh round: empty paths, the coasting's public view."""

from __future__ import annotations

import pytest
import typer
from typer.testing import CliRunner

from laserpeople.cli import TEXT_PATH_PARAMETERS, app, is_path_parameter


def _path_options() -> list[tuple[str, str, bool]]:
    """(command, what the command line calls the parameter, whether it is an argument) of
    every parameter that names files."""
    group = typer.main.get_command(app)
    found = []
    for name, command in group.commands.items():  # type: ignore[attr-defined]
        for param in command.params:
            if is_path_parameter(name, param):
                is_argument = param.param_type_name == "argument"
                shown = param.metavar if is_argument else param.opts[0]
                found.append((name, shown, is_argument))
    return sorted(found)


def test_every_text_path_parameter_exists_and_paths_are_found() -> None:
    group = typer.main.get_command(app)
    names = {
        (name, p.name)
        for name, command in group.commands.items()  # type: ignore[attr-defined]
        for p in command.params
    }
    assert names >= TEXT_PATH_PARAMETERS
    found = {(c, o) for c, o, _ in _path_options()}
    assert ("track", "--config") in found and ("evaluate", "--truth") in found
    assert ("batch", "RECORDINGS") in found and ("demo", "--out-dir") in found
    assert len(found) >= 40


@pytest.mark.parametrize(("command", "option", "is_argument"), _path_options())
def test_an_empty_path_is_refused_naming_the_option(
    command: str, option: str, is_argument: bool
) -> None:
    """``--config ""`` (an unset shell variable) is no ``.``: refused before any file is
    read or written, naming the option."""
    args = [command, ""] if is_argument else [command, option, ""]
    run = CliRunner().invoke(app, args)
    text = " ".join(run.output.split())
    assert run.exit_code == 2, run.output
    assert f"Invalid value for '{option}'" in text and "': is empty: give a file" in text, text


def test_groups_oracle_gap_reads_no_private_attribute_but_its_own() -> None:
    """The benchmark asks the tracker's coasting through its public ``in``, not ``_last``."""
    import ast
    from pathlib import Path

    bench = Path(__file__).resolve().parents[1] / "benchmarks" / "groups_oracle_gap.py"
    tree = ast.parse(bench.read_text(encoding="utf-8"))
    private = {
        ast.unparse(node)
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and node.attr.startswith("_")
        and not node.attr.startswith("__")
        and not (isinstance(node.value, ast.Name) and node.value.id == "self")
    }
    assert private == set()
    assert "self.tracker.coasting" in bench.read_text(encoding="utf-8")
