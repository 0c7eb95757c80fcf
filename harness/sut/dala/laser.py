"""Laser rays against the world's static shapes (the bounds' walls and round rocks), computed here.

A pymunk ray query costs several µs of Python wrapping per ray; the world's shapes are 4 segments and a few
circles, so the nearest hit is cheaper computed directly. The arithmetic is chipmunk's own
(Munk2D `CircleSegmentQuery`, `cpSegmentShapeSegmentQuery`, `cpSpaceSegmentQueryFirst`), operation
for operation in IEEE doubles, so every hit equals pymunk's to the last bit: the traces, which
depend on where the rover steers, stay the same (tests/sut/dala/test_sut_laser.py compares them).

Only shapes that the scan's range can reach are tested, each only by the rays that point at it: a
shape is left out only when it is out of range by more than REACH_MARGIN_M, or off the ray's
direction by more than ANGLE_MARGIN, both far beyond any rounding. The bounds'
walls are not point-queried first as chipmunk does: a rover never stands exactly on one.
"""
from __future__ import annotations

import math

REACH_MARGIN_M = 1e-6
ANGLE_MARGIN = 1e-6  # radians
TAU = 2 * math.pi
_TINY = 2.2250738585072014e-308  # CPFLOAT_MIN (DBL_MIN): chipmunk's guard in cpvnormalize


def wall(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, ...]:
    """A zero-thickness segment as chipmunk caches it: ends and unit normal (cpSegmentShapeInit);
    then its bounding box (left, bottom, right, top)."""
    vx, vy = b[0] - a[0], b[1] - a[1]
    scale = 1.0 / (math.sqrt(vx * vx + vy * vy) + _TINY)
    vx, vy = vx * scale, vy * scale
    return a[0], a[1], b[0], b[1], vy, -vx, min(a[0], b[0]), min(a[1], b[1]), max(a[0], b[0]), max(a[1], b[1])


def _spread(by_ray: list, item, low: float, width: float, step: float) -> None:
    """Give `item` to the rays (`step` apart) whose angle from the first ray is within
    [low, low + width] modulo 2 pi (0 <= low < 2 pi), widened by ANGLE_MARGIN on each side.
    A ray's list is made at its first item (None until then): most rays get none."""
    last = len(by_ray) - 1
    span = last * step
    # The interval's turn before it or after it can reach the field of view only when it wraps past
    # 2 pi or the field of view is nearly a full turn: tested first, they are rarely looked at.
    turns = (low,)
    if (low - TAU) + width + ANGLE_MARGIN >= 0.0 or (low + TAU) - ANGLE_MARGIN <= span:
        turns = (low - TAU, low, low + TAU)
    for start in turns:
        start, end = start - ANGLE_MARGIN, start + width + ANGLE_MARGIN
        if end < 0.0 or start > span:
            continue  # this turn of the interval lies outside the field of view
        for n in range(0 if start <= 0.0 else math.ceil(start / step),
                       last + 1 if end >= span else math.floor(end / step) + 1):
            listed = by_ray[n]
            if listed is None:
                by_ray[n] = [item]
            else:
                listed.append(item)


