"""One reusable matplotlib figure (Agg backend) that draws a :class:`SceneFrame` per call.

Speed: the axes, ticks and grid are drawn once; every frame restores that background and
draws only the changing artists (scan points, tracks, ellipses, labels, truth), then hands
back the RGB pixels. A 640x480 frame takes a few milliseconds this way.

Matplotlib is imported here only, lazily, so the rest of the package works without the
``plots`` extra.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from functools import lru_cache
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from laserpeople.errors import LaserPeopleError
from laserpeople.truth import TruthFrame
from laserpeople.viz.colors import (
    BACKGROUND,
    SCAN_POINTS,
    TRUTH,
    label_color,
    to_unit,
    track_color,
)
from laserpeople.viz.geometry import (
    covariance_ellipses,
    group_outline,
    square_extent,
    velocity_segments,
)
from laserpeople.viz.scene import SceneFrame

FloatArray = NDArray[np.float64]
Extent = tuple[float, float, float, float]
AXES_BOX = (0.09, 0.08, 0.88, 0.86)
"""Axes position (left, bottom, width, height) as fractions of the image."""
LEGEND_MIN_SIZE = (480, 360)
"""Smallest image (width, height) [px] that gets a legend."""


class PlotsExtraMissingError(LaserPeopleError):
    """matplotlib (or pillow) is not installed."""


def import_matplotlib() -> ModuleType:
    """matplotlib with the Agg backend, or a clear error naming the extra to install."""
    try:
        import matplotlib
    except ImportError as exc:
        raise PlotsExtraMissingError(
            "drawing needs matplotlib, which is not installed",
            hint="pip install 'laserpeople[all]'",
        ) from exc
    matplotlib.use("Agg", force=True)
    return matplotlib


MISSING_GLYPH = "?"
"""Drawn for a character of a title that the font has no glyph for."""


@lru_cache(maxsize=1)
def _font_chars() -> frozenset[int]:
    """The characters (code points) the default font of the drawings has glyphs for."""
    import_matplotlib()
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    path = font_manager.findfont(font_manager.FontProperties())
    return frozenset(FT2Font(path).get_charmap())


def drawable(text: str) -> str:
    """``text`` with each character the font cannot draw (an emoji of a file name) as
    :data:`MISSING_GLYPH`: matplotlib would draw a box and warn with its own source line
    on every frame."""
    if text.isascii():
        return text
    chars = _font_chars()
    return "".join(c if ord(c) in chars or c in "\n\t" else MISSING_GLYPH for c in text)


def _rgb(color: tuple[int, int, int], alpha: float = 1.0) -> tuple[float, float, float, float]:
    r, g, b = to_unit(color)
    return (r, g, b, alpha)


class FrameRenderer:
    """Draws scene frames into a fixed-size RGB image.

    Args:
        extent: ``(xmin, xmax, ymin, ymax)`` [m] shown (widened to keep metres square).
        size: Image ``(width, height)`` [px]; even numbers suit video encoders.
        frame: Name of the display frame, written on the axes.
        trail: Number of past frames whose positions are drawn as a trail behind each track.
        title: Text at the top left of every frame (the scan time is added).
        t0: Time stamp [s] the captions count from (the recording's first scan); None
            counts from the first frame drawn.
        legend: Draw a legend of the markers (leg tracks, person tracks, true people) when
            the image is at least :data:`LEGEND_MIN_SIZE` (it would hide too much of a
            smaller one).
        truth: Whether the legend lists the ground-truth markers.
        kinds: The kinds of track the legend lists (``leg``, ``person``, ``group``);
            None: legs and people.
    """

    def __init__(
        self,
        extent: Extent,
        *,
        size: tuple[int, int] = (640, 480),
        frame: str = "world",
        trail: int = 20,
        title: str = "",
        t0: float | None = None,
        legend: bool = True,
        truth: bool = True,
        kinds: frozenset[str] | None = None,
    ) -> None:
        mpl = import_matplotlib()
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import LineCollection, PolyCollection
        from matplotlib.figure import Figure

        self._mpl = mpl
        self.size = (int(size[0]), int(size[1]))
        dpi = 100.0
        self.fig = Figure(figsize=(self.size[0] / dpi, self.size[1] / dpi), dpi=dpi)
        self.fig.patch.set_facecolor(_rgb(BACKGROUND))
        self.canvas = FigureCanvasAgg(self.fig)
        ax = self.fig.add_axes(AXES_BOX)
        self.ax = ax
        ax.set_facecolor(_rgb(BACKGROUND))
        self.extent = square_extent(
            extent, (AXES_BOX[2] * self.size[0], AXES_BOX[3] * self.size[1])
        )
        ax.set_xlim(self.extent[0], self.extent[1])
        ax.set_ylim(self.extent[2], self.extent[3])
        ax.grid(True, color=(0.9, 0.9, 0.9), linewidth=0.6)
        ax.set_axisbelow(True)
        ax.set_xlabel(f"x [m] ({frame} frame)", fontsize=8)
        ax.set_ylabel("y [m]", fontsize=8)
        ax.tick_params(labelsize=7)
        self.trail_len = max(0, int(trail))
        self.title = title
        self.t0 = t0

        def anim(artist: Any) -> Any:
            artist.set_animated(True)
            return artist

        (self._scan,) = ax.plot([], [], ".", ms=2.2, color=_rgb(SCAN_POINTS), animated=True)
        self._sensor = anim(
            PolyCollection([], facecolors=[_rgb((30, 30, 30))], edgecolors="none", zorder=4)
        )
        self._groups = anim(PolyCollection([], linewidths=1.6, zorder=2))
        self._trails = anim(LineCollection([], linewidths=1.2, zorder=3))
        self._ellipses = anim(LineCollection([], linewidths=1.0, zorder=5))
        self._velocity = anim(LineCollection([], linewidths=1.2, zorder=5))
        self._truth_lines = anim(
            LineCollection([], linewidths=0.8, colors=[_rgb(TRUTH, 0.6)], linestyles="--")
        )
        for coll in (
            self._sensor,
            self._groups,
            self._trails,
            self._ellipses,
            self._velocity,
            self._truth_lines,
        ):
            ax.add_collection(coll, autolim=False)
        self._legs = ax.scatter([], [], s=22, marker="o", linewidths=0.6, zorder=6, animated=True)
        self._people = ax.scatter([], [], s=70, marker="o", linewidths=0.8, zorder=7, animated=True)
        self._truth = ax.scatter(
            [],
            [],
            s=110,
            marker="o",
            facecolors="none",
            edgecolors=[_rgb(TRUTH)],
            linewidths=1.0,
            zorder=8,
            animated=True,
        )
        self._truth_legs = ax.scatter(
            [], [], s=14, marker="x", c=[_rgb(TRUTH)], linewidths=0.7, zorder=8, animated=True
        )
        self._info = ax.text(
            0.01,
            0.99,
            "",
            transform=ax.transAxes,
            va="top",
            ha="left",
            fontsize=8,
            animated=True,
            bbox={"facecolor": (1, 1, 1, 0.75), "edgecolor": "none", "pad": 1.5},
            zorder=10,
        )
        self._legend: Any = None
        if legend and all(a >= b for a, b in zip(self.size, LEGEND_MIN_SIZE, strict=True)):
            self._legend = _add_legend(ax, truth, kinds)  # drawn last, over the data
        self._labels: list[Any] = []
        self._history: dict[tuple[str, int], deque[tuple[float, float]]] = {}
        self._truth_history: dict[int, deque[tuple[float, float]]] = {}
        self.canvas.draw()
        self._background = self.canvas.copy_from_bbox(self.fig.bbox)

    # ------------------------------------------------------------------------------------
    def _label(self, i: int) -> Any:
        while len(self._labels) <= i:
            self._labels.append(
                self.ax.text(0, 0, "", fontsize=7, animated=True, clip_on=True, zorder=9, ha="left")
            )
        return self._labels[i]

    def draw(self, f: SceneFrame) -> NDArray[np.uint8]:
        """Draw one frame; returns the image as RGB (height, width, 3) uint8 (a copy)."""
        self.canvas.restore_region(self._background)
        ax = self.ax
        self._scan.set_data(f.points[:, 0], f.points[:, 1])
        self._sensor.set_verts([_sensor_triangle(f)])

        tracks = f.tracks.tracks
        legs = [t for t in tracks if t.kind == "leg"]
        people = [t for t in tracks if t.kind == "person"]
        groups = [t for t in tracks if t.kind == "group"]
        colours = {(t.kind, t.track_id): _rgb(track_color(t.track_id, t.kind)) for t in tracks}

        def scatter(artist: Any, items: list[Any]) -> None:
            if items:
                artist.set_offsets(np.array([t.position for t in items]))
                cols = [colours[(t.kind, t.track_id)] for t in items]
                artist.set_facecolors(cols)
                artist.set_edgecolors([(0.1, 0.1, 0.1, 1.0)] * len(items))
            else:
                artist.set_offsets(np.empty((0, 2)))

        scatter(self._legs, legs)
        scatter(self._people, people)

        with_contour = [g for g in groups if g.contour.shape[0] >= 1]
        self._groups.set_verts([group_outline(g.contour) for g in with_contour])
        self._groups.set_facecolors(
            [(*colours["group", g.track_id][:3], 0.18) for g in with_contour]
        )
        self._groups.set_edgecolors([colours[("group", g.track_id)] for g in with_contour])

        # groups without a contour are drawn by their covariance ellipse only
        drawn = [t for t in tracks if t.kind != "leg" or not people]
        if drawn:
            pos = np.array([t.position for t in drawn])
            cov = np.array([t.covariance for t in drawn])
            vel = np.array([t.velocity for t in drawn])
            self._ellipses.set_segments(list(covariance_ellipses(pos, cov)))
            self._ellipses.set_colors([colours[(t.kind, t.track_id)] for t in drawn])
            self._velocity.set_segments(list(velocity_segments(pos, vel)))
            self._velocity.set_colors([colours[(t.kind, t.track_id)] for t in drawn])
        else:
            self._ellipses.set_segments([])
            self._velocity.set_segments([])

        self._update_trails(drawn, colours)

        n_label = 0
        for t in drawn:
            if t.kind == "group":
                text = f"G{t.track_id} ×{t.size}"
            else:
                text = f"{'L' if t.kind == 'leg' else 'P'}{t.track_id}"
            lab = self._label(n_label)
            lab.set_text(text)
            lab.set_position((t.position[0] + 0.15, t.position[1] + 0.15))
            lab.set_color(to_unit(label_color(t.track_id, t.kind)))
            lab.set_visible(True)
            n_label += 1
        for lab in self._labels[n_label:]:
            lab.set_visible(False)

        truth = f.truth
        self._update_truth_trails(truth)
        if truth is not None and len(truth):
            self._truth.set_offsets(truth.positions)
            legs_xy = truth.leg_positions.reshape(-1, 2)
            legs_xy = legs_xy[np.all(np.isfinite(legs_xy), axis=1)]
            self._truth_legs.set_offsets(legs_xy if legs_xy.size else np.empty((0, 2)))
        else:
            self._truth.set_offsets(np.empty((0, 2)))
            self._truth_legs.set_offsets(np.empty((0, 2)))

        if self.t0 is None:
            self.t0 = f.scan.stamp
        self._info.set_text(
            caption(
                self.title,
                f.scan.index,
                f.scan.stamp - self.t0,
                len(people),
                len(legs),
                len(groups),
                None if truth is None else len(truth),
            )
        )

        for artist in (
            self._groups,
            self._scan,
            self._sensor,
            self._trails,
            self._truth_lines,
            self._ellipses,
            self._velocity,
            self._legs,
            self._people,
            self._truth,
            self._truth_legs,
            *self._labels[:n_label],
            self._info,
            *([self._legend] if self._legend is not None else []),
        ):
            ax.draw_artist(artist)
        rgba = np.asarray(self.canvas.buffer_rgba())
        return np.ascontiguousarray(rgba[:, :, :3])

    def _update_trails(
        self, tracks: Sequence[Any], colours: dict[Any, tuple[float, float, float, float]]
    ) -> None:
        if self.trail_len == 0:
            self._trails.set_segments([])
            return
        alive = {(t.kind, t.track_id) for t in tracks}
        for key in [k for k in self._history if k not in alive]:
            del self._history[key]
        for t in tracks:
            key = (t.kind, t.track_id)
            hist = self._history.setdefault(key, deque(maxlen=self.trail_len))
            hist.append((float(t.position[0]), float(t.position[1])))
        keys = [k for k, h in self._history.items() if len(h) > 1]
        self._trails.set_segments([np.array(self._history[k]) for k in keys])
        self._trails.set_colors([(*colours[k][:3], 0.7) for k in keys])

    def _update_truth_trails(self, truth: TruthFrame | None) -> None:
        if self.trail_len == 0 or truth is None:
            self._truth_history.clear()
            self._truth_lines.set_segments([])
            return
        alive = {int(i) for i in truth.person_ids}
        for key in [k for k in self._truth_history if k not in alive]:
            del self._truth_history[key]
        for pid, xy in zip(truth.person_ids, truth.positions, strict=True):
            hist = self._truth_history.setdefault(int(pid), deque(maxlen=self.trail_len))
            hist.append((float(xy[0]), float(xy[1])))
        self._truth_lines.set_segments(
            [np.array(h) for h in self._truth_history.values() if len(h) > 1]
        )

    def reset(self) -> None:
        """Forget the trails (start a new sequence)."""
        self._history.clear()
        self._truth_history.clear()

    def close(self) -> None:
        """Free the figure."""
        self.fig.clear()


def caption(
    title: str,
    scan: int,
    seconds: float,
    people: int,
    legs: int,
    groups: int,
    truth: int | None,
) -> str:
    """The text at the top left of a frame: the title, the scan index and the seconds
    since the recording's first scan, and what is tracked (``truth`` None: no truth)."""
    counts = [
        counted(people, "person", "people") if people else "",
        counted(legs, "leg", "legs") if legs else "",
        counted(groups, "group", "groups") if groups else "",
        f"truth: {counted(truth, 'person', 'people')}" if truth is not None else "",
    ]
    lines = [title, f"scan {scan}  t = {seconds:.2f} s", ", ".join(c for c in counts if c)]
    return "\n".join(line for line in lines if line)


def counted(n: int, one: str, many: str) -> str:
    """``"1 person"``, ``"2 people"``."""
    return f"{n} {one if n == 1 else many}"


def _add_legend(ax: Any, truth: bool, kinds: frozenset[str] | None = None) -> Any:
    """The legend of the markers a frame uses (tracks of ``kinds``; None: legs and
    people), as an animated artist (drawn over the data of every frame); None when there
    is nothing to list."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    grey, dark = (0.6, 0.6, 0.6, 1.0), (0.1, 0.1, 0.1, 1.0)

    def marker(label: str, ms: float, face: Any, edge: Any, shape: str = "o") -> Any:
        return Line2D(
            [],
            [],
            linestyle="none",
            marker=shape,
            markersize=ms,
            markerfacecolor=face,
            markeredgecolor=edge,
            markeredgewidth=0.8,
            label=label,
        )

    kinds = frozenset({"person", "leg"}) if kinds is None else kinds
    handles = []
    if "group" in kinds:
        handles.append(
            Patch(
                facecolor=(*grey[:3], 0.18),
                edgecolor=dark,
                label="group track (outline; label G + id ×people)",
            )
        )
    if "person" in kinds:
        handles.append(marker("person track (label P + id, one colour per id)", 6.5, grey, dark))
    if "leg" in kinds:
        handles.append(marker("leg track (small dot)", 4.0, grey, dark))
    if truth:
        handles += [
            marker("true person (ground truth ring)", 7.5, "none", _rgb(TRUTH)),
            marker("true leg", 3.5, _rgb(TRUTH), _rgb(TRUTH), "x"),
        ]
    if not handles:
        return None
    legend = ax.legend(
        handles=handles,
        loc="lower right",
        fontsize=6,
        framealpha=0.85,
        borderpad=0.4,
        handlelength=2.0,
        handletextpad=0.8,
        labelspacing=0.5,
    )
    legend.set_animated(True)
    return legend


def _sensor_triangle(f: SceneFrame, size: float = 0.35) -> FloatArray:
    """A triangle (3, 2) [m] at the sensor pointing along its heading."""
    p = f.sensor_pose
    local = np.array([[size, 0.0], [-0.5 * size, 0.45 * size], [-0.5 * size, -0.45 * size]])
    return p.transform_points(local)
