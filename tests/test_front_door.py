"""What a new user meets first: output not folded in pipes, --version, --quiet after the
command, one style of usage line, papers named by their authors, a fast start, and the
README's demo in a fresh clone with a long path and nothing beside it."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from laserpeople.citations import cite
from laserpeople.cli import app, hoist_global_flags

REPO = Path(__file__).resolve().parents[1]
COMMANDS = (
    "info",
    "simulate",
    "scenarios",
    "detect",
    "train",
    "track",
    "evaluate",
    "bench",
    "view",
    "demo",
    "batch",
)


def _cli(args: list[str], cwd: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """The command line in a fresh interpreter, output piped (not a terminal)."""
    full_env = dict(os.environ, PYTHONPATH=str(REPO / "src"), **env)
    return subprocess.run(
        [sys.executable, "-m", "laserpeople.cli", *args],
        cwd=cwd,
        env=full_env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_status_lines_are_one_line_whatever_the_path_length_and_columns(tmp_path: Path) -> None:
    deep = tmp_path / ("x" * 120) / ("y" * 100)
    deep.mkdir(parents=True)
    out = deep / "a_recording_with_a_long_name.npz"
    done = _cli(["simulate", "speed-normal", "-o", str(out), "--seconds", "1"], deep, COLUMNS="40")
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if line.startswith("wrote ")]
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith(f"wrote {out}: ") and "seed 0" in lines[0]


def test_errors_are_one_line_whatever_the_columns(tmp_path: Path) -> None:
    missing = tmp_path / ("z" * 150) / "missing.bag"
    done = _cli(["info", str(missing)], tmp_path, COLUMNS="40")
    assert done.returncode == 1
    assert done.stderr.count("\n") == 1 and str(missing) in done.stderr, done.stderr


def test_tables_in_a_pipe_ignore_columns(tmp_path: Path) -> None:
    narrow = _cli(["scenarios"], tmp_path, COLUMNS="40")
    wide = _cli(["scenarios"], tmp_path, COLUMNS="300")
    assert narrow.returncode == 0 and narrow.stdout == wide.stdout


def test_version() -> None:
    from laserpeople import __version__

    result = CliRunner().invoke(app, ["--version"])
    assert result.exit_code == 0
    assert result.output.strip() == f"laserpeople {__version__}"


def test_global_flags_after_the_command_name() -> None:
    assert hoist_global_flags(["track", "a.bag", "--quiet", "-o", "t.csv"]) == [
        "--quiet",
        "track",
        "a.bag",
        "-o",
        "t.csv",
    ]
    assert hoist_global_flags(["view", "a", "--debug", "-q"]) == ["--debug", "-q", "view", "a"]
    # after "--" everything is an argument
    assert hoist_global_flags(["info", "--", "--quiet"]) == ["info", "--", "--quiet"]


def test_quiet_after_the_command_silences_status_lines(tmp_path: Path) -> None:
    out = tmp_path / "s.npz"
    loud = CliRunner().invoke(app, ["simulate", "speed-normal", "-o", str(out), "-s", "1"])
    quiet = CliRunner().invoke(
        app, ["simulate", "speed-normal", "-o", str(out), "-s", "1", "--quiet"]
    )
    assert loud.exit_code == 0 and "wrote" in loud.output
    assert quiet.exit_code == 0 and quiet.output == "", quiet.output


def test_usage_lines_have_one_style() -> None:
    for command in COMMANDS:
        result = CliRunner().invoke(app, [command, "--help"])
        assert result.exit_code == 0, result.output
        usage = next(line for line in result.output.splitlines() if line.startswith("Usage:"))
        assert re.fullmatch(
            rf"Usage: laserpeople {command} \[OPTIONS\]( \[?[A-Z_]+\]?(\.\.\.)?)*", usage
        ), usage


def test_help_names_papers_by_their_authors_and_the_group_tracker() -> None:
    top = " ".join(CliRunner().invoke(app, ["--help"]).output.split())
    assert "Arras et al. 2008" in top and "Schenk et al. 2011" in top
    assert "--tracker group-mht" in top
    for command in COMMANDS:
        text = CliRunner().invoke(app, [command, "--help"]).output
        assert not re.search(r"(?<![\w.,])00[024](?!\w)", text), (command, text)


def test_scenario_list_names_papers_by_their_authors(tmp_path: Path) -> None:
    done = _cli(["scenarios"], tmp_path)
    assert done.returncode == 0
    assert "Arras et al. 2008 Sec. 3.4.1" in done.stdout and "Kräußling et al." in done.stdout
    assert not re.search(r"(?<![\w.,])00[024](?!\w)", done.stdout)


def test_cite_names_the_papers_and_leaves_numbers_alone() -> None:
    assert cite("000 Table 10") == "Arras et al. 2008 Table 10"
    assert cite("(000 Sec. 3.3.1)") == "(Arras et al. 2008 Sec. 3.3.1)"
    assert cite("004's MOTP; 002") == "Schenk et al. 2011's MOTP; Kräußling et al."
    for number in ("1,000 scans", "0.004 m", "2000 Hz", "x000", "000.5"):
        assert cite(number) == number


def test_starting_the_program_imports_no_heavy_library() -> None:
    code = (
        "import sys; import laserpeople.cli; "
        "print(' '.join(m for m in ('numpy', 'scipy', 'matplotlib', 'rosbags', 'PIL', "
        "'rich.console', 'laserpeople.scan') if m in sys.modules))"
    )
    assert _python(code).strip() == ""


def _python(code: str) -> str:
    """The output of a fresh interpreter running ``code`` with this checkout's package."""
    done = subprocess.run(
        [sys.executable, "-c", code],
        env=dict(os.environ, PYTHONPATH=str(REPO / "src")),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_package_still_offers_its_data_model() -> None:
    import laserpeople

    assert laserpeople.Scan.__name__ == "Scan" and laserpeople.Tracks.__name__ == "Tracks"
    assert "TruthFrame" in dir(laserpeople)
    with pytest.raises(AttributeError):
        _ = laserpeople.NoSuchThing  # type: ignore[attr-defined]


@pytest.mark.slow
def test_fresh_clone_with_a_long_path_runs_the_demo(tmp_path: Path) -> None:
    """The README's demo in a clone with nothing beside it (no ../shared), a long path and
    narrow COLUMNS, run by this interpreter (which has the dependencies) on the clone's
    code. (.ci/run does the same with the full demo and the whole test suite.)"""
    git = shutil.which("git")
    if git is None or not (REPO / ".git").exists():
        pytest.skip("needs git and a git checkout")
    fresh = tmp_path / ("long-directory-name-" * 6) / "laserpeople"
    clone = subprocess.run(
        [git, "clone", "--quiet", str(REPO), str(fresh)], capture_output=True, text=True
    )
    assert clone.returncode == 0, clone.stderr
    env = {
        k: v for k, v in os.environ.items() if k not in ("LASERPEOPLE_SHARED_DATA", "PYTHONPATH")
    }
    done = subprocess.run(
        [sys.executable, "-m", "laserpeople.cli", "demo", "--seconds", "4"],
        cwd=fresh,
        env=dict(env, PYTHONPATH=str(fresh / "src"), COLUMNS="40"),
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert "leg-mht" in done.stdout and "MOTA" in done.stdout
    for name in ("demo.gif", "demo-tracks.csv", "demo.npz"):
        assert (fresh / name).stat().st_size > 0, name
    wrote = [line for line in done.stderr.splitlines() if line.startswith("wrote ")]
    assert any(line.endswith(" frames)") and "demo.gif" in line for line in wrote), done.stderr
    status = subprocess.run(
        [git, "status", "--porcelain"], cwd=fresh, capture_output=True, text=True
    )
    assert status.stdout == "", f"the demo left files git does not ignore: {status.stdout}"


def test_demo_without_plotting_libraries_prints_its_table_and_says_how_to_draw(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import laserpeople.cli.demo as demo_cli

    monkeypatch.setattr(demo_cli, "plotting_available", lambda: False)
    result = CliRunner().invoke(app, ["demo", "--seconds", "2", "--out-dir", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "leg-mht" in result.output and "MOTA" in result.output
    assert "pip install 'laserpeople[all]'" in result.output
    assert not (tmp_path / "demo.gif").exists()
    assert (tmp_path / "demo-tracks.csv").exists() and (tmp_path / "demo.npz").exists()


def test_a_command_is_built_alone_with_the_same_help() -> None:
    from laserpeople.cli import COMMANDS as ALL
    from laserpeople.cli import commands_needed, make_app

    assert commands_needed(["-q", "track", "x.bag", "--debug"]) == ("track",)
    assert commands_needed(["track", "--help"]) == ("track",)
    assert commands_needed(["-q", "--version"]) == ()
    for args in (["--help", "track"], ["trak"], [], ["--version", "-h"], ["--", "track"]):
        assert commands_needed(args) == ALL, args
    assert set(COMMANDS) <= set(ALL)
    for command in ALL:
        alone = CliRunner().invoke(make_app((command,)), [command, "--help"])
        full = CliRunner().invoke(app, [command, "--help"])
        assert alone.exit_code == full.exit_code == 0
        assert alone.output == full.output, command


def test_a_command_help_imports_neither_pydantic_nor_click() -> None:
    code = (
        "import sys; sys.argv = ['laserpeople', 'track', '--help']\n"
        "from laserpeople.cli import main\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\n"
        "print('LOADED', ' '.join(m for m in ('pydantic', 'click', 'laserpeople.cli.view') "
        "if m in sys.modules))"
    )
    out = _python(code)
    assert "Usage: laserpeople track" in out
    assert out.rstrip().endswith("LOADED"), out[-200:]


@pytest.mark.parametrize("args", [["--help"], ["live", "--help"], ["batch", "--help"]])
def test_help_imports_no_numpy(args: list[str]) -> None:
    """``--help`` of the program (which builds every command) and of the commands that
    warn about unused options after a run: neither numpy nor the pipeline package is
    imported (importing ``laserpeople.pipeline.unused_options`` at the top of a command
    module imported both: 0.25 s CPU, 21 times a bare Python start)."""
    code = (
        f"import sys; sys.argv = ['laserpeople', *{args!r}]\n"
        "from laserpeople.cli import main\n"
        "try:\n    main()\nexcept SystemExit:\n    pass\n"
        "print('LOADED', ' '.join(m for m in ('numpy', 'laserpeople.pipeline') "
        "if m in sys.modules))"
    )
    out = _python(code)
    assert "Usage: laserpeople" in out
    assert out.rstrip().endswith("LOADED"), out[-200:]


def test_a_run_imports_only_what_its_tracker_needs(tmp_path: Path) -> None:
    """``track`` with the default tracker, output piped: neither pydantic (typer's coercion
    of plain values), nor the other trackers (the registry names their parameter classes),
    nor rich's console (status lines off a terminal), nor scipy itself (the assignment
    solver's extension alone) is imported, and the run still writes its tracks."""
    from laserpeople.sim.scenarios import run_scenario

    rec = tmp_path / "r.npz"
    run_scenario("crossing-3", seconds=2.0, seed=0).write(rec)
    out = tmp_path / "t.csv"
    heavy = (
        "pydantic",
        "rich.console",
        "scipy",
        "laserpeople.tracking.groups",
        "laserpeople.tracking.csa",
        "laserpeople.tracking.particle",
    )
    code = (
        f"import sys; sys.argv = ['laserpeople', 'track', {str(rec)!r}, '-o', {str(out)!r}]\n"
        "from laserpeople.cli import main\n"
        "try:\n    main()\nexcept SystemExit as exc:\n    assert not exc.code, exc.code\n"
        f"print('LOADED', ' '.join(m for m in {heavy!r} if m in sys.modules))"
    )
    printed = _python(code)
    assert printed.rstrip().endswith("LOADED"), printed[-300:]
    assert len(out.read_text().splitlines()) > 10  # (the header and the tracks' rows)


def test_plain_values_are_coerced_as_typer_coerces_them(tmp_path: Path) -> None:
    """Every parameter of ``track`` gets the same value (or the same error) from the
    program's coercion of plain values as from typer's own (pydantic) coercion."""
    import typer.main

    coercion = pytest.importorskip("typer._coercion")
    from laserpeople.cli import PlainValues, make_app

    group = typer.main.get_command(make_app(("track",)))
    command = group.commands["track"]  # type: ignore[attr-defined]
    ctx = command.make_context("track", ["--help"], resilient_parsing=True)
    (tmp_path / "there.bag").write_bytes(b"")
    tried = 0
    for param in [*command.params, command.get_help_option(ctx)]:
        ours = param.get_runtime_param()
        assert isinstance(ours, PlainValues), param.name
        theirs = coercion.build_runtime_param(param.type_descriptor)
        for value in (
            None,
            param.default,
            "text",
            "2.5",
            "nan",
            str(tmp_path / "there.bag"),
            str(tmp_path / "missing.csv"),
            ("a", "b"),
            (),
            True,
            7,
            0.25,
        ):
            results = []
            for coerce in (ours.coerce, theirs.coerce):
                try:
                    results.append(("value", coerce(value, param=param, ctx=ctx)))
                except Exception as exc:  # (the same error, with the same message)
                    results.append(("error", f"{type(exc).__name__}: {exc}"))
            mine, typers = results
            assert repr(mine) == repr(typers), (param.name, value, mine, typers)  # (nan)
            assert type(mine[1]) is type(typers[1]), (param.name, value)
            tried += 1
    assert tried > 200
