"""The physical world of the simulated rover: a pymunk space with bounds, rocks and the rover body.

The world is described in a TOML file (missions/dala/world.toml):

    [bounds]                      # the arena, metres
    x = [0.0, 20.0]
    y = [0.0, 20.0]
    [rover]                       # start pose and body size
    x = 2.0
    y = 2.0
    heading_deg = 0.0
    radius = 0.4
    [[rock]]                      # any number of round rocks
    x = 5.5
    y = 3.0
    radius = 0.6

Physics advances lazily: only the wheel-driving codel calls `advance`, and a rover whose
wheels are still costs no pymunk step. Collisions of the rover with a rock or the bounds are
recorded as world events (virtual damage, never seen by the oracles).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import pymunk
from pymunk import cp

from pydantic import ConfigDict, Field, model_validator

from harness.errors import InputFileError
from harness.files import decode, parse_toml, read_bytes
from harness.schema import Strict, dotted, validated, where
from harness.sut.simulated.kernel import Environment
from harness.sut.dala.laser import Laser, wall

MAX_STEP_S = 0.1  # longest single physics step; longer advances are split
TRACTION_N = 3000.0  # force (N) and torque (N m) the wheels can exert on the 100 kg rover
ROVER, ROCK, BOUND = 1, 2, 3  # pymunk collision types


@dataclass(frozen=True)
class Rock:
    x: float
    y: float
    radius: float


@dataclass(frozen=True)
class WorldSpec:
    path: str
    x_range: tuple[float, float]
    y_range: tuple[float, float]
    start: tuple[float, float, float]  # x, y, heading (rad)
    rover_radius: float
    rocks: tuple[Rock, ...]


class BoundsTable(Strict):
    model_config = ConfigDict(title="[bounds]")
    x: list[float] = Field(min_length=2, max_length=2, description="give [low, high] with low < high (metres)")
    y: list[float] = Field(min_length=2, max_length=2, description="give [low, high] with low < high (metres)")

    @model_validator(mode="after")
    def _ordered(self):
        for key in ("x", "y"):
            low, high = getattr(self, key)
            if not low < high:
                raise ValueError(f"{key} = [{low!r}, {high!r}]; give [low, high] with low < high")
        return self


class RoverTable(Strict):
    model_config = ConfigDict(title="[rover]")
    x: float = Field(description="give a number (metres)")
    y: float = Field(description="give a number (metres)")
    heading_deg: float = Field(description="give a number (degrees)")
    radius: float = Field(gt=0, description="give a positive number (metres)")


class RockTable(Strict):
    model_config = ConfigDict(title="a [[rock]]")
    x: float = Field(description="give a number (metres)")
    y: float = Field(description="give a number (metres)")
    radius: float = Field(gt=0, description="give a positive number (metres)")


class WorldFile(Strict):
    model_config = ConfigDict(title="a world")
    doc: str = ""
    bounds: BoundsTable = Field(description="a world needs a [bounds] table (x, y)")
    rover: RoverTable = Field(description="a world needs a [rover] table (x, y, heading_deg, radius)")
    rock: list[RockTable] = Field([], description="write each rock as a [[rock]] table")


def _inside(path, text, keys, x, y, margin, x_range, y_range) -> None:
    if not (x_range[0] + margin <= x <= x_range[1] - margin and y_range[0] + margin <= y <= y_range[1] - margin):
        raise InputFileError(path, where(text, keys), f"{dotted(keys)}: ({x:g}, {y:g}) with radius {margin:g} is "
                             f"not inside the bounds x={list(x_range)} y={list(y_range)}; move it inside")


def load_world(path: str | Path) -> WorldSpec:
    """The world described in `path`; contents read before are not parsed again (every run loads them)."""
    path = Path(path)
    return _parse_world(path, read_bytes(path, "world file not found; pass an existing world.toml"))


@lru_cache(maxsize=8)
def _parse_world(path: Path, content: bytes) -> WorldSpec:
    text = decode(path, content)
    spec = validated(WorldFile, parse_toml(path, text), path, text)
    x_range, y_range = tuple(spec.bounds.x), tuple(spec.bounds.y)
    rover = spec.rover
    _inside(path, text, ("rover",), rover.x, rover.y, rover.radius, x_range, y_range)
    for n, rock in enumerate(spec.rock):
        _inside(path, text, ("rock", n), rock.x, rock.y, rock.radius, x_range, y_range)
        if math.dist((rock.x, rock.y), (rover.x, rover.y)) < rock.radius + rover.radius:
            raise InputFileError(path, where(text, ("rock", n)), f"rock #{n + 1}: rock at ({rock.x:g}, {rock.y:g}) "
                                 "overlaps the rover's start; move it")
    rocks = tuple(Rock(r.x, r.y, r.radius) for r in spec.rock)
    start = (rover.x, rover.y, math.radians(rover.heading_deg))
    return WorldSpec(str(path), x_range, y_range, start, rover.radius, rocks)


class World:
    """The pymunk space; `events` collects (t, kind, detail JSON) of virtual damage."""

    def __init__(self, spec: WorldSpec, env: Environment):
        self.spec, self.env = spec, env
        self.space = pymunk.Space()
        self.events: list[tuple[float, str, str]] = []
        self.time = 0.0
        self.odometer = 0.0  # metres travelled, for whoever must notice motion
        self.wheels = (0.0, 0.0)  # commanded linear (m/s) and angular (rad/s) speed
        self._add_static_shapes()
        x, y, heading = spec.start
        mass = 100.0
        self.rover = pymunk.Body(mass, pymunk.moment_for_circle(mass, 0.0, spec.rover_radius))
        self.rover.position, self.rover.angle = (x, y), heading
        self.pose = spec.start  # the rover moves only in `advance`, which keeps this up to date
        shape = pymunk.Circle(self.rover, spec.rover_radius)
        shape.collision_type, shape.friction = ROVER, 0.9
        # The wheels: a kinematic body the rover follows through force-limited joints (the
        # pymunk top-down "tank" idiom), so that a rock stops the rover instead of letting
        # commanded speeds push it through.
        self.wheelbase = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.wheelbase.position = self.rover.position
        traction = pymunk.PivotJoint(self.wheelbase, self.rover, (0, 0), (0, 0))
        traction.max_bias, traction.max_force = 0.0, TRACTION_N
        steering = pymunk.GearJoint(self.wheelbase, self.rover, 0.0, 1.0)
        steering.max_bias, steering.max_force = 0.0, TRACTION_N
        self.space.add(self.rover, shape, self.wheelbase, traction, steering)
        self.space.on_collision(ROVER, ROCK, begin=self._collided)
        self.space.on_collision(ROVER, BOUND, begin=self._collided)

    def _add_static_shapes(self) -> None:
        """The walls and rocks, in pymunk for collisions and in the laser for scans."""
        (x0, x1), (y0, y1) = self.spec.x_range, self.spec.y_range
        corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        walls = list(zip(corners, corners[1:] + corners[:1]))
        for n, (a, b) in enumerate(walls):
            segment = pymunk.Segment(self.space.static_body, a, b, 0.0)
            segment.collision_type, segment.friction, segment.label = BOUND, 0.9, f"bound {n + 1}"
            self.space.add(segment)
        for n, rock in enumerate(self.spec.rocks, 1):
            shape = pymunk.Circle(self.space.static_body, rock.radius, (rock.x, rock.y))
            shape.collision_type, shape.friction, shape.label = ROCK, 0.9, f"rock {n}"
            self.space.add(shape)
        self.laser = Laser([wall(a, b) for a, b in walls], [(r.x, r.y, r.radius) for r in self.spec.rocks])

    def _collided(self, arbiter: pymunk.Arbiter, _space, _data) -> None:
        obstacle = next(s for s in arbiter.shapes if s.collision_type != ROVER)
        x, y, _ = self.pose
        self.record("collision", {"with": obstacle.label, "x": round(x, 3), "y": round(y, 3),
                                  "speed": round(abs(self.wheels[0]), 3)})

    def record(self, kind: str, detail: dict) -> None:
        self.events.append((self.env.now, kind, json.dumps(detail)))

    def inside(self, x: float, y: float) -> bool:
        """Whether (x, y) lies within the arena's bounds (false for nan)."""
        (x0, x1), (y0, y1) = self.spec.x_range, self.spec.y_range
        return x0 <= x <= x1 and y0 <= y <= y1

    @property
    def still(self) -> bool:
        return self.wheels == (0.0, 0.0)

    def advance(self) -> None:
        """Move the rover from the last advance to now at the commanded wheel speeds."""
        remaining, self.time = self.env.now - self.time, self.env.now
        if self.still or remaining <= 1e-12:
            return
        speed, turn = self.wheels
        # The chipmunk calls that pymunk's properties and Space.step make, without their Python
        # wrapping (a third of this method's time): the same C calls with the same doubles.
        # Space.step adds only a check of the bodies' masses (fixed in __init__) and the handling
        # of shapes added or removed by collision callbacks (_collided only records).
        wheelbase, rover, space = self.wheelbase._body, self.rover._body, self.space._space
        cp.cpBodySetAngularVelocity(wheelbase, turn)  # the solver never changes a kinematic body's speeds
        while remaining > 1e-12:
            dt = min(remaining, MAX_STEP_S)
            x, y, heading = self.pose
            cp.cpBodySetVelocity(wheelbase, (speed * math.cos(heading), speed * math.sin(heading)))
            cp.cpSpaceStep(space, dt)
            position, heading = cp.cpBodyGetPosition(rover), cp.cpBodyGetAngle(rover)
            x1, y1 = position.x, position.y
            self.odometer += math.hypot(x1 - x, y1 - y)
            self.pose = (x1, y1, heading)
            remaining -= dt

    def set_wheels(self, speed: float, turn: float) -> None:
        stopping = not self.still and (speed, turn) == (0.0, 0.0)
        self.wheels = (speed, turn)
        if stopping:  # a still rover is never stepped, so its speeds stay zero until it moves again
            self.rover.velocity, self.rover.angular_velocity = (0.0, 0.0), 0.0

    def scan(self, fov_deg: float, range_m: float, step_deg: float) -> tuple[tuple[float, float], ...]:
        """Laser rays from the rover: (bearing relative to the heading, distance) of each hit."""
        return self.laser.scan(*self.pose, fov_deg, range_m, step_deg)

    def __repr__(self) -> str:
        x, y, heading = self.pose
        return (f"<World {Path(self.spec.path).name} t={self.time:.3f} rover=({x:.2f}, {y:.2f}, "
                f"{math.degrees(heading):.0f}deg) rocks={len(self.spec.rocks)} events={len(self.events)}>")
