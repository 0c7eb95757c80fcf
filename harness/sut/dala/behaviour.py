"""The Dala layer's behaviour (missions/dala/layer.toml names this module): the five Dala
modules, their settings, start phases and activity bodies (codels).

Codels run only while their activity runs. Modules share posters: Robot (pose, by rflex),
SCart (laser scan, by sick), CartA (map, by aspect), Ref (speed reference, by ndd).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from harness.sut.simulated.kernel import Environment
from harness.sut.simulated.module import Activity, Module
from harness.sut.dala.navigation import CLEARANCE_M, OccupancyMap, steer
from harness.sut.dala.world import World, load_world

MOVED_M = 0.001  # odometer change that counts as the rover moving


@dataclass(frozen=True)
class Scan:
    """Poster SCart: laser hits (bearing, distance) and the Robot pose they were taken from."""
    seq: int
    pose: tuple[float, float, float]
    hits: tuple[tuple[float, float], ...]


@dataclass
class Posters:
    """The shared data. Odometry is perfect: Robot is the rover's true pose at rflex's last period."""
    robot: tuple[float, float, float]
    scart: Scan = Scan(0, (0.0, 0.0, 0.0), ())
    cart_a: OccupancyMap = field(default_factory=OccupancyMap)
    ref: tuple[float, float] = (0.0, 0.0)  # linear (m/s), angular (rad/s)


def _json(values) -> list:
    """Numbers for a world event's detail: JSON has no nan or infinity, so those as text."""
    return [v if math.isfinite(v) else repr(v) for v in values]


class DalaModule(Module):
    def __init__(self, env: Environment, world: World, posters: Posters):
        super().__init__(env)
        self.world, self.posters = world, posters


class Rflex(DalaModule):
    """Odometry and wheels: TrackSpeedStart drives the rover from Ref; in mode idle (the default,
    until SetMode velocity) the wheels ignore Ref."""
    name = "rflex"
    start_s = {"TrackSpeedStart": 0.5}  # motor enable
    PERIOD_S = 0.1

    def __init__(self, env, world, posters):
        super().__init__(env, world, posters)
        self.settings = {"mode": "idle"}
        self.bodies["TrackSpeedStart"] = self._track

    def _drive(self, speed: float, turn: float) -> None:
        """Move the rover up to now at the old wheel speeds, then command new ones; publish the pose."""
        self.world.advance()
        self.world.set_wheels(speed, turn)
        self.posters.robot = self.world.pose

    def _track(self, _activity: Activity):
        while True:
            self._drive(*(self.posters.ref if self.settings["mode"] == "velocity" else (0.0, 0.0)))
            yield self.env.timeout(self.PERIOD_S)

    def ended(self, activity: Activity) -> None:
        if activity.service == "TrackSpeedStart" and not self.running("TrackSpeedStart"):
            self._drive(0.0, 0.0)


class Sick(DalaModule):
    """Laser range finder: ray casts into SCart, once (OneShot) or periodically (ContinuousShot)."""
    name = "sick"
    start_s = {"ContinuousShot": 0.5}  # spin-up
    PERIOD_S = 0.25
    RAY_STEP_DEG = 10.0  # sees a 0.6 m rock between two rays up to 6.9 m away

    def __init__(self, env, world, posters):
        super().__init__(env, world, posters)
        self.settings = {"fov": 90.0, "range": 4.0}  # until SetParams says otherwise
        self._last_scan = None  # (pose, fov, range)
        self._blind_since = None  # the setting the laser was last found blind with
        self.bodies.update(ContinuousShot=self._continuous, OneShot=self._one_shot)

    def _scan(self) -> None:
        pose, fov, reach = self.posters.robot, self.settings["fov"], self.settings["range"]
        if (pose, fov, reach) == self._last_scan:
            return  # a still rover in a static world: the last scan stands
        self._last_scan = (pose, fov, reach)
        if not (0.0 < fov <= 360.0 and 0.0 < reach < math.inf):  # also false for nan
            if self._blind_since != (fov, reach):  # once per setting
                self.world.record("laser_sees_nothing", {"fov": repr(fov), "range": repr(reach)})
                self._blind_since = (fov, reach)
            self.posters.scart = Scan(self.posters.scart.seq + 1, pose, ())
            return
        hits = self.world.scan(fov, reach, self.RAY_STEP_DEG)
        self.posters.scart = Scan(self.posters.scart.seq + 1, pose, hits)

    def _continuous(self, _activity: Activity):
        while True:
            self._scan()
            yield self.env.timeout(self.PERIOD_S)

    def _one_shot(self, _activity: Activity):
        self._scan()
        yield self.env.timeout(self.PERIOD_S)
        return "ok"


class Aspect(DalaModule):
    """2-D map: Reset clears CartA; Fuse adds each new SCart, seen from its pose, to CartA."""
    name = "aspect"
    PERIOD_S = 0.2

    def __init__(self, env, world, posters):
        super().__init__(env, world, posters)
        self.bodies.update(Reset=self._reset, Fuse=self._fuse)

    def _reset(self, _activity: Activity):
        yield self.env.timeout(0.1)
        self.posters.cart_a.clear()
        return "ok"

    def _fuse(self, _activity: Activity):
        fused = None
        while True:
            scan = self.posters.scart
            if scan.seq != fused:
                self.posters.cart_a.fuse(scan.pose, scan.hits)
                fused = scan.seq
            yield self.env.timeout(self.PERIOD_S)


