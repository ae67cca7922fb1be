"""004's six experiment families (Schenk et al., Sec. 3.1, Fig. 2).

Setup (004 Sec. 3.1): a 5.5 x 11 m room; four SICK LMS151 (270 deg, 0.5 deg, 50 Hz), two
at feet height (0.2 m) and two at upper-body height (1.1 m) at the same spots, 2 m to
the left and right of the centre of the trajectory. Here the room spans x in [0, 11],
y in [0, 5.5]; trajectory (a) runs along y = 2.75 and the scanners stand at (5.5, 0.75)
looking +y (``feet_a``, ``torso_a``) and at (5.5, 4.75) looking -y (``feet_b``,
``torso_b``). The exact shapes of Fig. 2's curves are not given in the text; the ones
here follow the figure's description (curve, circle, evading, corner, join, cross).
"""

from __future__ import annotations

import math

import numpy as np

from laserpeople.scan import Pose2D
from laserpeople.sim.groups import walk_in_formation
from laserpeople.sim.motion import Route
from laserpeople.sim.people import PersonSpec, random_person
from laserpeople.sim.scenarios import register
from laserpeople.sim.sensors import SensorSpec
from laserpeople.sim.simulator import Scene
from laserpeople.sim.world import World, room

ROOM = (0.0, 0.0, 11.0, 5.5)
LINE_Y = 2.75
START_X, END_X = 0.4, 10.6
FEET_HEIGHT = 0.2  # 004 Sec. 3.1
TORSO_HEIGHT = 1.1  # 004 Sec. 3.1
SPEEDS = {"slow": 0.6, "normal": 1.3, "fast": 2.6}
"""Walking speeds [m/s] of Exp. 1 (004 gives no numbers; "fast" is running, Sec. 3.3)."""


def schenk_world() -> World:
    """The 5.5 x 11 m room with doors at both short ends (on trajectory (a))."""
    return World(room(*ROOM, doors=(("west", LINE_Y, 1.2), ("east", LINE_Y, 1.2))))


def schenk_sensors() -> list[SensorSpec]:
    """Two LMS151 at feet height and two at upper-body height on opposite sides."""
    a = Pose2D(5.5, LINE_Y - 2.0, math.pi / 2)
    b = Pose2D(5.5, LINE_Y + 2.0, -math.pi / 2)
    return [
        SensorSpec("feet_a", "sick-lms151", FEET_HEIGHT, a, phase=0.0),
        SensorSpec("feet_b", "sick-lms151", FEET_HEIGHT, b, phase=0.004),
        SensorSpec("torso_a", "sick-lms151", TORSO_HEIGHT, a, phase=0.008),
        SensorSpec("torso_b", "sick-lms151", TORSO_HEIGHT, b, phase=0.012),
    ]


def _scene(people: list[PersonSpec], **notes: object) -> Scene:
    return Scene(schenk_world(), people, schenk_sensors(), notes=dict(notes))


def _speed(rng: np.random.Generator, nominal: float) -> float:
    return float(nominal * rng.uniform(0.9, 1.1))


def _line(rng: np.random.Generator, speed: float, y: float = LINE_Y, start: float = 0.0) -> Route:
    return Route(START_X, y, 0.0, start=start).walk_to(END_X, y, speed)


def _one(rng: np.random.Generator, route: Route, accessory: str | None = None) -> list[PersonSpec]:
    return [random_person(rng, 0, route, leave_at_end=True, accessory=accessory)]


for _name, _v in SPEEDS.items():

    def _build(rng: np.random.Generator, duration: float, v: float = _v) -> Scene:
        return _scene(_one(rng, _line(rng, _speed(rng, v))))

    register(
        f"speed-{_name}",
        f"one person {'running' if _name == 'fast' else 'walking ' + _name} (~{_v} m/s) "
        "along the straight line (a)",
        "004 Exp. 1",
        round(10.2 / _v + 1.0, 1),
    )(_build)


@register("curve", "one person walking a curve (Fig. 2b)", "004 Exp. 2", 10.0)
def _curve(rng: np.random.Generator, duration: float) -> Scene:
    x = np.linspace(START_X, END_X, 30)
    y = LINE_Y - 1.0 + 1.6 * np.sin(math.pi * (x - START_X) / (END_X - START_X))
    route = Route(float(x[0]), float(y[0]), 0.0).walk_path(
        np.column_stack([x, y])[1:], _speed(rng, 1.2)
    )
    return _scene(_one(rng, route))


