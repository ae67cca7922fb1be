"""The committed documentation matches the code."""

from __future__ import annotations

import importlib.util
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_parameter_reference_is_up_to_date() -> None:
    spec = importlib.util.spec_from_file_location("gen_params", REPO / "docs" / "gen_params.py")
    assert spec is not None and spec.loader is not None
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    assert gen.main(["--check"]) == 0, "docs/parameters.md is stale: run python docs/gen_params.py"


def test_readme_commands_match_ci() -> None:
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    ci = (REPO / ".ci" / "run").read_text(encoding="utf-8")
    test_command = ".venv/bin/python -m pytest"
    assert test_command in readme
    assert any(line.strip() == test_command for line in ci.splitlines())
