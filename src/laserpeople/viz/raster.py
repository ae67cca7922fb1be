"""Pictures and animations: one scan or a trajectory overview as PNG, every scan as GIF/MP4."""

from __future__ import annotations

import contextlib
import math
import shutil
import subprocess
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import LaserPeopleError
from laserpeople.viz.colors import (
    BACKGROUND,
    PALETTE,
    SCAN_POINTS,
    TRUTH,
    label_color,
    to_unit,
    track_color,
)
from laserpeople.viz.figure import (
    AXES_BOX,
    Extent,
    FrameRenderer,
    PlotsExtraMissingError,
    drawable,
    import_matplotlib,
)
from laserpeople.viz.geometry import square_extent
from laserpeople.viz.scene import ProgressFn, Scene, SceneFrame, TracksOutside

RGBImage = NDArray[np.uint8]


class VideoEncoderMissingError(LaserPeopleError):
    """An output format needs a program (ffmpeg) that is not on this machine."""


@dataclass(frozen=True)
class RenderResult:
    """What a drawing call wrote.

    Attributes:
        path: The output file.
        frames: Number of images written (1 for a PNG).
        size: Image ``(width, height)`` [px].
        extent: The shown area ``(xmin, xmax, ymin, ymax)`` [m] before squaring the metres.
        overview_scans: Scans drawn into a trajectory overview (0: not an overview).
        tracks_outside: Track positions outside the area the picture is fitted to (none
            when the output has no fitted area, e.g. ``.mcap``).
    """

    path: Path
    frames: int
    size: tuple[int, int]
    extent: Extent
    overview_scans: int = 0
    tracks_outside: TracksOutside = field(default_factory=TracksOutside)


def _pil() -> object:
    try:
        from PIL import Image
    except ImportError as exc:
        raise PlotsExtraMissingError(
            "writing images needs pillow, which is not installed",
            hint="pip install 'laserpeople[all]'",
        ) from exc
    return Image


def _no_progress(frames: Iterable[SceneFrame], total: int | None) -> Iterable[SceneFrame]:
    return frames


def save_png(image: RGBImage, path: str | Path) -> Path:
    """Write an RGB image (H, W, 3) as PNG."""
    from PIL import Image

    _pil()
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(p)
    return p


def plot_scan(
    scene: Scene,
    out: str | Path,
    *,
    scan: int | None = None,
    size: tuple[int, int] = (800, 600),
    extent: Extent | None = None,
    trail: int = 20,
) -> RenderResult:
    """Draw one scan (index ``scan`` on the topic; the first of the window when None) with
    its tracks and truth as PNG; trails show the ``trail`` scans before it."""
    frames: list[SceneFrame] = []
    target: SceneFrame | None = None
    first = last = None  # the scan indices the window holds
    for f in scene.frames():
        if scan is None or f.scan.index == scan:
            target = f
            break
        first = f.scan.index if first is None else first
        last = f.scan.index
        frames.append(f)
        if len(frames) > trail:
            frames.pop(0)
    if target is None:
        held = f"it holds scans {first}-{last}" if first is not None else "it holds no scan"
        raise LaserPeopleError(
            f"scan {scan} is not in the recording window ({held})",
            path=scene.source_name or None,
            hint="check --scan against the topic's scan count, --start and --stop",
        )
    if extent is None:
        extent = _frames_extent([*frames, target])
    renderer = FrameRenderer(
        extent,
        size=size,
        frame=scene.frame,
        trail=trail,
        title=_title(scene),
        t0=scene.first_stamp(),
        truth=scene.draws_truth(),
        kinds=scene.track_kinds(),
    )
    for f in frames:
        renderer.draw(f)
    image = renderer.draw(target)
    renderer.close()
    return RenderResult(save_png(image, out), 1, size, extent)


def _frames_extent(frames: list[SceneFrame], margin: float = 0.5) -> Extent:
    parts = []
    for f in frames:
        parts.append(f.points)
        parts.append(np.array([[f.sensor_pose.x, f.sensor_pose.y]]))
        parts.extend(np.array([t.position]) for t in f.tracks.tracks)
        if f.truth is not None:
            parts.append(f.truth.positions)
    pts = np.concatenate(parts)
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    lo, hi = pts.min(axis=0) - margin, pts.max(axis=0) + margin
    return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


def _title(scene: Scene) -> str:
    """The drawings' title: the scene's, else the recording's name and the topic (each
    character the font lacks as ``?``, :func:`~laserpeople.viz.figure.drawable`)."""
    if scene.title is not None:
        return drawable(scene.title)
    name = Path(scene.source_name).name if scene.source_name else ""
    return drawable(f"{name} {scene.topic or ''}".strip())


