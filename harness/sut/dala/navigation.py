"""The map (poster CartA, built by aspect) and the steering law of ndd.

The map is a sparse occupancy grid: a laser hit marks its cell occupied, and every cell within
CLEARANCE_M of an occupied cell keeps its distance to the nearest one. Steering needs only
those distances, so each new obstacle cell costs a fixed disc of updates once, and choosing a
heading costs a few dictionary look-ups per candidate.
"""
from __future__ import annotations

import math

CELL_M = 0.2
CLEARANCE_M = 0.7  # rover radius plus a margin: how far ndd keeps the rover centre from obstacles
LOOKAHEAD_M = 1.6
CANDIDATE_STEP = math.radians(10)
MAX_DEVIATION = math.radians(150)
TURN_GAIN, MAX_TURN = 2.0, 1.0  # rad/s per rad of heading error, rad/s
TURN_IN_PLACE = math.radians(60)  # beyond this heading error the rover turns without advancing

_FAR = CLEARANCE_M + 1  # the clearance of a cell no mapped obstacle is near
_REACH = math.ceil(CLEARANCE_M / CELL_M)
# Cells are keyed by i * _STRIDE + j rather than (i, j): an int key is cheaper than a tuple, all the
# more while it fits in one 30-bit digit of a Python int (|x| < 200 m). Unique while |j| < _STRIDE / 2,
# i.e. within 100 km of the origin.
_STRIDE = 1 << 20


def _distance(di: int, dj: int) -> float:
    return math.hypot(di, dj) * CELL_M


def _disc(beside: tuple[int, int] | None = None) -> tuple[tuple[int, float], ...]:
    """(key offset, distance) of the cells within CLEARANCE_M of a cell; `beside` (di, dj): only
    those nearer to it than to its occupied neighbour at (di, dj), the only ones it can update."""
    return tuple((di * _STRIDE + dj, _distance(di, dj))
                 for di in range(-_REACH, _REACH + 1) for dj in range(-_REACH, _REACH + 1)
                 if _distance(di, dj) <= CLEARANCE_M
                 and (beside is None or _distance(di, dj) < _distance(di - beside[0], dj - beside[1])))


_DISC = _disc()
# A new obstacle cell next to an occupied one needs only the 21 or 22 cells of its disc nearer to
# it than to that neighbour (of 37): the others already keep a distance at most as large.
_DISC_BESIDE = tuple((di * _STRIDE + dj, _disc((di, dj))) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj)


def _key(x: float, y: float) -> int:
    """The key of the cell holding (x, y)."""
    return math.floor(x / CELL_M) * _STRIDE + math.floor(y / CELL_M)


def wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


class OccupancyMap:
    """Poster CartA."""

    def __init__(self) -> None:
        self._occupied: set[int] = set()  # cell keys, as _nearness's
        self._nearness: dict[int, float] = {}  # cell key -> distance to the nearest occupied cell

    @property
    def occupied(self) -> set[tuple[int, int]]:
        """The occupied cells (i, j)."""
        return {((key + _STRIDE // 2) // _STRIDE, (key + _STRIDE // 2) % _STRIDE - _STRIDE // 2)
                for key in self._occupied}

    def clear(self) -> None:
        self._occupied.clear()
        self._nearness.clear()

    def fuse(self, pose: tuple[float, float, float], hits) -> None:
        """Mark the cells of laser hits (bearing, distance) seen from `pose`."""
        x, y, heading = pose
        occupied, nearness, cos, sin, floor = self._occupied, self._nearness, math.cos, math.sin, math.floor
        get = nearness.get
        for bearing, distance in hits:
            angle = heading + bearing
            centre = (floor((x + distance * cos(angle)) / CELL_M) * _STRIDE  # _key inlined
                      + floor((y + distance * sin(angle)) / CELL_M))
            if centre in occupied:
                continue  # most hits fall on walls and rocks already mapped
            occupied.add(centre)
            disc = _DISC
            for neighbour, nearer in _DISC_BESIDE:
                if centre + neighbour in occupied:
                    disc = nearer
                    break
            for offset, d in disc:
                if d < get(centre + offset, _FAR):
                    nearness[centre + offset] = d

    def clearance(self, x: float, y: float) -> float:
        """Distance from (x, y) to the nearest mapped obstacle, capped just above CLEARANCE_M."""
        return self._nearness.get(_key(x, y), _FAR)

    def path_is_clear(self, x: float, y: float, heading: float, reach: float, floor: float) -> bool:
        """Whether every cell-spaced point up to `reach` along `heading` keeps `floor` clearance."""
        nearness, down = self._nearness, math.floor
        dx, dy = CELL_M * math.cos(heading), CELL_M * math.sin(heading)
        for n in range(1, int(reach / CELL_M) + 1):  # _key inlined: the map's most frequent look-up
            if nearness.get(down((x + n * dx) / CELL_M) * _STRIDE + down((y + n * dy) / CELL_M), _FAR) < floor:
                return False
        return True

    def __repr__(self) -> str:
        return f"<OccupancyMap {len(self._occupied)} occupied cells>"


def steer(pose, goal, cart: OccupancyMap, speed: float, side: int) -> tuple[float, float, int]:
    """(linear speed, turn rate, side) toward `goal` around mapped obstacles.

    Candidate headings fan out from the goal bearing; the first whose look-ahead segment keeps
    CLEARANCE_M (or, for a rover already closer than that, does not get any closer) wins. `side`
    (+1 left, -1 right, 0 none) is the side of the last detour: trying it first stops the rover
    from dithering in front of an obstacle. With no clear heading the rover stops.
    """
    x, y, heading = pose
    distance = math.hypot(goal[0] - x, goal[1] - y)
    bearing = math.atan2(goal[1] - y, goal[0] - x)
    reach = min(LOOKAHEAD_M, distance)
    floor = min(CLEARANCE_M, cart.clearance(x, y))
    first = side or 1
    k = 0
    while k * CANDIDATE_STEP <= MAX_DEVIATION:
        for sign in ((0,) if k == 0 else (first, -first)):
            candidate = bearing + sign * k * CANDIDATE_STEP
            if cart.path_is_clear(x, y, candidate, reach, floor):
                error = wrap(candidate - heading)
                turn = max(-MAX_TURN, min(MAX_TURN, TURN_GAIN * error))
                linear = 0.0 if abs(error) > TURN_IN_PLACE else speed * math.cos(error)
                return linear, turn, sign
        k += 1
    return 0.0, 0.0, side
