"""One entry point that picks the output by the file extension of ``out``."""

from __future__ import annotations

import os
from contextlib import suppress
from dataclasses import replace
from pathlib import Path

from laserpeople.errors import LaserPeopleError
from laserpeople.io.paths import staging_name, why_unwritable
from laserpeople.spelling import did_you_mean
from laserpeople.viz.figure import Extent
from laserpeople.viz.raster import RenderResult, animate, plot_overview, plot_scan
from laserpeople.viz.scene import ProgressFn, Scene

OUTPUT_KINDS = (".png", ".gif", ".mp4", ".mcap", ".rrd")


def render(
    scene: Scene,
    out: str | Path,
    *,
    scan: int | None = None,
    size: tuple[int, int] | None = None,
    extent: Extent | None = None,
    fps: float | None = None,
    trail: int = 20,
    progress: ProgressFn | None = None,
) -> RenderResult:
    """Write ``scene`` to ``out``, the kind chosen by its extension.

    ``.png``: the scan ``scan`` with its tracks, or (``scan`` None) the trajectory overview
    of the whole window; ``.gif``/``.mp4``: one frame per drawn scan; ``.mcap``: Foxglove
    (LaserScan, TF, MarkerArrays); ``.rrd``: rerun. ``size`` is ``(width, height)`` [px]
    (default 800x600 for pictures, 640x480 for animations).


    Raises:
        LaserPeopleError: unknown extension, bad options, or the file cannot be written
            (the message names it).
    """
    p = Path(out)
    # the MCAP export assembles its file beside ``out`` itself; the other writers stream into
    # a file of their own beside it that replaces ``out`` once complete, so that a full disk
    # or an interruption leaves no torn picture and an older file as it was
    staged = p.suffix.lower() in OUTPUT_KINDS and p.suffix.lower() != ".mcap"
    target = staging_name(p) if staged else p
    try:
        result = _render(scene, target, scan, size, extent, fps, trail, progress)
        if staged:
            os.replace(target, p)
        return replace(result, path=p, tracks_outside=scene.tracks_outside)
    except LaserPeopleError as exc:
        raise exc.moved(target, p) from exc.__cause__
    except OSError as exc:  # image and animation writers let file-system errors through
        raise LaserPeopleError(
            f"cannot write the output: {why_unwritable(exc, p)}",
            path=p,
            hint="give -o a path in a writable directory",
        ) from exc
    finally:
        if staged:
            with suppress(OSError):
                target.unlink(missing_ok=True)


def _render(
    scene: Scene,
    p: Path,
    scan: int | None,
    size: tuple[int, int] | None,
    extent: Extent | None,
    fps: float | None,
    trail: int,
    progress: ProgressFn | None,
) -> RenderResult:
    suffix = p.suffix.lower()
    if suffix not in OUTPUT_KINDS:
        raise LaserPeopleError(
            f"unknown output kind {suffix or '(no extension)'!r}"
            + did_you_mean(suffix, OUTPUT_KINDS, lead="; "),
            path=p,
            hint=f"use one of {', '.join(OUTPUT_KINDS)}",
        )
    if suffix == ".png":
        px = size or (800, 600)
        if scan is None:
            return plot_overview(scene, p, size=px, extent=extent)
        return plot_scan(scene, p, scan=scan, size=px, extent=extent, trail=trail)
    if scan is not None:
        raise LaserPeopleError(
            f"--scan picks one scan for a .png; a {suffix} shows every scan",
            path=p,
            hint="use --start/--stop/--every to choose the scans of an animation or export",
        )
    total = scene.count() if progress is not None else None
    if suffix in {".gif", ".mp4"}:
        return animate(
            scene,
            p,
            size=size or (640, 480),
            extent=extent,
            fps=fps,
            trail=trail,
            progress=progress,
            total=total,
        )
    if suffix == ".mcap":
        from laserpeople.viz.mcap_export import export_mcap

        n = export_mcap(scene, p, progress=progress, total=total)
    else:
        from laserpeople.viz.rerun_export import export_rerun

        n = export_rerun(scene, p, progress=progress, total=total)
    return RenderResult(p, n, (0, 0), extent or (0.0, 0.0, 0.0, 0.0))