def iter_images(
    scene: Scene,
    *,
    size: tuple[int, int] = (640, 480),
    extent: Extent | None = None,
    trail: int = 20,
    progress: ProgressFn | None = None,
    total: int | None = None,
) -> Iterator[RGBImage]:
    """One RGB image per frame of ``scene`` (streaming; the extent takes one extra pass)."""
    if extent is None:
        extent = scene.extent()
    renderer = FrameRenderer(
        extent,
        size=size,
        frame=scene.frame,
        trail=trail,
        title=_title(scene),
        t0=scene.first_stamp(),
        truth=scene.draws_truth(),
        kinds=scene.track_kinds(),
    )
    try:
        for f in (progress or _no_progress)(scene.frames(), total):
            yield renderer.draw(f)
    finally:
        renderer.close()


MAX_FRAME_SECONDS = 600.0
"""Longest time [s] an animation frame is shown (a GIF frame delay is a 16-bit count of
centiseconds: at most 655.35 s)."""


def _frame_duration(scene: Scene, fps: float | None) -> float:
    """Seconds each frame is shown: 1/fps, or the scans' median spacing (real time); at
    most :data:`MAX_FRAME_SECONDS`."""
    if fps is not None:
        if not (math.isfinite(fps) and fps >= 1.0 / MAX_FRAME_SECONDS):
            raise LaserPeopleError(
                f"fps {fps!r} is too low: a frame is shown at most {MAX_FRAME_SECONDS:g} s "
                f"(fps at least {1.0 / MAX_FRAME_SECONDS:.4g})"
            )
        return 1.0 / fps
    stamps = []
    for f in scene.frames():
        stamps.append(f.scan.stamp)
        if len(stamps) >= 50:
            break
    if len(stamps) < 2:
        return 0.1
    dt = float(np.median(np.diff(stamps)))
    if dt > MAX_FRAME_SECONDS:
        raise LaserPeopleError(
            f"the scans are {dt:.6g} s apart: real time would show each frame longer than "
            f"{MAX_FRAME_SECONDS:g} s",
            hint="give --fps",
        )
    return dt if dt > 0 else 0.1


def gif_palette() -> list[int]:
    """The fixed 256-colour GIF palette: background, greys, each track colour blended with
    white at several strengths (antialiased edges and translucent fills land near one of
    them), and the darker label shades."""
    colours: list[tuple[int, int, int]] = [BACKGROUND, TRUTH, SCAN_POINTS]
    colours += [(v, v, v) for v in np.linspace(0, 255, 40).astype(int).tolist()]
    white = np.array(BACKGROUND, dtype=np.float64)
    for c in PALETTE:
        rgb = np.array(c, dtype=np.float64)
        for a in (1.0, 0.75, 0.5, 0.3, 0.18, 0.1):
            mix = np.rint(a * rgb + (1.0 - a) * white).astype(int)
            colours.append((int(mix[0]), int(mix[1]), int(mix[2])))
    colours += [(int(r * 0.6), int(g * 0.6), int(b * 0.6)) for r, g, b in PALETTE]  # labels
    colours = colours[:256]
    colours += [(0, 0, 0)] * (256 - len(colours))
    return [v for c in colours for v in c]


def _quantize(img: RGBImage, palette: Any) -> NDArray[np.uint8]:
    """Map an RGB image onto the fixed GIF palette; returns palette indices (H, W). Pillow's
    mapping is approximate (it caches on reduced colour bits) and would tint the white
    background; background pixels are therefore set to palette entry 0 (the background
    colour) exactly."""
    from PIL import Image

    q = Image.fromarray(img).quantize(palette=palette, dither=Image.Dither.NONE)
    idx = np.asarray(q).copy()
    if BACKGROUND == (255, 255, 255):  # fast path: all three channels at 255
        white = (img[:, :, 0] & img[:, :, 1] & img[:, :, 2]) == 255
    else:
        white = np.all(img == np.array(BACKGROUND, dtype=np.uint8), axis=-1)
    idx[white] = 0
    return idx


