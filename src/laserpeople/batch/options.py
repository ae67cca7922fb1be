"""What a batch run tracks with: every option of ``laserpeople track``, resolved once.

:class:`TrackOptions` holds the choices as given (tracker name, ``--config`` file, topics,
detector, background, ...). :func:`resolve` reads the config file once, on the machine
that starts the run, into :class:`ResolvedTrack`: parameter objects that are sent to the
workers (a worker never reads the config file, so a cluster needs no copy of it), and
:attr:`ResolvedTrack.digest`, a hash of the complete resolved configuration (every
parameter with its value, the detector's model file content, the map file content, the
options and the package version) that keys the manifest: change one value and every
recording is tracked again.
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from laserpeople.errors import ConfigError

FORMATS = ("csv", "parquet")
"""Formats of the per-recording tracks files."""

TOPIC_EACH = "each"
"""Topic mode: every laser topic of a recording on its own (one output and row each)."""


@dataclass(frozen=True)
class TrackOptions:
    """The options of ``laserpeople track``, as a batch run takes them.

    Attributes:
        tracker: Registered tracker name (``leg-mht``, ``nn``, ``group-mht``, ``csa``,
            ``feet-pf``, ``upper-body-pf``).
        preset: ``paper``: every parameter section starts from the papers' values
            (``--preset``, :data:`laserpeople.config.PRESETS`), before ``config``.
        config: TOML file with tracker, detector and static world parameters (None:
            defaults).
        topics: ``()`` tracks every laser topic on its own (one tracks file per topic);
            ``("all",)`` fuses every laser topic into one; named topics are fused into one
            (one name: that laser only).
        detector: ``adaboost`` or ``heuristic``.
        model: AdaBoost model JSON (None: the shipped model).
        output_frame: ``sensor``, ``world`` or None (the tracking frame).
        world_frame: Fixed frame for sensor poses in bags.
        mounts: Laser mounts missing from a bag's tf (``CHILD=PARENT:x,y,theta``, ``mir100``).
        people_policy: leg-mht person layer (``tracks`` or ``arras``; None: the config's).
        background: Static world model (``auto``, ``histogram``, ``occupancy``, ``none``).
        map_path: ROS map.yaml, or ``BAG:/topic`` of a ``nav_msgs/OccupancyGrid``, seeding
            the occupancy grid.
        reidentify: Colour re-identification (simulated recordings with truth only).
        on_error: A damaged scan: ``stop`` (the recording fails) or ``skip``.
        restamp: Track at this fixed scan rate [Hz] instead of the recorded stamps.
        format: Tracks file format, ``csv`` (as ``track`` writes) or ``parquet``.
    """

    tracker: str = "leg-mht"
    config: Path | None = None
    preset: str | None = None
    topics: tuple[str, ...] = ()
    detector: str = "adaboost"
    model: Path | None = None
    output_frame: str | None = None
    world_frame: str | None = None
    mounts: tuple[str, ...] = ()
    people_policy: str | None = None
    background: str = "auto"
    map_path: Path | None = None
    reidentify: bool = False
    on_error: str = "stop"
    restamp: float | None = None
    format: str = "csv"

    def __post_init__(self) -> None:
        if self.format not in FORMATS:
            raise ConfigError(f"--format {self.format!r} is not known", hint="use csv or parquet")
        if self.output_frame not in (None, "sensor", "world"):
            raise ConfigError(f"--output-frame must be sensor or world, not {self.output_frame!r}")
        if "all" in self.topics and len(self.topics) > 1:
            raise ConfigError("--topics all cannot be combined with named topics")


@dataclass(frozen=True)
class ResolvedTrack:
    """:class:`TrackOptions` with every parameter read (what a worker needs).

    Attributes:
        options: The options.
        tracker_params: The tracker's parameter object.
        static_world: The static world models' parameters.
        grouping: Grouping of several lasers into frames.
        leg_fusion: Fusion of legs seen by several lasers.
        detector_params: The leg detector's parameters.
        consumes: What the tracker reads of a frame (decides the contour column).
        digest: SHA-256 (hex) of the resolved configuration (see the module docstring).
        text: The resolved configuration as TOML-like text (what ``digest`` hashes).
    """

    options: TrackOptions
    tracker_params: Any
    static_world: Any
    grouping: Any
    leg_fusion: Any
    detector_params: Any
    consumes: frozenset[str] = field(default_factory=frozenset)
    digest: str = ""
    text: str = ""

    @property
    def contours(self) -> bool:
        """Whether tracks files get the ``contour`` column (trackers of points, as ``track``)."""
        return bool(self.consumes & {"points", "clusters"})


def resolve(
    options: TrackOptions, overrides: Mapping[str, Mapping[str, Any]] | None = None
) -> ResolvedTrack:
    """Read ``options.config`` into parameter objects and hash the result.

    Args:
        options: The run's options.
        overrides: ``{section: {key: value}}`` set over the config file (a sweep's grid
            point); an unknown section or key is a ConfigError.

    Raises:
        ConfigError: An unknown tracker, section, key or value (naming the file).
    """
    from laserpeople.config import (
        check_sections,
        from_mapping,
        load_config,
        merged,
        section_name,
        to_toml,
    )
    from laserpeople.detection.detector import LegDetectorParams
    from laserpeople.pipeline import GroupingParams, LegFusionParams
    from laserpeople.pipeline.background import StaticWorldParams, load_static_world
    from laserpeople.tracking import registry

    entry = registry.get(options.tracker)
    static_classes = StaticWorldParams.sections()
    classes = [LegDetectorParams, GroupingParams, LegFusionParams, entry.params_cls]
    others = [e.params_cls for e in registry.TRACKERS.values()]
    check_sections(options.config, [*classes, *static_classes], others)
    overrides = dict(overrides or {})
    known = {section_name(c): c for c in [*classes, *static_classes]}
    unknown = sorted(set(overrides) - set(known))
    if unknown:
        raise ConfigError(
            f"unknown section(s) {', '.join(f'[{u}]' for u in unknown)} in the settings",
            hint=f"the {options.tracker} run reads {', '.join(f'[{k}]' for k in sorted(known))}",
        )

    def load(cls: type) -> Any:
        obj: Any = load_config(cls, options.config, options.preset)
        values = overrides.get(section_name(cls))
        if not values:
            return obj
        # the current values as a table (nested parameter classes as tables, as a file
        # writes them), the grid point's over them; the error names no file: the sweep's
        return from_mapping(cls, merged(dataclasses.asdict(obj), values))

    params = load(entry.params_cls)
    if options.people_policy is not None:
        from laserpeople.tracking.registry import with_people_policy

        params = with_people_policy(params, options.people_policy, options.tracker)
    static = load_static_world(options.config, options.preset)
    static = replace(
        static,
        **{
            name: load(type(getattr(static, name)))
            for name in static.__dataclass_fields__
            if section_name(type(getattr(static, name))) in overrides
        },
    )
    grouping = load(GroupingParams)
    fusion = load(LegFusionParams)
    det = load(LegDetectorParams)
    every = [
        params,
        det,
        grouping,
        fusion,
        *(getattr(static, n) for n in static.__dataclass_fields__),
    ]
    text = "\n".join(dict.fromkeys(to_toml(obj) for obj in every))
    text += "\n" + _options_text(options)
    return ResolvedTrack(
        options=options,
        tracker_params=params,
        static_world=static,
        grouping=grouping,
        leg_fusion=fusion,
        detector_params=det,
        consumes=frozenset(entry.consumes),
        digest=hashlib.sha256(text.encode()).hexdigest(),
        text=text,
    )


def _options_text(options: TrackOptions) -> str:
    """The options that change a run's output, with the content hashes of the files they
    name and the package version (``config`` is left out: its values are in the text)."""
    from laserpeople import __version__
    from laserpeople.batch.hashing import content_hash

    lines = [f"laserpeople = {__version__}"]
    for name in TrackOptions.__dataclass_fields__:
        if name == "config":
            continue
        value = getattr(options, name)
        if name == "map_path" and value is not None:
            value = _map_text(value)
        elif isinstance(value, Path):
            value = f"{value.name} sha256:{content_hash(value)}"
        lines.append(f"{name} = {value!r}")
    return "\n".join(lines) + "\n"


def _map_text(spec: Path) -> str:
    """A ``--map`` for the configuration hash: the bag's content hash and topic for
    ``BAG:/topic``, else the content hashes of ``map.yaml`` and the image it names."""
    from laserpeople.background.bag_map import split_bag_spec
    from laserpeople.background.occupancy import map_files
    from laserpeople.batch.hashing import content_hash

    bag = split_bag_spec(spec)
    if bag is not None:
        return f"{bag[0].name}:{bag[1]} sha256:{content_hash(bag[0])}"
    return " ".join(f"{f.name} sha256:{content_hash(f)}" for f in map_files(spec))


def parse_topics(topic: Sequence[str] | None, topics: str | None) -> tuple[str, ...]:
    """The ``topics`` of :class:`TrackOptions` from ``--topic`` (repeatable) and ``--topics``
    (``all``: fuse every laser; ``each``: every laser on its own, the default)."""
    if topics is not None:
        if topics not in ("all", TOPIC_EACH):
            raise ConfigError(f"--topics {topics!r}: only 'all' or 'each' is known")
        if topic:
            raise ConfigError("give --topic or --topics, not both")
        return ("all",) if topics == "all" else ()
    return tuple(topic or ())


__all__ = ["FORMATS", "TOPIC_EACH", "ResolvedTrack", "TrackOptions", "parse_topics", "resolve"]
