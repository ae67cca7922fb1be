from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

from laserpeople.config import check_sections, describe, load_config, param, to_toml
from laserpeople.errors import ConfigError


@dataclass(frozen=True)
class DemoParams:
    p_occ: float = param(0.79, "000 Table 10", "P(occluded | approved)")
    window: int = param(5, "000 Sec. 3.3", "sliding window L", "scans")
    adaptive: bool = param(True, "000 Sec. 3.3.1", "adapt occlusion probabilities")


def test_defaults_and_sources() -> None:
    rows = {r[0]: r for r in describe(DemoParams)}
    assert rows["p_occ"][1] == 0.79 and rows["p_occ"][3] == "000 Table 10"
    assert "[demo]" in to_toml(DemoParams())


def test_load_overrides_and_rejects_unknown(tmp_path: Path) -> None:
    f = tmp_path / "c.toml"
    f.write_text("[demo]\np_occ = 1\nwindow = 7\n")
    cfg = load_config(DemoParams, f)
    assert cfg.p_occ == 1.0 and isinstance(cfg.p_occ, float) and cfg.window == 7
    f.write_text("[demo]\nbogus = 1\n")
    with pytest.raises(ConfigError, match="bogus"):
        load_config(DemoParams, f)
    f.write_text("[demo]\nwindow = 'x'\n")
    with pytest.raises(ConfigError, match="wrong type"):
        load_config(DemoParams, f)


def test_round_trip_through_toml(tmp_path: Path) -> None:
    f = tmp_path / "c.toml"
    f.write_text(to_toml(DemoParams(window=9)))
    assert load_config(DemoParams, f) == DemoParams(window=9)


def test_unknown_sections_are_rejected(tmp_path: Path) -> None:
    f = tmp_path / "c.toml"
    f.write_text("[demo]\nwindow = 3\n[demoo]\nwindow = 4\n")
    with pytest.raises(ConfigError, match=r"unknown section\(s\) \[demoo\]"):
        check_sections(f, [DemoParams])
    f.write_text("[demo]\nwindow = 3\n")
    check_sections(f, [DemoParams])
    check_sections(None, [DemoParams])

    @dataclass(frozen=True)
    class OtherParams:
        config_section = "other"
        gain: float = param(1.0, "test", "another command's parameter")

    # a section another command reads may share the file; a misspelt one still may not
    f.write_text("[demo]\nwindow = 3\n[other]\ngain = 2.0\n")
    check_sections(f, [DemoParams], [OtherParams])
    with pytest.raises(ConfigError, match=r"\[other\]"):
        check_sections(f, [DemoParams])
    with pytest.raises(ConfigError, match="is a directory"):
        load_config(DemoParams, tmp_path)


def test_print_config_says_which_values_a_file_or_the_preset_set(tmp_path: Path) -> None:
    """A value read from the file names the file and the default; one the preset set names
    the preset; one the file sets back to its default is plain; the rest are plain."""
    from types import MappingProxyType

    from laserpeople.config import origins

    @dataclass(frozen=True)
    class PresetParams:
        paper_preset = MappingProxyType({"window": 8, "adaptive": False})
        p_occ: float = param(0.79, "000 Table 10", "P(occluded | approved)")
        window: int = param(5, "000 Sec. 3.3", "sliding window L", "scans")
        adaptive: bool = param(True, "000 Sec. 3.3.1", "adapt occlusion probabilities")

    f = tmp_path / "mine.toml"
    f.write_text("[preset]\np_occ = 0.5\nadaptive = true\n")
    obj = load_config(PresetParams, f, "paper")
    where = origins(obj, f, "paper")
    assert where == {
        "p_occ": "from mine.toml (default 0.79)",
        "window": "from --preset paper (default 5)",
    }
    text = to_toml(obj, where)
    assert "p_occ = 0.5  # from mine.toml (default 0.79); P(occluded | approved)" in text
    assert "window = 8  # from --preset paper (default 5); sliding window L" in text
    assert "adaptive = true  # adapt occlusion probabilities" in text
    assert origins(load_config(PresetParams, None), None) == {}