def write_gif(
    images: Iterable[RGBImage], out: str | Path, frame_seconds: float, *, loop: bool = True
) -> int:
    """Write RGB images as an animated GIF with a fixed palette; returns the frame count.

    Frames are written as they come (:class:`~laserpeople.viz.gif.GifWriter`): memory
    stays at about one frame however many there are. A failed or empty animation leaves
    no file behind.
    """
    from PIL import Image

    from laserpeople.viz.gif import GifWriter

    _pil()
    pal = Image.new("P", (1, 1))
    palette = gif_palette()
    pal.putpalette(palette)
    p = Path(out)
    writer: GifWriter | None = None
    try:
        for img in images:
            if writer is None:
                writer = GifWriter(p, (img.shape[1], img.shape[0]), palette, loop=loop)
            writer.add(_quantize(img, pal), frame_seconds)
    except BaseException:
        if writer is not None:
            writer.close()
            p.unlink(missing_ok=True)
        raise
    if writer is None:
        raise LaserPeopleError("no frames to animate", hint="check --start/--stop/--every")
    writer.close()
    return writer.frames


def find_ffmpeg() -> str | None:
    """The ``ffmpeg`` program: the one on the PATH, else the static binary bundled with the
    optional ``imageio-ffmpeg`` package (extra ``plots``), else None."""
    on_path = shutil.which("ffmpeg")
    if on_path is not None:
        return on_path
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    try:
        return str(imageio_ffmpeg.get_ffmpeg_exe())
    except RuntimeError:  # the package is there but has no binary for this platform
        return None


def require_ffmpeg(out: str | Path) -> str:
    """The path of the ``ffmpeg`` program (see :func:`find_ffmpeg`), or a clear error naming
    what to install."""
    ffmpeg = find_ffmpeg()
    if ffmpeg is None:
        raise VideoEncoderMissingError(
            "writing .mp4 needs the ffmpeg program, which is neither on the PATH nor bundled "
            "by imageio-ffmpeg",
            path=out,
            hint="pip install 'laserpeople[all]' (bundles ffmpeg), or install ffmpeg "
            "(e.g. apt install ffmpeg), or write a .gif instead",
        )
    return ffmpeg


def mp4_command(ffmpeg: str, size: tuple[int, int], frame_seconds: float, out: Path) -> list[str]:
    """The ffmpeg command line reading raw RGB frames of ``size`` ``(width, height)`` [px]
    from stdin and writing H.264 (yuv420p, so width and height are padded to even numbers
    with white) at ``1 / frame_seconds`` frames/s to ``out``."""
    w, h = size
    return [
        ffmpeg,
        "-y",
        "-nostdin",
        "-loglevel",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgb24",
        "-s",
        f"{w}x{h}",
        "-r",
        f"{1.0 / frame_seconds:.6g}",
        "-i",
        "-",
        "-an",
        "-vf",
        "pad=ceil(iw/2)*2:ceil(ih/2)*2:0:0:white",
        "-c:v",
        "libx264",
        "-pix_fmt",
        "yuv420p",
        "-crf",
        "20",
        "-movflags",
        "+faststart",
        str(out),
    ]


def write_mp4(images: Iterable[RGBImage], out: str | Path, frame_seconds: float) -> int:
    """Encode RGB images (all the same size) as H.264 MP4 by piping raw frames to
    ``ffmpeg``; returns the frame count."""
    ffmpeg = require_ffmpeg(out)
    p = Path(out)
    p.parent.mkdir(parents=True, exist_ok=True)
    it = iter(images)
    first = next(it, None)
    if first is None:
        raise LaserPeopleError("no frames to animate", hint="check --start/--stop/--every")
    h, w = first.shape[:2]
    cmd = mp4_command(ffmpeg, (w, h), frame_seconds, p)
    n = 0
    with subprocess.Popen(
        cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    ) as proc:
        assert proc.stdin is not None
        try:
            for img in _chain(first, it):
                if img.shape != first.shape:
                    raise LaserPeopleError(
                        f"frame {n} is {img.shape[1]}x{img.shape[0]} px, the first was {w}x{h}",
                        path=p,
                    )
                proc.stdin.write(np.ascontiguousarray(img, dtype=np.uint8).tobytes())
                n += 1
        except BrokenPipeError:
            pass  # ffmpeg stopped early; its message is reported below
        except BaseException:
            proc.kill()
            raise
        finally:
            with contextlib.suppress(BrokenPipeError):
                proc.stdin.close()
        err = proc.stderr.read().decode(errors="replace") if proc.stderr else ""
        code = proc.wait()
    if code != 0:
        p.unlink(missing_ok=True)  # a half-written file is no use
        raise LaserPeopleError(
            f"ffmpeg ({ffmpeg}) failed after {n} frames: {err.strip()[-400:]}",
            path=p,
            hint=ffmpeg_hint(err),
        )
    return n


