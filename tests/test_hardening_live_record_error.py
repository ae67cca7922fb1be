"""`live --record` failing mid-run (a full disk): the summary of what ran is printed
before the error, as at a normal end."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner


@pytest.mark.slow
def test_a_recording_that_fails_mid_run_still_gets_its_summary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("zenoh")
    from laserpeople.cli import app
    from laserpeople.errors import RecordingError
    from laserpeople.io import open_recording
    from laserpeople.live import sinks
    from laserpeople.sim.scenarios import run_scenario
    from live_harness import free_port, play_when_subscribed

    bag = tmp_path / "walk.bag"
    run_scenario("figure-eight", seconds=2.0, seed=3).write(bag)
    with open_recording(bag) as rec:
        topic, n = rec.topics()[0].name, rec.topics()[0].count
    write = sinks.RecordSink.write

    def full_after_five(self: Any, frame: Any, tracks: Any) -> None:
        if self._writer.frames >= 5:
            raise RecordingError("cannot write the bag: No space left on device", path="x.mcap")
        write(self, frame, tracks)

    monkeypatch.setattr(sinks.RecordSink, "write", full_after_five)
    port = free_port()
    player = play_when_subscribed(bag, topic, port)
    args = ["live", "--topic", topic, "--listen", f"tcp/127.0.0.1:{port}", "--frame", "sensor"]
    args += ["--queue", "100000", "--max-scans", str(n), "--duration", "120"]
    args += ["--record", str(tmp_path / "live.mcap")]
    result = CliRunner().invoke(app, args)
    player.join(30)
    assert isinstance(result.exception, RecordingError), result.output
    assert "No space left on device" in str(result.exception)
    assert f"{topic}: " in result.output and " scans received, " in result.output
    # the sixth frame was published, then its recording failed
    assert "5 frames tracked, 6 published" in result.output
    assert "wrote " not in result.output
