"""Real-time runs on parallel slots: the golden mission through the out-of-process simulator
(`sim-reference` of missions/dala/suts.toml, at TIME_SCALE times real time), on 1 slot and on
8 slots of the campaign's worker pool. A real-time run mostly waits, so slots may outnumber
the cores; the speed-up of N slots over 1 is the figure (issue 8 aims at >= 0.8 N for N = 8).
"""
import time

from harness import DEFAULT_MISSION_DIR
from harness.sut.definitions import resolve
from harness.dispatch import transport
from harness.dispatch.description import Setup, Task
from harness.dispatch.workers import run_all

TIME_SCALE = 10.0
ROUNDS = 2  # runs per slot


def golden_runs(count: int, time_scale: float) -> tuple[Setup, list[Task]]:
    """`count` runs of the golden mission through `sim-reference` at `time_scale`."""
    _, external = resolve("sim-reference", DEFAULT_MISSION_DIR, time_scale)
    setup = transport.setup(None, DEFAULT_MISSION_DIR / "interface.toml", DEFAULT_MISSION_DIR / "world.toml", 0.0, external)
    body = (DEFAULT_MISSION_DIR / "golden.mission").read_text()
    return setup, [Task(n, 1, "sim-reference", n, body) for n in range(1, count + 1)]


def timed(run_tasks, tasks: list[Task]) -> tuple[float, list]:
    """Wall seconds of `run_tasks(tasks, on_trace)`, and the traces (all must complete)."""
    traces = []
    start = time.perf_counter()
    run_tasks(tasks, lambda task, trace: traces.append(trace))
    wall = time.perf_counter() - start
    assert all(t.outcome == "completed" for t in traces), [t.error for t in traces]
    return wall, traces


def runs_per_second(slots: int) -> tuple[float, float]:
    setup, tasks = golden_runs(slots * ROUNDS, TIME_SCALE)
    wall, traces = timed(lambda tasks, on_trace: run_all(tasks, setup, slots, on_trace), tasks)
    return len(traces) / wall, sum(t.sim_s for t in traces) / wall


def main() -> int:
    one, one_sim = runs_per_second(1)
    eight, eight_sim = runs_per_second(8)
    print(f"golden mission at {TIME_SCALE:g}x real time through untimely/1, {ROUNDS} runs per slot "
          "(each run starts its own adapter process)")
    print(f"1 slot           {one:.3f} runs/s, {one_sim:.1f} mission s per wall s")
    print(f"8 slots          {eight:.3f} runs/s, {eight_sim:.1f} mission s per wall s")
    print(f"speed-up         {eight / one:.2f}x with 8 slots over 1 ({eight / one / 8:.2f} N; aim >= 0.8 N)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
