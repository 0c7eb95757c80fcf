"""A fixed pure-Python workload timed in the same run as a benchmark, so that figures measured on a
busy machine compare with those from a quiet one: a benchmark divides its times by this one's.

The loop mixes what the simulator spends its time on (dict and heap operations, float arithmetic,
method calls); the median of several repetitions resists a passing load spike. Both its wall time
and its CPU time are kept: on a shared machine the wall clock also counts other people's work, the
CPU clock much less so.
"""
import heapq
import statistics
import time
from dataclasses import dataclass

REPEATS = 7


@dataclass(frozen=True)
class Calibration:
    """Repetitions of the loop: wall and CPU seconds of each."""
    walls: tuple[float, ...]
    cpus: tuple[float, ...]

    @property
    def wall_s(self) -> float:
        return statistics.median(self.walls)

    @property
    def cpu_s(self) -> float:
        return statistics.median(self.cpus)

    def __add__(self, other: "Calibration") -> "Calibration":
        return Calibration(self.walls + other.walls, self.cpus + other.cpus)


def _workload() -> float:
    heap, table, total = [], {}, 0.0
    for i in range(200_000):
        heapq.heappush(heap, ((i * 7919) % 1000 * 0.001, i))
        table[i % 512] = table.get(i % 512, 0.0) + i * 0.5
        if len(heap) > 64:
            total += heapq.heappop(heap)[0]
    return total + sum(table.values())


def calibrate(repeats: int = REPEATS) -> Calibration:
    walls, cpus = [], []
    for _ in range(repeats):
        wall, cpu = time.perf_counter(), time.process_time()
        _workload()
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return Calibration(tuple(walls), tuple(cpus))

