from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import RecordingError, TopicNotFoundError
from laserpeople.io import open_recording, write_recording
from laserpeople.scan import Pose2D, Scan
from laserpeople.truth import BeamLabels, TruthFrame


def _scans() -> list[Scan]:
    out = []
    for k in range(4):
        n = 5 + k
        labels = BeamLabels(np.arange(n), np.zeros(n), np.full(n, -1), np.full(n, -1))
        out.append(
            Scan(
                0.1 * k,
                -0.5,
                0.1,
                np.linspace(1, 2, n),
                0.05,
                8.0,
                intensities=np.ones(n),
                sensor="front" if k % 2 else "rear",
                pose=Pose2D(k, 0, 0.1) if k else None,
                index=k // 2,
                labels=labels,
            )
        )
    return out


def _truth() -> list[TruthFrame]:
    return [
        TruthFrame(
            0.1 * f,
            f,
            np.arange(f + 1),
            np.ones((f + 1, 2)) * f,
            np.zeros((f + 1, 2)),
            np.full(f + 1, -1),
            np.zeros((f + 1, 2, 2)),
            np.full(f + 1, 120.0),
        )
        for f in range(3)
    ]


def test_round_trip(tmp_path: Path) -> None:
    path = write_recording(tmp_path / "r.npz", _scans(), _truth(), meta={"scenario": "x"})
    rec = open_recording(path)
    assert [t.name for t in rec.topics()] == ["rear", "front"]
    assert [t.count for t in rec.topics()] == [2, 2]
    back = list(rec.scans())
    for a, b in zip(_scans(), back, strict=True):
        assert (a.stamp, a.sensor, a.index, a.pose) == (b.stamp, b.sensor, b.index, b.pose)
        np.testing.assert_allclose(a.ranges, b.ranges, rtol=1e-6)
        assert b.labels is not None and a.labels is not None
        np.testing.assert_array_equal(a.labels.person, b.labels.person)
    assert [s.index for s in rec.scans(["front"])] == [0, 1]
    frames = list(rec.truth())
    assert len(frames) == 3 and len(frames[2]) == 3
    np.testing.assert_allclose(frames[2].positions, 2.0)
    assert rec.meta == {"scenario": "x"}  # type: ignore[attr-defined]


def test_arrays_are_memory_mapped(tmp_path: Path) -> None:
    path = write_recording(tmp_path / "r.npz", _scans())
    rec = open_recording(path)
    assert isinstance(rec._a["ranges"], np.memmap)  # type: ignore[attr-defined]
    assert not rec.has_truth


def test_unknown_topic_lists_the_known_ones(tmp_path: Path) -> None:
    rec = open_recording(write_recording(tmp_path / "r.npz", _scans()))
    with pytest.raises(TopicNotFoundError, match="front"):
        list(rec.scans(["/nope"]))


def test_truncated_and_foreign_files_are_clear_errors(tmp_path: Path) -> None:
    path = write_recording(tmp_path / "r.npz", _scans())
    data = path.read_bytes()
    cut = tmp_path / "cut.npz"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(RecordingError, match=r"cut\.npz"):
        open_recording(cut)
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, a=np.ones(3))
    with pytest.raises(RecordingError, match="not a laserpeople recording"):
        open_recording(foreign)


def test_object_arrays_are_refused(tmp_path: Path) -> None:
    path = tmp_path / "evil.npz"
    with zipfile.ZipFile(path, "w") as zf, zf.open("format.npy", "w") as fh:
        np.lib.format.write_array(fh, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with pytest.raises(RecordingError, match="objects"):
        open_recording(path)


def test_directories_and_unwritable_paths_are_clear_errors(tmp_path: Path) -> None:
    with pytest.raises(RecordingError, match="is a directory"):
        open_recording(tmp_path)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(RecordingError, match="cannot write"):
        write_recording(blocker / "r.npz", _scans())
    assert not list(tmp_path.glob("**/*.partial*"))


def test_the_truth_frame_is_kept_when_stated(tmp_path: Path) -> None:
    """Truth frames that state their frame keep it through a file; frames that do not
    (or disagree) write none, and a file that states something else is refused."""
    from dataclasses import replace

    for stated, back in (("sensor", "sensor"), ("world", "world"), (None, None)):
        frames = [replace(f, frame=stated) for f in _truth()]
        path = write_recording(tmp_path / f"{stated}.npz", _scans(), frames)
        rec = open_recording(path)
        assert {f.frame for f in rec.truth()} == {back}
        rec.close()
    mixed = [replace(f, frame="sensor" if k else "world") for k, f in enumerate(_truth())]
    rec = open_recording(write_recording(tmp_path / "mixed.npz", _scans(), mixed))
    assert {f.frame for f in rec.truth()} == {None}
    rec.close()
    with np.load(tmp_path / "world.npz") as data:
        arrays = {k: data[k] for k in data.files}
    arrays["truth_frame"] = np.array("odom")
    np.savez(tmp_path / "odom.npz", **arrays)  # type: ignore[arg-type]
    rec = open_recording(tmp_path / "odom.npz")
    with pytest.raises(RecordingError, match="truth_frame is 'odom'"):
        list(rec.truth())
    rec.close()