@register("circle", "one person walking once round a 1.5 m circle (Fig. 2c)", "004 Exp. 2", 16.0)
def _circle(rng: np.random.Generator, duration: float) -> Scene:
    v = _speed(rng, 1.1)
    route = Route(START_X, LINE_Y, 0.0).walk_to(5.5, LINE_Y, v)
    # diameter 1.5 m: a radius of 1.5 m ran through the wall at y = 5.5 and the laser stand
    # at (5.5, 4.75); this circle stays 0.5 m clear of the stand
    route.arc(5.5, LINE_Y + 0.75, 2 * math.pi, v).walk_to(END_X, LINE_Y, v)
    return _scene(_one(rng, route))


@register("evading", "one person stepping aside round an obstacle (Fig. 2g)", "004 Exp. 2", 10.0)
def _evading(rng: np.random.Generator, duration: float) -> Scene:
    pts = np.array(
        [[4.0, LINE_Y], [4.8, LINE_Y + 0.9], [6.2, LINE_Y + 0.9], [7.0, LINE_Y], [END_X, LINE_Y]]
    )
    route = Route(START_X, LINE_Y, 0.0).walk_path(pts, _speed(rng, 1.2))
    return _scene(_one(rng, route))


@register("corner", "one person turning a 90 degree corner (Fig. 2d)", "004 Exp. 3", 10.0)
def _corner(rng: np.random.Generator, duration: float) -> Scene:
    route = Route(START_X, LINE_Y - 0.75, 0.0).walk_to(8.0, LINE_Y - 0.75, _speed(rng, 1.2))
    route.walk_to(8.0, 5.2, _speed(rng, 1.2))
    return _scene(_one(rng, route))


@register("stop", "one person stopping 3 s halfway along line (a)", "004 Exp. 3", 12.0)
def _stop(rng: np.random.Generator, duration: float) -> Scene:
    v = _speed(rng, 1.2)
    route = Route(START_X, LINE_Y, 0.0).walk_to(5.0, LINE_Y, v).wait(3.0).walk_to(END_X, LINE_Y, v)
    return _scene(_one(rng, route))


@register(
    "turn", "one person stopping, turning round to look behind, and walking on", "004 Exp. 3", 14.0
)
def _turn(rng: np.random.Generator, duration: float) -> Scene:
    v = _speed(rng, 1.2)
    route = Route(START_X, LINE_Y, 0.0).walk_to(5.0, LINE_Y, v).wait(0.5)
    route.turn_by(math.pi, 1.5).wait(1.0).turn_by(-math.pi, 1.5).walk_to(END_X, LINE_Y, v)
    return _scene(_one(rng, route))


def _people_on_lines(rng: np.random.Generator, n: int) -> list[PersonSpec]:
    """n people on parallel lines (a), 0.9 m apart, starting within 1.5 s of each other;
    five people walk as two rows (Fig. 2i)."""
    people = []
    lanes = min(n, 3)
    for i in range(n):
        lane, row = i % lanes, i // lanes
        y = LINE_Y + (lane - (lanes - 1) / 2) * 0.9
        start = row * 1.6 + float(rng.uniform(0.0, 0.6))
        route = _line(rng, _speed(rng, 1.2), y=y, start=start)
        people.append(random_person(rng, i, route, leave_at_end=True))
    return people


for _n in (1, 2, 3, 5):

    def _build_n(rng: np.random.Generator, duration: float, n: int = _n) -> Scene:
        return _scene(_people_on_lines(rng, n))

    register(
        f"people-{_n}",
        f"{_n} {'person' if _n == 1 else 'people'} walking along parallel lines (a)",
        "004 Exp. 4",
        12.0,
    )(_build_n)


LANES = (0.0, -0.9, 0.9)
"""Lane offsets [m] of the 1st, 2nd and 3rd person on the multi-person trajectories (b)
and (d) of Exp. 4 (the figure draws them as parallel lines ~1 m apart)."""


def _curve_route(rng: np.random.Generator, offset: float, start: float) -> Route:
    x = np.linspace(START_X, END_X, 30)
    y = LINE_Y - 1.0 + offset + 1.6 * np.sin(math.pi * (x - START_X) / (END_X - START_X))
    return Route(float(x[0]), float(y[0]), 0.0, start=start).walk_path(
        np.column_stack([x, y])[1:], _speed(rng, 1.2)
    )


def _corner_route(rng: np.random.Generator, offset: float, start: float) -> Route:
    y0, x_turn = LINE_Y - 0.75 + offset, 8.0 - offset
    route = Route(START_X, y0, 0.0, start=start).walk_to(x_turn, y0, _speed(rng, 1.2))
    return route.walk_to(x_turn, 5.2, _speed(rng, 1.2))


