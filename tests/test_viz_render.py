"""Every output kind, rendered from a small synthetic recording and read back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from laserpeople.errors import LaserPeopleError
from laserpeople.viz import Scene, export_mcap, plot_scan, render, track_color
from test_viz_support import (
    SENSOR,
    make_scans,
    make_tracks,
    make_truth,
    near_colour,
    people_at,
    pixel_of,
    write_scene,
)

pytest.importorskip("matplotlib")
from PIL import Image


def test_png_of_one_scan_has_its_size_and_tracks_where_they_are(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path)
    out = tmp_path / "one.png"
    result = plot_scan(Scene(rec, csv, "recording"), out, scan=6, size=(800, 600))
    img = np.asarray(Image.open(out).convert("RGB"))
    assert img.shape == (600, 800, 3)
    assert result.frames == 1
    for tid, xy in zip((3, 8), people_at(6), strict=True):
        col, row = pixel_of(xy, result.extent, (800, 600))
        assert near_colour(img, col, row, track_color(tid, "person")), (tid, col, row)
    # a track colour never appears far from its track
    far = pixel_of(np.array([5.5, 4.5]), result.extent, (800, 600))
    assert not near_colour(img, *far, track_color(3, "person"), r=4)
    # not a blank picture: the background is white, scan points are grey
    assert (img.reshape(-1, 3) != 255).any(axis=1).mean() > 0.01


def test_png_in_the_sensor_frame_moves_tracks_with_the_sensor(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path)
    out = tmp_path / "sensor.png"
    result = plot_scan(Scene(rec, csv, frame="sensor"), out, scan=4, size=(640, 480))
    img = np.asarray(Image.open(out).convert("RGB"))
    local = SENSOR.inverse_transform_points(people_at(4))
    for tid, xy in zip((3, 8), local, strict=True):
        col, row = pixel_of(xy, result.extent, (640, 480))
        assert near_colour(img, col, row, track_color(tid, "person"))


def test_png_from_tracker_output_draws_group_contours(tmp_path: Path) -> None:
    scans, tracks = make_scans(5), make_tracks(5)
    out = tmp_path / "group.png"
    result = plot_scan(Scene(scans, tracks), out, scan=4, size=(640, 480))
    img = np.asarray(Image.open(out).convert("RGB"))
    contour = tracks[4].of_kind("group")[0].contour
    mid = 0.5 * (contour[0] + contour[1])  # on the contour's first edge
    col, row = pixel_of(mid, result.extent, (640, 480))
    assert near_colour(img, col, row, track_color(1, "group"))


def test_overview_png_shows_every_trajectory(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=15)
    out = tmp_path / "overview.png"
    result = render(Scene(rec, csv, "recording"), out, size=(700, 500))
    img = np.asarray(Image.open(out).convert("RGB"))
    assert img.shape == (500, 700, 3)
    for tid, xy in zip((3, 8), people_at(7), strict=True):
        col, row = pixel_of(xy, result.extent, (700, 500))
        assert near_colour(img, col, row, track_color(tid, "person"), r=3)


def test_gif_has_one_frame_per_scan_and_per_subsampled_scan(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=10)
    out = tmp_path / "all.gif"
    result = render(Scene(rec, csv, "recording"), out, size=(320, 240))
    with Image.open(out) as gif:
        assert gif.n_frames == 10 == result.frames
        assert gif.size == (320, 240)
        assert gif.info["duration"] == 100  # real time: scans are 0.1 s apart
    sub = tmp_path / "sub.gif"
    render(Scene(rec, csv, start=1, stop=9, every=3), sub, size=(320, 240), fps=5)
    with Image.open(sub) as gif:
        assert gif.n_frames == 3  # scans 1, 4, 7
        assert gif.info["duration"] == 200


def test_gif_frames_show_the_track_where_it_is_at_that_scan(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=6)
    out = tmp_path / "a.gif"
    scene = Scene(rec, csv)
    extent = scene.extent()
    render(scene, out, size=(480, 360), extent=extent)
    with Image.open(out) as gif:
        gif.seek(5)
        img = np.asarray(gif.convert("RGB"))
    col, row = pixel_of(people_at(5)[0], extent, (480, 360))
    rgb = track_color(3, "person")
    assert (
        near_colour(img, col, row, rgb)
        or np.abs(img[row - 2 : row + 3, col - 2 : col + 3].astype(int) - rgb).sum(axis=-1).min()
        < 40
    )  # GIF palette rounding


def test_mcap_reads_back_with_channels_counts_and_markers(tmp_path: Path) -> None:
    from rosbags.rosbag2 import Reader
    from rosbags.typesys import Stores, get_typestore

    n = 8
    rec, csv = write_scene(tmp_path, n=n)
    out = tmp_path / "scene.mcap"
    assert export_mcap(Scene(rec, csv, "recording"), out) == n
    store = get_typestore(Stores.ROS2_HUMBLE)
    with Reader(out) as reader:
        counts = {c.topic: (c.msgtype, c.msgcount) for c in reader.connections}
        assert counts == {
            "/front": ("sensor_msgs/msg/LaserScan", n),
            "/tf": ("tf2_msgs/msg/TFMessage", n),
            "/laserpeople/legs": ("visualization_msgs/msg/MarkerArray", n),
            "/laserpeople/people": ("visualization_msgs/msg/MarkerArray", n),
            "/laserpeople/groups": ("visualization_msgs/msg/MarkerArray", n),
            "/laserpeople/truth": ("visualization_msgs/msg/MarkerArray", n),
        }
        first: dict[str, object] = {}
        for conn, _, raw in reader.messages():
            first.setdefault(conn.topic, store.deserialize_cdr(raw, conn.msgtype))
    scan = first["/front"]
    assert np.allclose(scan.ranges, make_scans(1)[0].ranges.astype(np.float32))  # type: ignore[attr-defined]
    tf = first["/tf"].transforms[0]  # type: ignore[attr-defined]
    assert (tf.header.frame_id, tf.child_frame_id) == ("world", "front")
    assert np.isclose(tf.transform.translation.x, SENSOR.x)
    assert np.isclose(
        2 * np.arctan2(tf.transform.rotation.z, tf.transform.rotation.w), SENSOR.theta
    )
    people = first["/laserpeople/people"].markers  # type: ignore[attr-defined]
    assert people[0].action == 3  # DELETEALL first
    cylinders = {m.id: m for m in people if m.ns == "people"}
    assert set(cylinders) == {3, 8}
    assert np.isclose(cylinders[3].pose.position.x, people_at(0)[0, 0])
    assert {m.text for m in people if m.type == 9} == {"P3", "P8"}
    ellipses = [m for m in people if m.ns == "person_covariance"]
    assert len(ellipses) == 2 and all(len(m.points) == 33 for m in ellipses)
    truth = first["/laserpeople/truth"].markers  # type: ignore[attr-defined]
    assert {m.id for m in truth if m.ns == "truth"} == {0, 1}


def test_truth_csv_is_drawn(tmp_path: Path) -> None:
    scans = make_scans(3)
    p = tmp_path / "truth.csv"
    rows = ["scan,stamp,person_id,x,y"]
    for f in make_truth(3):
        rows += [
            f"{f.scan_index},{f.stamp},{i},{x},{y}"
            for i, (x, y) in zip(f.person_ids, f.positions, strict=True)
        ]
    p.write_text("\n".join(rows) + "\n")
    frames = list(Scene(scans, None, p).frames())
    assert all(f.truth is not None and len(f.truth) == 2 for f in frames)


def test_user_errors_are_clear(tmp_path: Path) -> None:
    rec, csv = write_scene(tmp_path, n=3)
    with pytest.raises(LaserPeopleError, match="unknown output kind"):
        render(Scene(rec, csv), tmp_path / "x.jpg")
    with pytest.raises(LaserPeopleError, match="scan 50 is not in"):
        render(Scene(rec, csv), tmp_path / "x.png", scan=50)
    with pytest.raises(LaserPeopleError, match="--scan picks one scan"):
        render(Scene(rec, csv), tmp_path / "x.gif", scan=1)
    with pytest.raises(LaserPeopleError, match="no ground truth"):
        list(Scene(make_scans(2), None, "recording").frames())
    with pytest.raises(LaserPeopleError, match="empty scan window"):
        Scene(rec, start=3, stop=2)


def test_mcap_export_reads_back_through_the_project_reader(tmp_path: Path) -> None:
    pytest.importorskip("laserpeople.io.rosbag")
    from laserpeople.io import open_recording

    rec, csv = write_scene(tmp_path, n=5)
    out = tmp_path / "scene.mcap"
    export_mcap(Scene(rec, csv), out)
    source = open_recording(out)
    try:
        scans = list(source.scans())
    finally:
        source.close()
    assert [s.index for s in scans] == list(range(5))
    assert np.allclose(scans[3].ranges, make_scans(4)[3].ranges.astype(np.float32))
    pose = scans[3].pose
    if pose is not None:  # the reader places the scan with /tf when it reads poses
        assert np.allclose(pose.as_array(), SENSOR.as_array(), atol=1e-6)


def test_one_shot_iterators_survive_the_sizing_pass(tmp_path: Path) -> None:
    scene = Scene(iter(make_scans(4)), iter(make_tracks(4)), iter(make_truth(4)))
    scene.extent()
    frames = list(scene.frames())
    assert len(frames) == 4
    assert all(len(f.tracks) >= 2 and f.truth is not None for f in frames)
