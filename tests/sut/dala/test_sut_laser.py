"""The laser's hits, computed without pymunk, equal pymunk's ray queries to the last bit."""
import math
import random

import pymunk
import pytest

from harness.sut.dala.laser import Laser, wall
from harness.sut.dala.world import load_world
from tests.support.sut_driver import WORLD


def pymunk_scan(space, x, y, heading, fov_deg, range_m, step_deg):
    """The scan as the world cast it before issue 14: one pymunk query per ray."""
    rays = max(1, int(fov_deg / step_deg)) + 1
    first, step = -math.radians(fov_deg) / 2, math.radians(fov_deg) / (rays - 1)
    hits = []
    for n in range(rays):
        bearing = first + n * step
        angle = heading + bearing
        end = (x + range_m * math.cos(angle), y + range_m * math.sin(angle))
        hit = space.segment_query_first((x, y), end, 0.0, pymunk.ShapeFilter())
        if hit is not None:
            hits.append((bearing, hit.alpha * range_m))
    return tuple(hits)


def shapes(spec):
    (x0, x1), (y0, y1) = spec.x_range, spec.y_range
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return list(zip(corners, corners[1:] + corners[:1])), [(r.x, r.y, r.radius) for r in spec.rocks]


@pytest.fixture(scope="module")
def dala():
    spec = load_world(WORLD)
    walls, circles = shapes(spec)
    space = pymunk.Space()
    space.add(*[pymunk.Segment(space.static_body, a, b, 0.0) for a, b in walls])
    space.add(*[pymunk.Circle(space.static_body, r, (x, y)) for x, y, r in circles])
    return spec, space, Laser([wall(a, b) for a, b in walls], circles)


def test_hits_equal_pymunk_s_from_random_poses_bit_for_bit(dala):
    spec, space, laser = dala
    rng = random.Random(14)
    hits = 0
    for _ in range(3000):
        x, y = rng.uniform(*spec.x_range), rng.uniform(*spec.y_range)  # inside rocks too
        heading, fov, reach = rng.uniform(-7, 7), rng.choice([90.0, 180.0, rng.uniform(1, 360)]), rng.uniform(0.5, 12)
        expected = pymunk_scan(space, x, y, heading, fov, reach, 10.0)
        assert laser.scan(x, y, heading, fov, reach, 10.0) == expected, (x, y, heading, fov, reach)
        hits += len(expected)
    assert hits > 10_000  # the poses do see walls and rocks


def test_hits_equal_pymunk_s_near_walls_corners_and_rock_edges(dala):
    spec, space, laser = dala
    rng = random.Random(15)
    rock = spec.rocks[0]
    poses = [(0.4, 0.4), (19.6, 0.41), (19.99, 19.99), (10.0, 1e-9), (rock.x - rock.radius - 1e-12, rock.y),
             (rock.x, rock.y + rock.radius), (rock.x + rock.radius + 1e-9, rock.y)]
    for x, y in poses:
        for heading in [0.0, math.pi / 4, math.pi / 2, math.pi, -math.pi / 2, rng.uniform(-4, 4)]:
            assert laser.scan(x, y, heading, 360.0, 4.0, 1.0) == pymunk_scan(space, x, y, heading, 360.0, 4.0, 1.0)


def test_rays_grazing_a_rock_hit_or_miss_as_in_pymunk(dala):
    spec, space, laser = dala
    rng = random.Random(16)
    grazes = 0
    for rock in spec.rocks:
        for _ in range(40):
            x, y = rng.uniform(*spec.x_range), rng.uniform(*spec.y_range)
            distance = math.dist((x, y), (rock.x, rock.y))
            if distance <= rock.radius:
                continue
            centre, half = math.atan2(rock.y - y, rock.x - x), math.asin(rock.radius / distance)
            for side in (-1, 1):
                for off in (0.0, 1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9, 1e-7, -1e-7, 2e-6, -2e-6):
                    heading = centre + side * (half + off) + math.radians(15)  # the first ray grazes
                    got = laser.scan(x, y, heading, 30.0, 30.0, 10.0)
                    assert got == pymunk_scan(space, x, y, heading, 30.0, 30.0, 10.0), (x, y, heading)
                    grazes += 1
    assert grazes > 3000
