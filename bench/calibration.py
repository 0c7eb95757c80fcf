"""A fixed pure-Python workload timed in the same run as a benchmark, so that figures measured on a
busy machine compare with those from a quiet one: a benchmark divides its wall time by this one's.

The loop mixes what the simulator spends its time on (dict and heap operations, float arithmetic,
method calls); the median of several repetitions resists a passing load spike.
"""
import heapq
import statistics
import time

REPEATS = 7


def _workload() -> float:
    heap, table, total = [], {}, 0.0
    for i in range(200_000):
        heapq.heappush(heap, ((i * 7919) % 1000 * 0.001, i))
        table[i % 512] = table.get(i % 512, 0.0) + i * 0.5
        if len(heap) > 64:
            total += heapq.heappop(heap)[0]
    return total + sum(table.values())


def calibration_s() -> float:
    """Median wall time of the fixed workload, in seconds."""
    walls = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        _workload()
        walls.append(time.perf_counter() - start)
    return statistics.median(walls)

