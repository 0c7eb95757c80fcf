"""The slots shared by a focused campaign's test runs and background shrink runs on external SUTs
(harness.campaign.slots): never two runs on one slot, tests served before shrinks, errors kept,
and runs of one process that start and close side by side leave each other's adapters alone."""
import subprocess
import threading
import time

import pytest

from harness.campaign.slots import Slots, SlotsClosed
from harness.errors import UntimelyError
from harness.sut.external import channel
from harness.sut.external.channel import StdioChannel
from harness.target.suts import ExternalSut
from harness.dispatch.description import Task
from harness.trace import Trace


class FakeSetup:
    """Setup.run's signature; records which slots were busy at once."""

    def __init__(self, seconds: float = 0.05, fail: int | None = None):
        self.seconds, self.fail = seconds, fail
        self.busy, self.most, self.lock = set(), 0, threading.Lock()

    def run(self, task: Task, interface, slot: int):
        with self.lock:
            assert slot not in self.busy, f"slot {slot} given twice"
            self.busy.add(slot)
            self.most = max(self.most, len(self.busy))
        time.sleep(self.seconds)
        with self.lock:
            self.busy.discard(slot)
        if task.trace_id == self.fail:
            return UntimelyError("the adapter could not be started")
        return Trace(sut=task.sut, seed=task.seed, outcome="completed", sim_s=1.0)


def tasks(count: int) -> list[Task]:
    return [Task(n, 1, "ext", n, "") for n in range(1, count + 1)]


def test_tests_run_on_distinct_slots_and_every_trace_comes_back():
    setup = FakeSetup()
    done = []
    Slots(setup, None, 3).run_all(tasks(10), lambda task, trace: done.append(task.trace_id))
    assert sorted(done) == list(range(1, 11)) and setup.most == 3


class Watched(threading.Condition):
    """The slots' condition, counting the waits begun on it: a test knows that a thread waits for a
    slot without sleeping a while and hoping."""

    def __init__(self):
        super().__init__()
        self.waits = threading.Semaphore(0)

    def wait(self, timeout=None):
        self.waits.release()
        return super().wait(timeout)


def test_a_free_slot_goes_to_the_waiting_run_of_lowest_rank_not_to_the_one_that_waited_longest():
    """A test of the round in flight first, then a shrink (ranked between the rounds), then a test
    of the round started ahead of time, whatever order they came in."""
    slots = Slots(FakeSetup(), None, 1)
    slots.turn = Watched()
    slots.shrink_rank = 1.5
    order = []

    def take(who: str, rank: float | None) -> None:
        with slots.taken(rank):
            order.append(who)
    with slots.taken(0):
        waiting = []
        for who, rank in (("round 2", 2), ("shrink", None), ("round 1", 1)):
            waiting.append(Slots.background(take, who, rank))
            assert slots.turn.waits.acquire(timeout=5), f"the {who} run never waited for the slot"
    for future in waiting:
        future.result(timeout=5)
    assert order == ["round 1", "shrink", "round 2"]


def test_a_shrink_waiting_for_a_slot_gives_up_when_the_campaign_stops():
    slots = Slots(FakeSetup(), None, 1)
    with slots.taken(0):
        waiting = Slots.background(lambda: slots.taken().__enter__())
        slots.close()
    with pytest.raises(SlotsClosed):
        waiting.result(timeout=5)


def test_an_adapter_that_cannot_start_stops_the_campaign():
    with pytest.raises(UntimelyError, match="could not be started"):
        Slots(FakeSetup(fail=2), None, 2).run_all(tasks(4), lambda task, trace: None)


class Announced:
    """The lock of the channel's starts, telling when a thread asks for it while another holds it."""

    def __init__(self):
        self.lock, self.contended = threading.Lock(), threading.Event()

    def __enter__(self):
        if not self.lock.acquire(blocking=False):
            self.contended.set()
            self.lock.acquire()

    def __exit__(self, *exc):
        self.lock.release()


def test_an_adapter_starting_while_another_run_closes_is_no_orphan_of_it(monkeypatch):
    """A closing channel ends the detached children of the process it does not know: an adapter
    whose start (fork to exec) overlaps that close, in another thread, is not one of them."""
    reader = ExternalSut("reader", command="{python} -c 'import sys; sys.stdin.read()'")
    first = StdioChannel(reader, 0)
    real_popen, started, go_on = subprocess.Popen, threading.Event(), threading.Event()

    def slow_popen(*args, **kwargs):  # the child runs, its Popen has not returned yet
        process = real_popen(*args, **kwargs)
        started.set()
        go_on.wait(10)
        return process
    monkeypatch.setattr(channel.subprocess, "Popen", slow_popen)
    starting = Announced()
    monkeypatch.setattr(channel, "_starting", starting)
    second = Slots.background(StdioChannel, reader, 1)
    assert started.wait(10)
    closing = Slots.background(first.close)
    assert starting.contended.wait(20), "the close never came to the lock the start holds"
    go_on.set()
    closing.result(timeout=20)
    connection = second.result(timeout=20)
    assert connection.process.poll() is None, "the starting adapter was ended"
    connection.close()
