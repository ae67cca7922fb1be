"""The coordinate frame of a live run, decided as the scans arrive (``--frame auto``).

A recording's ``auto`` looks at its first 200 frames before it tracks the first one. A live
run cannot hold frames that long: the first frames would leave seconds late. So ``auto``
decides from the pose lookups as the frames come:

- **World** at the first frame whose (lead) scan has a sensor pose, if it arrives within
  ``within`` seconds of the first scan.
- **Sensor** when none did. Pose lookups then stop, so scans no longer wait for transforms.
- **Nothing is held while undecided.** With one laser, the frames are tracked in the sensor
  frame as they come. Several lasers are fused only in the world frame, so their frames
  without a pose are skipped and counted.
- **Transforms are waited for once.** While undecided, a scan waits for a transform only
  when some transform has come, and at most until ``tf_wait`` after the first scan arrived
  (not ``tf_wait`` each). A robot without tf never waits.
- **One switch at most.** When world is chosen after frames were tracked in the sensor
  frame, :class:`FrameSwitch` ends that pipeline. The run starts a new one (new tracker, new
  track ids) from the frame that decided, and says so.

:class:`FrameDecision` holds the choice for the whole run: it is kept across the pipelines
of a run's time jumps and of the switch.
"""

from __future__ import annotations

from dataclasses import dataclass

from laserpeople.frame import Frame
from laserpeople.pipeline.sources import FrameChoice
from laserpeople.scan import CoordinateFrame

DECIDE_WITHIN = 1.0
"""Seconds after the first scan's arrival within which ``auto`` waits for a sensor pose
(our choice: a robot publishes /tf and odometry at 10 Hz or more)."""


class FrameSwitch(Exception):  # noqa: N818 (a signal to the run, not an error)
    """World was chosen after frames were tracked in the sensor frame: tracking restarts.

    Attributes:
        frame: The frame that decided; the next pipeline starts from it.
    """

    def __init__(self, frame: Frame, message: str) -> None:
        self.frame = frame
        super().__init__(message)


@dataclass
class FrameDecision:
    """The run's coordinate frame and how it was chosen.

    Args:
        requested: ``world``, ``sensor`` or ``auto``.
        within: ``auto``: seconds after the first scan's arrival to wait for a pose [s].

    Attributes:
        frame: The frame chosen (None: not yet).
        started: Arrival of the first scan looked at [s, the scans' clock].
        seconds: When the choice was made, after ``started`` [s].
        index: Index of the frame that decided.
        looked_at: Frames looked at before and including the deciding one.
        sensor_frames: Frames tracked in the sensor frame while undecided.
        skipped: Frames skipped while undecided (several lasers, no pose).
        message: The sentence that names the frame and why (empty until decided).
    """

    requested: FrameChoice = "auto"
    within: float = DECIDE_WITHIN
    frame: CoordinateFrame | None = None
    started: float | None = None
    seconds: float = 0.0
    index: int = -1
    looked_at: int = 0
    sensor_frames: int = 0
    skipped: int = 0
    message: str = ""

    def __post_init__(self) -> None:
        if self.requested != "auto":
            self.frame = self.requested
            self.message = f"working in the {self.requested} frame (as requested)"

    @property
    def undecided(self) -> bool:
        """Whether ``auto`` has not chosen yet."""
        return self.frame is None

    def look(
        self,
        frame: Frame,
        arrival: float,
        *,
        reason: str,
        world: str | None = None,
        posable: bool = True,
    ) -> bool:
        """Look at the next frame while undecided; returns whether it decided.

        Args:
            frame: The frame, its scans' poses looked up.
            arrival: Arrival of its last scan [s, the scans' clock].
            reason: Why its lead scan has no pose (when it has none).
            world: The world frame's name (when known).
            posable: False when no transforms are subscribed (sensor at once).
        """
        if self.started is None:
            self.started = arrival
        self.looked_at += 1
        elapsed = max(0.0, arrival - self.started)
        if frame.scans[0].pose is not None:
            self._decide("world", frame, elapsed)
            name = f" '{world}'" if world else ""
            looked = f"{self.looked_at} frame{'s' if self.looked_at != 1 else ''} looked at"
            text = (
                f"working in the world frame{name}: frame {frame.index} has a sensor pose "
                f"({looked}, {elapsed:.2f} s after the first scan)"
            )
            if self.sensor_frames:
                text += (
                    f"; the {self.sensor_frames} frames before it were tracked in the sensor "
                    "frame; tracking restarts from it (new track ids)"
                )
            elif self.skipped:
                text += f"; the {self.skipped} frames before it had none and were skipped"
            self.message = text
            return True
        if not posable:
            self._decide("sensor", frame, elapsed)
            self.message = "working in the sensor frame: no transforms are subscribed"
            return True
        if elapsed >= self.within:
            self._decide("sensor", frame, elapsed)
            self.message = (
                f"working in the sensor frame: no sensor pose within {self.within:g} s of the "
                f"first scan ({self.looked_at} frames looked at in {elapsed:.2f} s, up to frame "
                f"{frame.index}; {reason}); transforms that come later are not used "
                "(--frame world waits for them)"
            )
            return True
        return False

    def _decide(self, chosen: CoordinateFrame, frame: Frame, elapsed: float) -> None:
        self.frame, self.index, self.seconds = chosen, frame.index, elapsed


__all__ = ["DECIDE_WITHIN", "FrameDecision", "FrameSwitch"]
