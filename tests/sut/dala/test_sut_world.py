"""The world file and the pymunk world: loading errors, laser ray casts, driving, collisions."""
import math

import pytest

from harness.errors import InputFileError
from harness.sut.simulated.kernel import Environment
from harness.sut.dala.world import World, load_world
from tests.support.sut_driver import WORLD

ARENA = """
[bounds]
x = [0.0, 10.0]
y = [0.0, 10.0]
[rover]
x = 2.0
y = 2.0
heading_deg = 0.0
radius = 0.4
[[rock]]
x = 5.0
y = 2.0
radius = 0.5
"""


def world_of(tmp_path, text=ARENA) -> World:
    path = tmp_path / "world.toml"
    path.write_text(text)
    return World(load_world(path), Environment())


def test_the_dala_world_loads():
    spec = load_world(WORLD)
    assert (spec.x_range, spec.y_range, spec.start, spec.rover_radius) == ((0, 20), (0, 20), (2, 2, 0), 0.4)
    assert len(spec.rocks) == 7 and spec.rocks[0].radius == 0.6


@pytest.mark.parametrize("change,message", [
    (("radius = 0.5", "radius = -1"), "world.toml:13: rock[1].radius = -1; give a positive number"),
    (("x = 5.0", 'x = "far"'), "world.toml:11: rock[1].x = 'far'; give a number"),
    (("x = 5.0", "x = 9.8"), "world.toml:10: rock[1]: (9.8, 2) with radius 0.5 is not inside the bounds "
                             "x=[0.0, 10.0] y=[0.0, 10.0]; move it inside"),
    (("x = 5.0", "x = 2.5"), "world.toml:10: rock #1: rock at (2.5, 2) overlaps the rover's start; move it"),
    (("x = [0.0, 10.0]", "x = [10.0, 0.0]"), "world.toml:2: bounds: x = [10.0, 0.0]; give [low, high] with low < high"),
    (("[rover]", "[robot]"), "world.toml: rover is missing; a world needs a [rover] table"),
    (("heading_deg = 0.0", "heading_deg = true"), "world.toml:8: rover.heading_deg = True; give a number"),
    (("[[rock]]", "[[rock]"), "world.toml: not valid TOML"),
    # an unknown key, NaN, a list for a number
    (("[[rock]]", "[[rock]]\ncolour = 'red'"), "world.toml:11: unknown key 'colour'; a [[rock]] takes x, y, radius"),
    (("radius = 0.5", "radius = nan"), "world.toml:13: rock[1].radius = nan; give a positive number"),
    (("heading_deg = 0.0", "heading_deg = [0.0]"), "world.toml:8: rover.heading_deg = [0.0]; give a number"),
])
def test_a_bad_world_entry_is_named_with_its_value(tmp_path, change, message):
    with pytest.raises(InputFileError) as error:
        world_of(tmp_path, ARENA.replace(*change))
    assert message in str(error.value)


def test_a_missing_world_file_says_so(tmp_path):
    with pytest.raises(InputFileError, match="world file not found; pass an existing world.toml"):
        load_world(tmp_path / "nowhere.toml")


def test_the_laser_sees_the_rock_ahead_and_the_bounds(tmp_path):
    world = world_of(tmp_path)
    hits = world.scan(180, 12, 10)
    assert len(hits) == 19  # in a 10 m arena every ray ends on something within 12 m
    assert hits[0] == (pytest.approx(-math.pi / 2), pytest.approx(2.0))  # the bound y = 0
    assert hits[9] == (0.0, pytest.approx(2.5))  # the rock surface, 3 m ahead minus its radius
    assert hits[18] == (pytest.approx(math.pi / 2), pytest.approx(8.0))  # the bound y = 10
    assert len(world.scan(180, 3, 10)) == 6  # within 3 m: the bound y = 0 from -90 to -50 deg, the rock


def test_still_wheels_cost_nothing_and_move_nothing(tmp_path):
    world = world_of(tmp_path)
    world.env.run(until=5.0)
    world.advance()
    assert world.pose == (2.0, 2.0, 0.0) and world.odometer == 0


def test_driving_moves_the_rover_at_the_commanded_speeds(tmp_path):
    world = world_of(tmp_path, ARENA.replace("y = 2.0\nradius = 0.5", "y = 8.0\nradius = 0.5"))
    world.set_wheels(0.5, 0.0)
    world.env.run(until=2.0)
    world.advance()
    x, y, heading = world.pose
    # pymunk moves a body before solving its joints: the wheels bite one 0.1 s step late
    assert x == pytest.approx(2.95) and y == pytest.approx(2.0) and heading == pytest.approx(0)
    assert world.odometer == pytest.approx(0.95)
    world.set_wheels(0.0, 0.5)
    world.env.run(until=4.0)
    world.advance()
    assert world.pose[2] == pytest.approx(0.95) and world.events == []


def test_a_rock_stops_the_rover_and_the_collision_is_recorded(tmp_path):
    world = world_of(tmp_path)
    world.set_wheels(0.6, 0.0)
    for step in range(1, 101):  # 10 s in rflex periods: the rover would go 6 m
        world.env.run(until=step * 0.1)
        world.advance()
    assert len(world.events) == 1
    t, kind, detail = world.events[0]
    assert kind == "collision" and '"with": "rock 1"' in detail
    assert t == pytest.approx((5.0 - 0.5 - 0.4 - 2.0) / 0.6 + 0.1, abs=0.1)  # 2.1 m at 0.6 m/s, one step late
    assert world.pose[0] == pytest.approx(5.0 - 0.5 - 0.4, abs=0.05)  # against the rock, not through it
