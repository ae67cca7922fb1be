"""The generator of docs/parameters.md finds parameter classes by itself and lists them."""

from __future__ import annotations

import importlib.util
import sys
import types
from dataclasses import dataclass
from pathlib import Path

from laserpeople.config import param

SCRIPT = Path(__file__).resolve().parents[1] / "docs" / "gen_params.py"


def load_generator() -> types.ModuleType:
    spec = importlib.util.spec_from_file_location("gen_params", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@dataclass(frozen=True)
class InnerParams:
    """Nested part."""

    radius: float = param(0.2, "000 Table 9", "a radius | with a bar", "m")


@dataclass(frozen=True)
class WidgetParams:
    """A made-up parameter class.

    More text that is not part of the summary.
    """

    config_section = "widget"

    speed: float = param(1.5, "004 Sec. 2", "walking speed", "m/s")
    names: tuple[str, ...] = param(("a", "b"), "our choice", "some names")
    enabled: bool = param(True, "our choice", "switch")
    inner: InnerParams = param(InnerParams(), "see inner", "nested")  # noqa: RUF009


@dataclass(frozen=True)
class NotParams:
    x: int = 1


def test_discovers_param_classes_where_they_are_defined() -> None:
    gen = load_generator()
    fake = types.ModuleType("laserpeople_fake_params")
    fake.WidgetParams = WidgetParams  # type: ignore[attr-defined]
    fake.NotParams = NotParams  # type: ignore[attr-defined]
    WidgetParams.__module__ = fake.__name__
    InnerParams.__module__ = "elsewhere"
    sys.modules[fake.__name__] = fake
    try:
        assert gen.param_classes([fake.__name__]) == [WidgetParams]
    finally:
        del sys.modules[fake.__name__]


def test_section_lists_every_parameter_with_default_unit_and_source() -> None:
    gen = load_generator()
    text = gen.class_section(WidgetParams)
    assert text.startswith("## `[widget]` — WidgetParams")
    assert "A made-up parameter class." in text and "More text" not in text
    assert "| `speed` | `1.5` | m/s | 004 Sec. 2 | walking speed |" in text
    assert '| `names` | `["a", "b"]` |' in text
    assert "| `enabled` | `true` |" in text
    assert "| `inner.radius` | `0.2` | m | 000 Table 9 | a radius \\| with a bar |" in text


def test_whole_package_scan_finds_the_metrics_parameters() -> None:
    gen = load_generator()
    modules, failed = gen.iter_modules()
    assert "laserpeople.config" in modules
    names = {f"{c.__module__}.{c.__qualname__}" for c in gen.param_classes(modules)}
    if "laserpeople.evaluation.params" in modules:
        assert "laserpeople.evaluation.params.EvaluationParams" in names
    text = gen.render_markdown(gen.param_classes(modules))
    assert text.startswith("# Parameter reference")
    assert all(isinstance(e, str) for _, e in failed)