FFMPEG_WRITE_ERRORS = ("No space left on device", "Read-only file system", "Permission denied")
"""What ffmpeg prints (the C library's wording) when the file system refused its output."""


def ffmpeg_hint(err: str) -> str:
    """What to do about ffmpeg's error text ``err``: free space or another folder when the
    file system refused the output, else an ffmpeg that can write H.264."""
    if any(text in err for text in FFMPEG_WRITE_ERRORS):
        return "free disk space, or give -o a path in a writable directory"
    return (
        "an ffmpeg without libx264 cannot write H.264: pip install "
        "'laserpeople[all]' bundles one that can"
    )


def _chain(first: RGBImage, rest: Iterator[RGBImage]) -> Iterator[RGBImage]:
    yield first
    yield from rest


def animate(
    scene: Scene,
    out: str | Path,
    *,
    size: tuple[int, int] = (640, 480),
    extent: Extent | None = None,
    fps: float | None = None,
    trail: int = 20,
    progress: ProgressFn | None = None,
    total: int | None = None,
) -> RenderResult:
    """Animate ``scene`` (one frame per drawn scan) as ``.gif`` or ``.mp4``.

    ``fps`` None plays in real time (frame spacing = median scan spacing times ``every``).
    """
    p = Path(out)
    suffix = p.suffix.lower()
    if suffix not in {".gif", ".mp4"}:
        raise LaserPeopleError(
            f"cannot animate to {suffix or 'a file without extension'}",
            path=p,
            hint="use .gif or .mp4",
        )
    if suffix == ".mp4":
        require_ffmpeg(p)
    import_matplotlib()
    if extent is None:
        extent = scene.extent()
    seconds = _frame_duration(scene, fps)
    images = iter_images(
        scene, size=size, extent=extent, trail=trail, progress=progress, total=total
    )
    n = write_gif(images, p, seconds) if suffix == ".gif" else write_mp4(images, p, seconds)
    return RenderResult(p, n, size, extent)


OVERVIEW_LINE_WIDTH = {"group": 1.8, "person": 0.9, "leg": 0.6}
"""Line width [pt] of each kind's trajectory in the overview: thin, so that a long
recording's hundreds of tracks stay apart."""


@dataclass(frozen=True)
class OverviewLabel:
    """A track's id written at the end of its trajectory.

    Attributes:
        frames: Number of scans the track was reported in (longer tracks win a place).
        x: End position x [m].
        y: End position y [m].
        text: The label.
        colour: RGB in [0, 1].
    """

    frames: int
    x: float
    y: float
    text: str
    colour: tuple[float, float, float]


def place_labels(
    labels: list[OverviewLabel],
    extent: Extent,
    size: tuple[int, int],
    *,
    min_frames: int = 5,
    char_px: tuple[float, float] = (5.0, 9.0),
) -> list[OverviewLabel]:
    """The labels that are written: longest tracks first, each only where it overlaps no
    label already placed, and (when more than 20 tracks) none for tracks shorter than
    ``min_frames`` scans. ``extent`` is the shown area (xmin, xmax, ymin, ymax) [m],
    ``size`` the image (width, height) [px], ``char_px`` the width of a character and the
    height of a line [px] at the label font."""
    box_w, box_h = AXES_BOX[2] * size[0], AXES_BOX[3] * size[1]
    sx = box_w / max(extent[1] - extent[0], 1e-9)
    sy = box_h / max(extent[3] - extent[2], 1e-9)
    keep_short = len(labels) <= 20
    boxes: list[tuple[float, float, float, float]] = []
    placed: list[OverviewLabel] = []
    for lab in sorted(labels, key=lambda lb: -lb.frames):
        if lab.frames < min_frames and not keep_short:
            continue
        x0, y0 = (lab.x - extent[0]) * sx, (lab.y - extent[2]) * sy
        box = (x0, y0, x0 + char_px[0] * len(lab.text), y0 + char_px[1])
        if any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in boxes):
            continue
        boxes.append(box)
        placed.append(lab)
    return placed