class Laser:
    """Rays from a point against fixed walls (made by `wall`) and circles (x, y, radius)."""

    def __init__(self, walls: list[tuple[float, ...]], circles: list[tuple[float, float, float]]):
        self.walls, self.circles = walls, circles

    def _walls_by_ray(self, x: float, y: float, reach: float, step: float, first_angle: float, by_ray) -> None:
        """Give each ray the reachable walls between whose ends it points, with what
        cpSegmentShapeSegmentQuery computes before it looks at the ray: the ends relative to (x, y)
        (moved by a thickness of 0), the normal, the offset."""
        for ax, ay, bx, by, nx, ny, left, bottom, right, top in self.walls:
            off_x = left - x if x < left else x - right if x > right else 0.0
            off_y = bottom - y if y < bottom else y - top if y > top else 0.0
            if off_x * off_x + off_y * off_y > reach * reach:
                continue  # its bounding box is out of reach
            d = (ax - x) * nx + (ay - y) * ny
            fx, fy = (-nx, -ny) if d > 0.0 else (nx, ny)
            ox, oy = fx * 0.0 - x, fy * 0.0 - y
            terms = (ax + ox, ay + oy, bx + ox, by + oy, nx, ny, d + (-0.0 if d > 0.0 else 0.0))
            to_a, to_b = math.atan2(ay - y, ax - x), math.atan2(by - y, bx - x)
            sweep = (to_b - to_a) % TAU
            low, width = (to_a, sweep) if sweep <= math.pi else (to_b, TAU - sweep)
            _spread(by_ray, terms, (low - first_angle) % TAU, width, step)

    def _circles_by_ray(self, x: float, y: float, reach: float, step: float, first_angle: float, by_ray) -> bool:
        """Give each ray the reachable circles it points at, with the ray-independent terms of
        CircleSegmentQuery; False when (x, y) is inside a circle (chipmunk's point query comes
        first: then every ray hits at once)."""
        for cx, cy, r in self.circles:
            ax, ay = x - cx, y - cy
            aa = ax * ax + ay * ay
            centre_m = math.sqrt(aa)
            gap = centre_m - r
            if gap <= 0.0:
                return False
            if gap > reach:
                continue
            half = math.asin(r / centre_m)
            _spread(by_ray, (cx, cy, ax, ay, aa, aa - r * r), (math.atan2(-ay, -ax) - half - first_angle) % TAU,
                    2 * half, step)
        return True

    def scan(self, x: float, y: float, heading: float, fov_deg: float, range_m: float,
             step_deg: float) -> tuple[tuple[float, float], ...]:
        """(bearing relative to the heading, distance) of each ray's nearest hit within range."""
        reach = range_m + REACH_MARGIN_M
        rays = max(1, int(fov_deg / step_deg)) + 1  # both edges of the field of view
        first = -math.radians(fov_deg) / 2
        step = math.radians(fov_deg) / (rays - 1)
        circles_by_ray, walls_by_ray = [None] * rays, [None] * rays
        if not self._circles_by_ray(x, y, reach, step, heading + first, circles_by_ray):
            return tuple((first + n * step, 0.0) for n in range(rays))
        self._walls_by_ray(x, y, reach, step, heading + first, walls_by_ray)
        cos, sin, sqrt = math.cos, math.sin, math.sqrt
        hits = []
        for n in range(rays):
            walls, circles = walls_by_ray[n] or (), circles_by_ray[n] or ()
            if not walls and not circles:
                continue
            bearing = first + n * step
            angle = heading + bearing
            qx, qy = x + range_m * cos(angle), y + range_m * sin(angle)
            dx, dy = qx - x, qy - y
            nearest = 1.0  # chipmunk keeps a hit only if it is nearer than the ray's end
            for sax, say, sbx, sby, nx, ny, offset in walls:  # cpSegmentShapeSegmentQuery, r = 0
                if (dx * say - dy * sax) * (dx * sby - dy * sbx) <= 0.0:
                    ad, bd = -offset, (dx * nx + dy * ny) - offset
                    if ad * bd < 0.0 and ad / (ad - bd) < nearest:
                        nearest = ad / (ad - bd)
            for cx, cy, ax, ay, aa, aa_rr in circles:  # CircleSegmentQuery, r2 = 0
                bx, by = qx - cx, qy - cy
                ab = ax * bx + ay * by
                qa = aa - 2.0 * ab + (bx * bx + by * by)
                qb = ab - aa
                det = qb * qb - qa * aa_rr
                if det >= 0.0:
                    t = (-qb - sqrt(det)) / qa
                    if 0.0 <= t <= 1.0 and t < nearest:
                        nearest = t
            if nearest < 1.0:
                hits.append((bearing, nearest * range_m))
        return tuple(hits)