for _n in (2, 3):
    for _shape, _make in (("curve", _curve_route), ("corner", _corner_route)):

        def _build_multi(
            rng: np.random.Generator, duration: float, n: int = _n, make: object = _make
        ) -> Scene:
            people = []
            for i in range(n):
                route = make(rng, LANES[i], float(rng.uniform(0.0, 0.6)))  # type: ignore[operator]
                people.append(random_person(rng, i, route, leave_at_end=True))
            return _scene(people)

        register(
            f"people-{_n}-{_shape}",
            f"{_n} people walking side by side along the {_shape} "
            f"(Fig. 2{'b' if _shape == 'curve' else 'd'})",
            "004 Exp. 4",
            12.0,
        )(_build_multi)


def schenk_sensors_one_side() -> list[SensorSpec]:
    """Setup (h) of Fig. 2: both laser stands on the same side of the trajectory, 2 m
    apart and 2 m from the line, looking across it."""
    a = Pose2D(4.5, LINE_Y - 2.0, math.pi / 2)
    b = Pose2D(6.5, LINE_Y - 2.0, math.pi / 2)
    return [
        SensorSpec("feet_a", "sick-lms151", FEET_HEIGHT, a, phase=0.0),
        SensorSpec("feet_b", "sick-lms151", FEET_HEIGHT, b, phase=0.004),
        SensorSpec("torso_a", "sick-lms151", TORSO_HEIGHT, a, phase=0.008),
        SensorSpec("torso_b", "sick-lms151", TORSO_HEIGHT, b, phase=0.012),
    ]


@register(
    "one-side",
    "one person walking line (a) with all lasers on one side (Fig. 2h, alternative setup)",
    "004 Sec. 3.1",
    10.0,
)
def _one_side(rng: np.random.Generator, duration: float) -> Scene:
    people = _one(rng, _line(rng, _speed(rng, 1.2)))
    return Scene(schenk_world(), people, schenk_sensors_one_side(), notes={"setup": "h"})


@register("join", "two people drawing near (0.6 m) without crossing (Fig. 2e)", "004 Exp. 5", 11.0)
def _join(rng: np.random.Generator, duration: float) -> Scene:
    v = _speed(rng, 1.2)
    people = []
    for i, side in enumerate((-1.0, 1.0)):
        y_far, y_near = LINE_Y + side * 1.6, LINE_Y + side * 0.3
        pts = np.array([[3.5, y_near], [7.5, y_near], [END_X, y_far]])
        route = Route(START_X, y_far, 0.0).walk_path(pts, v)
        people.append(random_person(rng, i, route, leave_at_end=True))
    return _scene(people)


@register("cross", "two people crossing diagonally (Fig. 2f)", "004 Exp. 5", 11.0)
def _cross(rng: np.random.Generator, duration: float) -> Scene:
    v = _speed(rng, 1.2)
    people = []
    for i, side in enumerate((-1.0, 1.0)):
        # 0.7 s apart so that they pass each other instead of colliding
        route = Route(START_X, LINE_Y + side * 1.8, 0.0, start=0.7 * i)
        route.walk_to(END_X, LINE_Y - side * 1.8, v)
        people.append(random_person(rng, i, route, leave_at_end=True))
    return _scene(people)


ACCESSORY_KINDS = (
    "suitcase-carried",
    "suitcase-pulled",
    "baggage-cart",
    "cane",
    "long-skirt",
    "carried-item",
    "shoulder-bag",
)

for _kind in ACCESSORY_KINDS:

    def _build_acc(rng: np.random.Generator, duration: float, kind: str = _kind) -> Scene:
        return _scene(_one(rng, _line(rng, _speed(rng, 1.1)), accessory=kind))

    register(
        _kind,
        f"one person with a {_kind.replace('-', ' ')} walking line (a)",
        "004 Exp. 6",
        10.5,
    )(_build_acc)


@register(
    "accessories",
    "five people one after another, each with another accessory, on line (a)",
    "004 Exp. 6",
    18.0,
)
def _accessories(rng: np.random.Generator, duration: float) -> Scene:
    kinds = ("suitcase-carried", "suitcase-pulled", "baggage-cart", "cane", "long-skirt")
    people = [
        random_person(
            rng, i, _line(rng, _speed(rng, 1.1), start=2.0 * i), leave_at_end=True, accessory=k
        )
        for i, k in enumerate(kinds)
    ]
    return _scene(people)


@register(
    "group-walk",
    "a group of three walking side by side along line (a), turning at the end",
    "000 Sec. 4.2 (Hall's personal space)",
    14.0,
)
def _group_walk(rng: np.random.Generator, duration: float) -> Scene:
    routes = [Route(START_X, LINE_Y + 0.75 * (i - 1), 0.0) for i in range(3)]
    path = np.array([[START_X + 0.5, LINE_Y], [7.5, LINE_Y], [7.5, 4.6]])
    walk_in_formation(routes, path, _speed(rng, 1.0))
    people = [random_person(rng, i, r, groups=((-math.inf, 0),)) for i, r in enumerate(routes)]
    return _scene(people)
