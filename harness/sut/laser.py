"""Laser rays against the world's static shapes (the bounds' walls and round rocks), computed here.

A pymunk ray query costs some 9 µs of wrapping per ray; the world's shapes are 4 segments and a few
circles, so the nearest hit is cheaper computed directly. The arithmetic is chipmunk's own
(Munk2D `CircleSegmentQuery`, `cpSegmentShapeSegmentQuery`, `cpSpaceSegmentQueryFirst`), operation
for operation in IEEE doubles, so every hit equals pymunk's to the last bit: the traces, which
depend on where the rover steers, stay the same (tests/test_sut_laser.py compares them).

Only shapes that the scan's range can reach are tested; a shape is left out only when it is
farther than the range by more than REACH_MARGIN_M, far beyond any rounding.
"""
from __future__ import annotations

import math

REACH_MARGIN_M = 1e-6
_TINY = 2.2250738585072014e-308  # CPFLOAT_MIN (DBL_MIN): chipmunk's guard in cpvnormalize


def wall(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, ...]:
    """A zero-thickness segment as chipmunk caches it: ends and unit normal (cpSegmentShapeInit)."""
    vx, vy = b[0] - a[0], b[1] - a[1]
    scale = 1.0 / (math.sqrt(vx * vx + vy * vy) + _TINY)
    vx, vy = vx * scale, vy * scale
    return a[0], a[1], b[0], b[1], vy, -vx  # cpvrperp


def _segment_distance(px: float, py: float, segment: tuple[float, ...]) -> float:
    ax, ay, bx, by = segment[:4]
    dx, dy = bx - ax, by - ay
    along = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(px - ax - along * dx, py - ay - along * dy)


class Laser:
    """Rays from a point against fixed walls and circles (x, y, radius)."""

    def __init__(self, walls: list[tuple[float, ...]], circles: list[tuple[float, float, float]]):
        self.walls, self.circles = walls, circles

    def _walls_seen_from(self, x: float, y: float, reach: float) -> list[tuple[float, ...]]:
        """Per reachable wall, what cpSegmentShapeSegmentQuery computes before it looks at the ray:
        the ends relative to (x, y) (moved by a thickness of 0), the normal, the offset."""
        seen = []
        for segment in self.walls:
            if _segment_distance(x, y, segment) > reach:
                continue
            ax, ay, bx, by, nx, ny = segment
            d = (ax - x) * nx + (ay - y) * ny
            fx, fy = (-nx, -ny) if d > 0.0 else (nx, ny)
            ox, oy = fx * 0.0 - x, fy * 0.0 - y
            seen.append((ax + ox, ay + oy, bx + ox, by + oy, nx, ny, d + (-0.0 if d > 0.0 else 0.0)))
        return seen

    def _circles_seen_from(self, x: float, y: float, reach: float) -> tuple[list[tuple[float, ...]], bool]:
        """Per reachable circle, the ray-independent terms of CircleSegmentQuery; and whether (x, y)
        is inside one (chipmunk's point query comes first: such a ray hits at once)."""
        seen = []
        for cx, cy, r in self.circles:
            ax, ay = x - cx, y - cy
            aa = ax * ax + ay * ay
            if math.sqrt(aa) - r <= 0.0:
                return [], True
            if math.sqrt(aa) - r <= reach:
                seen.append((cx, cy, ax, ay, aa, aa - r * r))
        return seen, False

    def scan(self, x: float, y: float, heading: float, fov_deg: float, range_m: float,
             step_deg: float) -> tuple[tuple[float, float], ...]:
        """(bearing relative to the heading, distance) of each ray's nearest hit within range."""
        reach = range_m + REACH_MARGIN_M
        rays = max(1, int(fov_deg / step_deg)) + 1  # both edges of the field of view
        first = -math.radians(fov_deg) / 2
        step = math.radians(fov_deg) / (rays - 1)
        circles, inside = self._circles_seen_from(x, y, reach)
        if inside:
            return tuple((first + n * step, 0.0) for n in range(rays))
        walls = self._walls_seen_from(x, y, reach)
        cos, sin, sqrt = math.cos, math.sin, math.sqrt
        hits = []
        for n in range(rays):
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
