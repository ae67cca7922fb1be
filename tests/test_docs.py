"""The committed documentation matches the code."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path
from typing import Any

import pytest

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


def load_script(name: str) -> Any:
    spec = importlib.util.spec_from_file_location(name, REPO / "docs" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod  # dataclasses look their module up while the script runs
    try:
        spec.loader.exec_module(mod)
    finally:
        del sys.modules[name]
    return mod


def test_benchmarks_page_is_up_to_date() -> None:
    gen = load_script("gen_benchmarks")
    assert gen.main(["--check"]) == 0, "docs/benchmarks.md is stale: run docs/gen_benchmarks.py"


def test_benchmark_list_names_existing_scripts_and_pages() -> None:
    gen = load_script("gen_benchmarks")
    for bench in gen.BENCHMARKS:
        assert (REPO / bench.command[0]).is_file(), bench.command[0]
        if bench.page:
            assert (REPO / "docs" / bench.page.split("#")[0]).is_file(), bench.page
    for path, _, key in gen.PLOTS:
        assert (REPO / "docs" / path).is_file(), path
        assert key in {b.key for b in gen.BENCHMARKS} | {"csa"}, key


def test_readme_is_short_and_installs_from_the_clone() -> None:
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    assert len(readme.splitlines()) <= 120
    assert "python3 -m venv .venv && .venv/bin/pip install -e '.[all]'" in readme
    # the package is not on an index: every install line installs the clone (-e .)
    for line in readme.splitlines():
        if "pip install" in line:
            assert "pip install -e '." in line, line


def test_readme_and_outputs_page_list_the_real_csv_columns() -> None:
    from laserpeople.io import detections_csv, tracks_csv

    tracks = ",".join(
        (
            *tracks_csv.HEADER,
            tracks_csv.TOPIC_COLUMN,
            tracks_csv.FRAME_COLUMN,
            *tracks_csv.SENSOR_POSE_COLUMNS,
        )
    )
    detections = ",".join((*detections_csv.HEADER, detections_csv.TOPIC_COLUMN))
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    outputs = (REPO / "docs" / "outputs.md").read_text(encoding="utf-8")
    assert f"`{tracks}`" in readme
    assert tracks in outputs and detections in outputs
    columns = (
        tracks_csv.TOPIC_COLUMN,
        tracks_csv.FRAME_COLUMN,
        tracks_csv.CONTOUR_COLUMN,
        *tracks_csv.SENSOR_POSE_COLUMNS,
    )
    for column in (*tracks_csv.HEADER, *columns):
        assert re.search(rf"^\| [^|]*`{column}`", outputs, flags=re.MULTILINE), column


# Pages a user reads hold results, not history: no lab-notebook references. The parameter
# reference is generated from the parameters' sources and is checked by its own test.
HISTORY = re.compile(r"\b(session \d+|sessions \d|issue \d+|helper `)", re.IGNORECASE)


def test_user_pages_read_as_documentation_not_a_lab_notebook() -> None:
    pages = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
    pages += sorted((REPO / "docs" / "api").glob("*.md"))
    found = []
    for page in pages:
        if page.name == "parameters.md":
            continue
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            if HISTORY.search(line):
                found.append(f"{page.relative_to(REPO)}:{number}: {line.strip()}")
    assert not found, "\n".join(found)


def test_every_page_is_in_the_site_nav() -> None:
    lines = (REPO / "mkdocs.yml").read_text(encoding="utf-8").splitlines()
    nav = "\n".join(line for line in lines if not line.lstrip().startswith("#"))
    listed = set(re.findall(r":\s*([\w/.-]+\.md)\s*$", nav, flags=re.MULTILINE))
    pages = {p.relative_to(REPO / "docs").as_posix() for p in (REPO / "docs").rglob("*.md")}
    assert pages <= listed, f"pages missing from mkdocs.yml's nav: {sorted(pages - listed)}"
    assert listed <= pages, f"nav entries without a page: {sorted(listed - pages)}"


def test_api_pages_show_sphinx_roles_and_doctests_as_markdown() -> None:
    pytest.importorskip("griffe")  # the docs extra (part of dev)
    roles = load_script("griffe_roles")
    text = (
        "A :class:`~laserpeople.frame.Frame` and :func:`laserpeople.io.open_recording`\n"
        "in three lines::\n\n    x = 1\n\nExample:\n"
        "    >>> from laserpeople.pipeline import build  # doctest: +SKIP\n"
        "    >>> build('run.bag')\nEnd."
    )
    assert roles.markdown(text) == (
        "A `Frame` and `laserpeople.io.open_recording`\n"
        "in three lines:\n\n    x = 1\n\nExample:\n"
        "    ```python\n    from laserpeople.pipeline import build\n    build('run.bag')\n"
        "    ```\nEnd."
    )