def plot_overview(
    scene: Scene,
    out: str | Path,
    *,
    size: tuple[int, int] = (800, 600),
    extent: Extent | None = None,
    max_points: int = 150_000,
) -> RenderResult:
    """Draw the whole window at once as PNG: the scan points (sub-sampled to at most
    ``max_points``), the sensor's path, every track's trajectory as a thin line in its
    colour, ids at the trajectory ends (:func:`place_labels`: the longest tracks first,
    never overlapping), group trajectories thicker with their largest size, and the truth
    dashed black."""
    mpl = import_matplotlib()
    del mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure

    points: list[np.ndarray] = []
    n_points = 0
    sensor: list[tuple[float, float]] = []
    paths: dict[tuple[str, int], list[tuple[float, float]]] = {}
    group_size: dict[int, int] = {}
    truth_paths: dict[int, list[tuple[float, float]]] = {}
    n_frames = 0
    for f in scene.frames():
        n_frames += 1
        sensor.append((f.sensor_pose.x, f.sensor_pose.y))
        if n_points < max_points:
            points.append(f.points)
            n_points += f.points.shape[0]
        elif n_frames % 8 == 0:
            points.append(f.points[::8])
        for t in f.tracks.tracks:
            paths.setdefault((t.kind, t.track_id), []).append(
                (float(t.position[0]), float(t.position[1]))
            )
            if t.kind == "group":
                group_size[t.track_id] = max(group_size.get(t.track_id, 0), t.size)
        if f.truth is not None:
            for pid, xy in zip(f.truth.person_ids, f.truth.positions, strict=True):
                truth_paths.setdefault(int(pid), []).append((float(xy[0]), float(xy[1])))
    if n_frames == 0:
        raise scene.empty_window_error()
    cloud = np.concatenate(points) if points else np.empty((0, 2))
    if cloud.shape[0] > max_points:
        cloud = cloud[:: int(np.ceil(cloud.shape[0] / max_points))]
    if extent is None:
        extent = scene.extent()
    fig = Figure(figsize=(size[0] / 100.0, size[1] / 100.0), dpi=100.0)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes(AXES_BOX)
    shown = square_extent(extent, (AXES_BOX[2] * size[0], AXES_BOX[3] * size[1]))
    ax.set_xlim(shown[0], shown[1])
    ax.set_ylim(shown[2], shown[3])
    ax.grid(True, color=(0.9, 0.9, 0.9), linewidth=0.6)
    ax.set_axisbelow(True)
    ax.tick_params(labelsize=7)
    ax.set_xlabel(f"x [m] ({scene.frame} frame)", fontsize=8)
    ax.set_ylabel("y [m]", fontsize=8)
    ax.plot(cloud[:, 0], cloud[:, 1], ",", color=(*to_unit(SCAN_POINTS), 0.2), zorder=1)
    s = np.array(sensor)
    ax.plot(s[:, 0], s[:, 1], "-", color=(0.1, 0.1, 0.1), linewidth=1.0, zorder=2)
    ax.plot(s[-1:, 0], s[-1:, 1], "^", color=(0.1, 0.1, 0.1), ms=6, zorder=2)
    if truth_paths:
        ax.add_collection(
            LineCollection(
                [np.array(v) for v in truth_paths.values()],
                colors=[(*to_unit(TRUTH), 0.7)],
                linestyles="--",
                linewidths=0.9,
                zorder=3,
            ),
            autolim=False,
        )
    has_people = any(k == "person" for k, _ in paths)
    shown_paths = {
        key: np.array(xy) for key, xy in paths.items() if not (key[0] == "leg" and has_people)
    }
    if shown_paths:
        keys = list(shown_paths)
        ax.add_collection(
            LineCollection(
                [shown_paths[k] for k in keys],
                colors=[to_unit(track_color(tid, kind)) for kind, tid in keys],
                linewidths=[OVERVIEW_LINE_WIDTH[kind] for kind, _ in keys],
                zorder=4,
            ),
            autolim=False,
        )
    labels = [
        OverviewLabel(
            len(xy),
            float(xy[-1, 0]),
            float(xy[-1, 1]),
            f"G{tid} ×{group_size[tid]}" if kind == "group" else f"{kind[0].upper()}{tid}",
            to_unit(label_color(tid, kind)),
        )
        for (kind, tid), xy in shown_paths.items()
    ]
    placed = place_labels(labels, shown, size)
    for lab in placed:
        ax.text(lab.x, lab.y, lab.text, color=lab.colour, fontsize=7, zorder=5, clip_on=True)
    n_tracks = len(shown_paths)
    labelled = "" if len(placed) == n_tracks else f" ({len(placed)} labelled at their ends)"
    ax.set_title(
        f"{_title(scene)}  {n_frames} scans, {n_tracks} tracks{labelled}"
        + (f", truth {len(truth_paths)} people" if truth_paths else ""),
        fontsize=9,
    )
    canvas.draw()
    image = np.ascontiguousarray(np.asarray(canvas.buffer_rgba())[:, :, :3])
    fig.clear()
    return RenderResult(save_png(image, out), 1, size, extent, overview_scans=n_frames)