class Ndd(DalaModule):
    """Navigation: GotoPosition steers (Ref) to x, y around the obstacles mapped in CartA."""
    name = "ndd"
    start_s = {"GotoPosition": 0.2}
    PERIOD_S = 0.2
    GOAL_TOLERANCE_M = 0.25
    STALL_S, PROGRESS_M = 5.0, 0.05  # no PROGRESS_M closer for STALL_S: goal_unreachable

    def __init__(self, env, world, posters, aspect: Aspect):
        super().__init__(env, world, posters)
        self.aspect = aspect  # only to note, as ground truth, a navigation without a live map
        self.settings = {"speed": 0.3}
        self.bodies["GotoPosition"] = self._goto

    def _goto(self, activity: Activity):
        goal = (activity.args["x"], activity.args["y"])
        if not any(a.phase == "running" for a in self.aspect.running("Fuse")):
            self.world.record("navigation_without_map", {"rqst_id": activity.rqst_id, "goal": _json(goal)})
        if not self.world.inside(*goal):
            self.world.record("goal_outside_world", {"rqst_id": activity.rqst_id, "goal": _json(goal)})
        if not all(map(math.isfinite, goal)):  # nowhere to steer to: the rover stays, then gives up
            yield self.env.timeout(self.STALL_S)
            return "goal_unreachable"
        best, progressed_at, side = math.inf, self.env.now, 0
        cart = self.posters.cart_a
        while True:
            pose = self.posters.robot
            distance = math.dist(pose[:2], goal)
            if distance <= self.GOAL_TOLERANCE_M:
                return "ok"
            if distance < best - self.PROGRESS_M:
                best, progressed_at = distance, self.env.now
            if cart.clearance(*goal) < CLEARANCE_M or self.env.now - progressed_at > self.STALL_S:
                return "goal_unreachable"
            speed = self.settings["speed"]
            if not math.isfinite(speed):  # no speed to steer by: the rover stays
                yield self.env.timeout(self.PERIOD_S)
                continue
            speed, turn, side = steer(pose, goal, cart, speed, side)
            self.posters.ref = (speed, turn)
            yield self.env.timeout(self.PERIOD_S)

    def ended(self, activity: Activity) -> None:
        if activity.service == "GotoPosition":
            self.posters.ref = (0.0, 0.0)


class Antenna(DalaModule):
    """Orbiter link: Point slews the antenna; Communication talks while the rover stands still."""
    name = "antenna"
    start_s = {"Point": 0.2, "Communication": 0.2}
    PERIOD_S = 0.2
    SLEW_DEG_S = 45.0

    def __init__(self, env, world, posters):
        super().__init__(env, world, posters)
        self.settings = {"channel": None}
        self.azimuth = 0.0
        self.pointed_at = None  # odometer reading when the last Point ended ok
        self.bodies.update(Point=self._point, Communication=self._communication)

    def _moved_since(self, odometer: float) -> bool:
        return self.world.odometer - odometer > MOVED_M

    def _point(self, activity: Activity):
        self.pointed_at = None
        if not math.isfinite(activity.args["az"]):  # the antenna slews to nowhere
            self.world.record("antenna_lost", {"rqst_id": activity.rqst_id, "az": repr(activity.args["az"])})
            yield self.env.timeout(self.PERIOD_S)
            return "ok"
        target, start, noted = activity.args["az"] % 360.0, self.world.odometer, False
        stride = self.SLEW_DEG_S * self.PERIOD_S
        while (gap := (target - self.azimuth + 180.0) % 360.0 - 180.0) != 0.0:
            self.azimuth = target if abs(gap) <= stride else (self.azimuth + math.copysign(stride, gap)) % 360.0
            yield self.env.timeout(self.PERIOD_S)
            if not noted and self._moved_since(start):
                noted = True
                self.world.record("drove_with_antenna_deployed", {"rqst_id": activity.rqst_id})
        self.pointed_at = self.world.odometer
        return "ok"

    def _communication(self, activity: Activity):
        if self.pointed_at is None or self._moved_since(self.pointed_at) or self.settings["channel"] is None:
            yield self.env.timeout(self.PERIOD_S)  # the orbiter never answers
            return "link_lost"
        end, start = self.env.now + activity.args["duration"], self.world.odometer
        while (left := end - self.env.now) > 1e-9:
            yield self.env.timeout(min(left, self.PERIOD_S))
            if self._moved_since(start):
                self.world.record("link_broken_while_moving", {"rqst_id": activity.rqst_id})
                return "link_lost"
        return "ok"


def build(env: Environment, world_file: Path) -> tuple[dict[str, DalaModule], list]:
    """The Dala layer's behaviour (missions/dala/layer.toml names this module): the five modules
    on the world of `world_file`, and the list the world records its virtual damage in."""
    world = World(load_world(world_file), env)
    posters = Posters(robot=world.pose)
    aspect = Aspect(env, world, posters)
    modules = (Rflex(env, world, posters), Sick(env, world, posters), aspect,
               Ndd(env, world, posters, aspect), Antenna(env, world, posters))
    return {m.name: m for m in modules}, world.events
