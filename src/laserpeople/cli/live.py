"""`laserpeople live`: track a running ROS 2 robot's laser scans over Zenoh, publish people."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from laserpeople.cli.common import (
    BackgroundOption,
    ConfigOption,
    DetectorOption,
    MapOption,
    ModelOption,
    MountOption,
    PeoplePolicyOption,
    PresetOption,
    WorldFrameOption,
    say,
    warn,
)
from laserpeople.cli.track import make_detector
from laserpeople.errors import ConfigError, LaserPeopleError


def _optional_topic(name: str) -> str | None:
    """A topic option: empty or ``none`` turns the subscription off."""
    return None if name.strip().lower() in ("", "none") else name


def _check_seconds(option: str, value: float | None, *, zero: bool) -> None:
    """A time option must be a finite number of seconds, above 0 (``zero``: or 0)."""
    if value is None:
        return
    import math

    if not (math.isfinite(value) and (value >= 0.0 if zero else value > 0.0)):
        raise ConfigError(
            f"{option} {value!r} must be a finite number of seconds "
            + ("(0 or more)" if zero else "above 0"),
            hint=f"e.g. {option} {'0.1' if zero else '60'}",
        )


def check_live_names(
    lasers: list[str],
    tf_topic: str,
    tf_static_topic: str,
    odom_topic: str,
    output_prefix: str,
    key_prefix: str,
) -> None:
    """Refuse topic options that are not ROS 2 topic names, a ``--key-prefix`` that cannot
    start a Zenoh key (:mod:`laserpeople.live.names`), a laser topic given twice, and an
    ``--output-prefix`` under which a topic the run reads would be published to.

    Raises:
        ConfigError: Naming the option and the value.
    """
    from laserpeople.live.keys import strip_topic
    from laserpeople.live.messages import output_topics
    from laserpeople.live.names import check_key_prefix, check_topic

    for laser in lasers:
        check_topic("--topic", laser)
    read = {"--tf-topic": tf_topic, "--tf-static-topic": tf_static_topic}
    read["--odom-topic"] = odom_topic
    for option, name in read.items():
        if _optional_topic(name) is not None:
            check_topic(option, name)
    check_topic("--output-prefix", output_prefix, empty_ok=True)
    check_key_prefix(key_prefix)
    names = [strip_topic(t) for t in lasers]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ConfigError(f"--topic /{twice[0]} is given twice", hint="give each laser topic once")
    written = {strip_topic(t) for t in output_topics(output_prefix)}
    for option, name in [*(("--topic", t) for t in lasers), *read.items()]:
        if _optional_topic(name) is not None and strip_topic(name) in written:
            raise ConfigError(
                f"{option} {name!r} is a topic this run publishes its tracks on "
                f"(--output-prefix {output_prefix!r})",
                hint="choose another --output-prefix",
            )


def check_live_options(
    transport: str,
    key_prefix: str,
    domain: int,
    type_hashes: str,
    frame: str,
    world_frame: str | None,
    mount: list[str] | None,
    map_path: Path | None,
) -> None:
    """Refuse options the chosen transport or frame would not use: ``--key-prefix`` with
    rmw_zenoh (its keys start with the domain), ``--domain`` and ``--type-hashes`` with the
    bridge (its keys are the topic names), poses (``--world-frame``, ``--mount``) and a
    ``--map`` with ``--frame sensor``; and a ``--type-hashes`` that is not rihs01 or none.

    Raises:
        ConfigError: Naming the option and what it needs.
    """
    if type_hashes not in ("rihs01", "none"):
        raise ConfigError(f"--type-hashes {type_hashes!r}: choose rihs01 or none")
    if transport == "rmw" and key_prefix.strip("/"):
        raise ConfigError(
            f"--key-prefix {key_prefix!r} applies to the bridge transport",
            hint="rmw_zenoh keys start with the ROS domain: give --domain, or --transport bridge",
        )
    if transport == "bridge":
        unused = [f"--domain {domain}"] if domain != 0 else []
        unused += [f"--type-hashes {type_hashes}"] if type_hashes != "rihs01" else []
        if unused:
            raise ConfigError(
                f"{' and '.join(unused)} {'apply' if len(unused) > 1 else 'applies'} to the "
                "rmw transport",
                hint="zenoh-bridge-ros2dds keys are the topic names, and the bridge's own "
                "configuration picks the domain; drop them, or give --transport rmw",
            )
    if frame == "sensor":
        given = [name for name, value in (("--world-frame", world_frame), ("--mount", mount),
                                          ("--map", map_path)) if value]  # fmt: skip
        if given:
            raise ConfigError(
                f"{' and '.join(given)} {'need' if len(given) > 1 else 'needs'} the world "
                "frame, but --frame sensor tracks without poses",
                hint="drop them, or give --frame world (or auto)",
            )


def _status_printer(meter: Any, stop: Any) -> None:
    """Refresh the status line every half second (a line every 10 s when not a terminal);
    once, after :data:`~laserpeople.live.waiting.NO_SCAN_WAIT` without a scan, warn what to
    check (warnings are printed with ``--quiet`` too)."""
    import sys
    import time

    from laserpeople.cli.common import STATE
    from laserpeople.live.waiting import connected_count, no_scan_note

    tty = sys.stderr.isatty()
    period = 0.5 if tty else 10.0
    session = meter.session
    start = last = time.monotonic()
    noted = False
    while not stop.wait(min(period, 1.0)):  # (each second at least: the warning's time)
        if not noted and not sum(session.scans.counts.received.values()):
            note = no_scan_note(
                time.monotonic() - start,
                session.topics.lasers,
                session.settings.connect,
                connected_count(session.session),
            )
            if note:
                noted = True
                if tty and not STATE.quiet:
                    sys.stderr.write("\n")
                warn(note)
        if STATE.quiet or time.monotonic() - last < period - 0.01:
            continue
        last = time.monotonic()
        line = meter.line()
        if tty:
            sys.stderr.write("\r" + line + "\x1b[K")
            sys.stderr.flush()
        else:
            print(line, file=sys.stderr, flush=True)
    if tty and not STATE.quiet:
        sys.stderr.write("\n")


def register(app: typer.Typer) -> None:
    """Add the `live` command to ``app``."""

    @app.command("live")
    def live(
        tracker: Annotated[
            str,
            typer.Option(
                "--tracker",
                help="Tracker, as for track: leg-mht, nn, group-mht, csa, "
                "feet-pf or upper-body-pf.",
            ),
        ] = "leg-mht",
        topic: Annotated[
            list[str] | None,
            typer.Option(
                "--topic",
                "-t",
                help="Laser topic (repeatable: several lasers are fused into one frame, the "
                "first leads; default: /scan).",
            ),
        ] = None,
        config: ConfigOption = None,
        preset: PresetOption = None,
        detector: DetectorOption = "adaboost",
        model: ModelOption = None,
        people_policy: PeoplePolicyOption = None,
        background: BackgroundOption = "auto",
        map_path: MapOption = None,
        world_frame: WorldFrameOption = None,
        mount: MountOption = None,
        frame: Annotated[
            str,
            typer.Option(
                "--frame",
                help="Tracking frame: world (poses from tf/odometry), sensor (no transforms "
                "subscribed; one laser) or auto (world from the first scan with a pose within "
                "1 s of the first scan, else sensor; frames are not held meanwhile).",
            ),
        ] = "auto",
        transport: Annotated[
            str,
            typer.Option(
                "--transport",
                help="How the robot puts ROS 2 on Zenoh: bridge (zenoh-bridge-ros2dds: keys "
                "are topic names) or rmw (rmw_zenoh: <domain>/<topic>/<type>/<hash> keys and "
                "liveliness tokens).",
            ),
        ] = "bridge",
        connect: Annotated[
            list[str] | None,
            typer.Option(
                "--connect",
                help="Zenoh endpoint of the bridge or router (repeatable), e.g. "
                "tcp/192.168.1.10:7447.",
            ),
        ] = None,
        listen: Annotated[
            list[str] | None,
            typer.Option("--listen", help="Zenoh endpoint to listen on (repeatable)."),
        ] = None,
        mode: Annotated[
            str, typer.Option("--mode", help="Zenoh session mode: peer or client.")
        ] = "peer",
        scouting: Annotated[
            bool,
            typer.Option(
                "--scouting/--no-scouting", help="Find Zenoh peers by multicast on the LAN."
            ),
        ] = False,
        domain: Annotated[
            int, typer.Option("--domain", min=0, max=232, help="ROS domain id (rmw transport).")
        ] = 0,
        type_hashes: Annotated[
            str,
            typer.Option(
                "--type-hashes",
                help="rmw transport: rihs01 (Iron, Jazzy and later) or none (Humble).",
            ),
        ] = "rihs01",
        key_prefix: Annotated[
            str,
            typer.Option("--key-prefix", help="bridge transport: prefix of every Zenoh key."),
        ] = "",
        tf_topic: Annotated[
            str, typer.Option("--tf-topic", help="tf topic ('none': off).")
        ] = "/tf",
        tf_static_topic: Annotated[
            str, typer.Option("--tf-static-topic", help="Static tf topic ('none': off).")
        ] = "/tf_static",
        odom_topic: Annotated[
            str,
            typer.Option("--odom-topic", help="nav_msgs/Odometry topic ('none': off)."),
        ] = "/odom",
        output_prefix: Annotated[
            str,
            typer.Option(
                "--output-prefix",
                help="Tracks are published on PREFIX/people, /legs, /groups "
                "(people_msgs/People) and PREFIX/markers (visualization_msgs/MarkerArray).",
            ),
        ] = "/laserpeople",
        queue: Annotated[
            int | None,
            typer.Option(
                "--queue",
                min=1,
                help="Scans kept per laser while the tracker is busy; older ones are dropped "
                "and counted (1: always the newest). Default: 1 with one laser, 2 with several.",
            ),
        ] = None,
        tf_wait: Annotated[
            float,
            typer.Option(
                "--tf-wait", help="Longest wait for a transform covering a scan's stamp [s]."
            ),
        ] = 0.1,
        order_wait: Annotated[
            float | None,
            typer.Option(
                "--order-wait",
                help="Several lasers: longest wait of a frame for the other lasers' scans of "
                "its instant [s]; default: one scan period of the slowest other laser.",
            ),
        ] = None,
        record: Annotated[
            Path | None,
            typer.Option(
                "--record",
                help="Write the scans tracked and the published tracks to this .mcap (replay "
                "it with track).",
            ),
        ] = None,
        foxglove: Annotated[
            int | None,
            typer.Option(
                "--foxglove",
                metavar="PORT",
                min=0,
                max=65535,
                help="Serve scans, legs, people and groups to Foxglove on this port "
                "(ws://HOST:PORT; 8765 is Foxglove's default).",
            ),
        ] = None,
        foxglove_host: Annotated[
            str,
            typer.Option("--foxglove-host", help="Address the Foxglove server listens on."),
        ] = "127.0.0.1",
        duration: Annotated[
            float | None,
            typer.Option("--duration", help="Stop after this many seconds."),
        ] = None,
        max_scans: Annotated[
            int | None,
            typer.Option("--max-scans", min=1, help="Stop after receiving this many scans."),
        ] = None,
    ) -> None:
        """Track a running ROS 2 robot without ROS installed: subscribe to its LaserScan
        topics, /tf and /odom over Zenoh, run the same pipeline as track, and publish the
        people, legs and groups back (the messages track --bag writes). Runs until Ctrl-C,
        SIGTERM, --duration or --max-scans; prints a refreshing status line and a summary."""
        import signal
        import threading

        from laserpeople.live.zenoh_link import ZenohSettings, import_zenoh

        import_zenoh()  # says what to install before anything else is loaded

        from laserpeople.cli.common import ignored_sections
        from laserpeople.cli.track import tracker_param_classes
        from laserpeople.config import check_sections, load_config
        from laserpeople.detection.detector import LegDetectorParams
        from laserpeople.live.runner import (
            LiveSession,
            LiveTopics,
            StatusMeter,
            tracker_pipelines,
        )
        from laserpeople.pipeline import GroupingParams, LegFusionParams
        from laserpeople.pipeline.background import StaticWorldParams, load_static_world
        from laserpeople.tracking import registry

        if transport not in ("bridge", "rmw"):
            raise ConfigError(f"--transport {transport!r}: choose bridge or rmw")
        _check_seconds("--duration", duration, zero=False)
        _check_seconds("--tf-wait", tf_wait, zero=True)
        _check_seconds("--order-wait", order_wait, zero=True)
        if frame not in ("auto", "world", "sensor"):
            raise ConfigError(f"--frame {frame!r}: choose auto, world or sensor")
        check_live_names(
            topic or ["/scan"], tf_topic, tf_static_topic, odom_topic, output_prefix, key_prefix
        )
        check_live_options(
            transport, key_prefix, domain, type_hashes, frame, world_frame, mount, map_path
        )
        if frame == "sensor" and topic is not None and len(topic) > 1:
            raise ConfigError(
                f"--frame sensor with {len(topic)} lasers: several lasers are fused only in the "
                "world frame; give --frame world (or auto), or one --topic"
            )
        if record is not None and record.suffix.lower() != ".mcap":
            raise ConfigError(f"--record writes a .mcap, not {record.name!r}")
        if record is not None:
            from laserpeople.io.paths import check_outputs

            check_outputs({"--record": record}, [config, model, map_path])
        entry = registry.get(tracker)
        # (imported here: laserpeople.pipeline imports numpy, which `live --help` needs not)
        from laserpeople.pipeline.unused_options import preset_note

        note = preset_note(tracker, entry.params_cls, preset)
        if note:
            warn(note)
        ignored_sections(
            config,
            check_sections(
                config,
                [LegDetectorParams, GroupingParams, LegFusionParams, entry.params_cls,
                 *StaticWorldParams.sections()],
                tracker_param_classes() if config is not None else (),
            ),
        )  # fmt: skip
        params: Any = load_config(entry.params_cls, config, preset)
        if people_policy is not None:
            params = registry.with_people_policy(params, people_policy, tracker)
        from laserpeople.io.poses import parse_mounts

        if map_path is not None and frame != "sensor":
            from laserpeople.background.bag_map import world_frame_with_map

            chosen = world_frame_with_map(map_path, world_frame)
            if chosen != world_frame:
                say(f"world frame: {chosen!r}, the frame of the map {map_path}")
            world_frame = chosen
        make = tracker_pipelines(
            tracker,
            params,
            detector=make_detector(detector, model, config, preset),
            leg_fusion=load_config(LegFusionParams, config),
            background=background,
            map_path=map_path,
            static_world=load_static_world(config, preset),
        )
        use_poses = frame != "sensor"
        topics = LiveTopics(
            lasers=tuple(topic or ["/scan"]),
            tf=_optional_topic(tf_topic) if use_poses else None,
            tf_static=_optional_topic(tf_static_topic) if use_poses else None,
            odometry=_optional_topic(odom_topic) if use_poses else None,
            output_prefix=output_prefix,
        )
        sinks: list[Any] = []
        viewer = None
        if foxglove is not None:
            from laserpeople.live.foxglove import FoxgloveSink

            viewer = FoxgloveSink(foxglove, foxglove_host, lasers=topic or ["/scan"])
            sinks.append(viewer)
        session = LiveSession(
            topics,
            ZenohSettings(mode, tuple(connect or ()), tuple(listen or ()), scouting),  # type: ignore[arg-type]
            transport,  # type: ignore[arg-type]
            make,
            domain=domain,
            hashes=type_hashes,
            key_prefix=key_prefix,
            world_frame=world_frame,
            mounts=parse_mounts(mount or []),
            use_poses=use_poses,
            frame=frame,  # type: ignore[arg-type]
            depth=queue,
            tf_wait=tf_wait,
            order_wait=order_wait,
            grouping=load_config(GroupingParams, config),
            extra_sinks=sinks,
            record=record,
            on_reset=warn,
            on_choice=say,
        )
        session.scans.limit = max_scans
        for laser in topics.lasers:
            say(f"listening to {laser} on key {session.receiver.keys[laser]}")
        if viewer is not None:
            say(f"Foxglove: open ws://{viewer.host}:{viewer.port}")
        stop = threading.Event()

        def on_signal(signum: int, _frame: Any) -> None:
            if stop.is_set():  # a second Ctrl-C: stop at once
                raise KeyboardInterrupt
            session.scans.close()
            stop.set()

        old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
        timer = threading.Timer(duration, session.scans.finish) if duration else None
        status = threading.Thread(
            target=_status_printer, args=(StatusMeter(session), stop), daemon=True
        )
        try:
            if timer is not None:
                timer.start()
            status.start()
            try:
                stats = session.run.run()
                stop.set()
                status.join(timeout=1.0)
                session.close()
            except LaserPeopleError:  # e.g. --record on a full disk: what ran is still said
                stop.set()
                status.join(timeout=1.0)
                if sum(session.scans.counts.received.values()):
                    _summary(session, session.run.stats, None)
                raise
            _summary(session, stats, record)
            from laserpeople.pipeline.unused_options import detector_options

            _unused_options(session, tracker, detector_options(detector, model, config), background)
        finally:
            stop.set()
            if timer is not None:
                timer.cancel()
            session.close()
            for s, handler in old.items():
                signal.signal(s, handler)


def _unused_options(session: Any, tracker: str, asked: list[str], background: str) -> None:
    """Warn when the leg detector options ``asked`` or ``--background`` had no effect on a
    run without resets (the rules of :mod:`laserpeople.pipeline.unused_options`, as
    ``track``'s; after a reset, the pipelines before it are gone)."""
    pipeline = getattr(session.run, "pipeline", None)
    if pipeline is None or session.scans.counts.resets or not pipeline.stats.frames:
        return
    from laserpeople.pipeline.background import detector_used, static_model_used
    from laserpeople.pipeline.unused_options import (
        unused_background_warning,
        unused_detector_warning,
    )

    for unused in (
        unused_detector_warning(tracker, asked, detector_used(pipeline.stages)),
        unused_background_warning(tracker, background, static_model_used(pipeline.stages)),
    ):
        if unused:
            warn(unused)


def _summary(session: Any, stats: Any, record: Path | None) -> None:
    """The lines printed when a live run ends; an error when no scan arrived at all.

    Raises:
        LaserPeopleError: Not one scan arrived (nothing to show for the run).
    """
    counts = session.scans.counts
    run = session.run
    end = session.scans.now()
    for laser in session.topics.lasers:
        say(
            f"{laser}: {counts.received[laser]} scans received, {counts.dropped[laser]} dropped "
            f"(queue full), {counts.undecodable[laser]} undecodable"
        )
        behind = counts.dropped_warning(laser, stats.median_ms)
        if behind:
            warn(behind)
        quiet = counts.silence(laser, end)
        if quiet is not None:
            warn(
                f"{laser}: no scan in the last {quiet:.1f} s of the run: the laser, its "
                "driver, the robot or the link stopped publishing (the tracks end there)"
            )
        if laser in counts.errors:
            warn(f"{laser}: {counts.errors[laser]}")
    if session.scans.transforms is not None:
        for line in session.scans.transforms.mount_notes:
            say(line)
    if run.frames is not None:
        for line in run.frames.summary():
            say(line)
    if counts.reasons:
        for reason, n in counts.reasons.most_common():
            say(f"{n} scans without a pose: {reason}")
    if counts.tf_timeouts:
        say(
            f"{counts.tf_timeouts} scans waited --tf-wait for a transform in vain and took the "
            "last one held (within the pose tolerance)"
        )
    if counts.resets:
        say(f"{counts.resets} time jumps reset tracking")
    say(
        f"{stats.frames} frames tracked, {stats.published} published: "
        f"{stats.count('person')} person tracks, {stats.count('leg')} leg tracks; tracking "
        f"{stats.median_ms:.2f} ms/scan median"
    )
    if stats.published:
        stamp = stats.latency("stamp")
        said = (
            f"from the scan's stamp: median {stamp:.1f} ms"
            if abs(stamp) < 60_000
            else f"the scans' stamps are {stamp / 1e3:.0f} s off this computer's clock (a "
            "replay, or the robot's clock is not synchronised), so no latency from them"
        )
        say(
            f"latency from arrival to publication: median {stats.latency('arrival'):.1f} ms, "
            f"p99 {stats.latency('arrival', 0.99):.1f} ms; {said}"
        )
        say(session.scans.timings.summary())
    if record is not None:
        say(f"wrote {record}")
    if not sum(counts.received.values()):
        from laserpeople.live.waiting import connected_count, why_no_scan

        raise LaserPeopleError(
            f"no scan arrived on {', '.join(session.topics.lasers)}: nothing was tracked",
            hint=why_no_scan(session.settings.connect, connected_count(session.session)),
        )
