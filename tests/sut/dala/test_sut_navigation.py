"""The map poster (CartA) and ndd's steering law, without the simulation around them."""
import math
import random

import pytest

from harness.sut.dala.navigation import CELL_M, CLEARANCE_M, OccupancyMap, steer, wrap


def wall(cart: OccupancyMap, x: float, y0: float, y1: float) -> None:
    """Map a wall x = const from y0 to y1, as seen from the origin facing +x."""
    cart.fuse((0.0, 0.0, 0.0), [(math.atan2(y0 + k * 0.1, x), math.hypot(x, y0 + k * 0.1))
                                for k in range(int((y1 - y0) / 0.1) + 1)])


def test_fused_hits_mark_cells_and_their_clearance():
    cart = OccupancyMap()
    cart.fuse((1.0, 1.0, math.pi / 2), [(0.0, 2.0)])  # facing +y: a hit at (1, 3)
    assert cart.occupied == {(5, 15)}
    assert cart.clearance(1.1, 3.1) == 0.0
    assert cart.clearance(1.1, 3.5) == pytest.approx(0.4)
    assert cart.clearance(1.1, 5.0) > CLEARANCE_M  # far from anything mapped
    cart.clear()
    assert not cart.occupied and cart.clearance(1.1, 3.1) > CLEARANCE_M


def test_cells_on_the_negative_side_are_keyed_apart():
    cart = OccupancyMap()
    cart.fuse((0.0, 0.0, 0.0), [(math.pi, 0.5), (-math.pi / 2, 0.5), (3 * math.pi / 4, 1.0)])
    assert cart.occupied == {(-3, 0), (0, -3), (-4, 3)}


def test_clearances_are_the_distances_to_the_nearest_occupied_cell():
    """Against the definition, after many fuses: a new cell beside an occupied one updates only
    part of its disc (navigation._DISC_BESIDE), which must not change any clearance."""
    rng = random.Random(14)
    cart = OccupancyMap()
    for _ in range(60):
        pose = (rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-math.pi, math.pi))
        cart.fuse(pose, [(rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 2.0)) for _ in range(rng.randint(1, 8))])
    occupied = cart.occupied
    for i in range(-30, 31):
        for j in range(-30, 31):
            nearest = min((math.hypot(i - oi, j - oj) * CELL_M for oi, oj in occupied), default=math.inf)
            expected = nearest if nearest <= CLEARANCE_M else pytest.approx(CLEARANCE_M + 1)
            assert cart.clearance((i + 0.5) * CELL_M, (j + 0.5) * CELL_M) == expected, (i, j)


def test_steer_heads_for_the_goal_when_nothing_is_mapped():
    speed, turn, side = steer((0.0, 0.0, 0.0), (5.0, 0.0), OccupancyMap(), 0.6, 0)
    assert (speed, turn, side) == (0.6, 0.0, 0)


def test_steer_turns_in_place_toward_a_goal_behind():
    speed, turn, _ = steer((0.0, 0.0, 0.0), (-5.0, 0.1), OccupancyMap(), 0.6, 0)
    assert speed == 0.0 and turn == 1.0  # the turn rate is capped


def test_steer_goes_around_a_mapped_obstacle_on_the_side_it_chose():
    cart = OccupancyMap()
    wall(cart, 1.5, -0.5, 0.5)
    speed, turn, side = steer((0.0, 0.0, 0.0), (5.0, 0.0), cart, 0.6, 0)
    assert side == 1 and turn > 0 and speed > 0  # left first, by default
    speed, turn, side = steer((0.0, 0.0, 0.0), (5.0, 0.0), cart, 0.6, -1)
    assert side == -1 and turn < 0  # keeps the side of the last detour


def test_steer_stops_when_every_heading_is_blocked():
    cart = OccupancyMap()
    cart.fuse((0.0, 0.0, 0.0), [(math.radians(a), 0.8) for a in range(0, 360, 5)])  # a ring around
    assert steer((0.0, 0.0, 0.0), (5.0, 0.0), cart, 0.6, 1) == (0.0, 0.0, 1)


def test_a_rover_already_too_close_may_still_move_away():
    cart = OccupancyMap()
    wall(cart, 0.5, -1.0, 1.0)  # 0.5 m ahead, closer than the clearance
    speed, turn, side = steer((0.0, 0.0, 0.0), (-3.0, 0.1), cart, 0.6, 0)
    assert (speed, turn, side) == (0.0, 1.0, 0)  # turns round toward the goal behind, away from the wall
    speed, turn, side = steer((0.0, 0.0, 0.0), (3.0, 0.0), cart, 0.6, 0)
    assert speed == 0.0 and turn == 1.0 and side == 1  # not into the wall: along it, to the left


def test_wrap_keeps_angles_within_a_half_turn():
    assert wrap(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert wrap(-3 * math.pi / 2) == pytest.approx(math.pi / 2)
