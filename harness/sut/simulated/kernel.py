"""A tiny discrete-event kernel in virtual time, in the manner of SimPy.

Processes are generators that yield events; the kernel resumes a process when the event
it waits on is processed. Scheduled events sit in a heap of (time, priority, seq, event):
`seq` is a global counter, so events at equal times run in a reproducible order.
Nothing here sleeps: time jumps from one event to the next.

Failures as in SimPy: an event may `fail(exception)`, which is thrown into the processes waiting
on it; a process whose generator raises fails with that exception, noted with the process's name;
a failure that nothing waits on is raised out of `run`, so that it never passes silently.
"""
from __future__ import annotations

from heapq import heappop, heappush
from itertools import count
from typing import Any, Callable, Generator

from harness.errors import InternalSignal

URGENT, NORMAL = 0, 1


class Interrupt(InternalSignal):
    """Thrown into a process by Process.interrupt(cause)."""

    @property
    def cause(self) -> Any:
        return self.args[0] if self.args else None


class Event:
    """Something that happens once; callbacks run when the kernel processes it."""

    # Slots: a run creates hundreds of thousands of events (mostly timeouts), each cheaper so.
    __slots__ = ("env", "callbacks", "triggered", "ok", "value")

    def __init__(self, env: "Environment"):
        self.env = env
        self.callbacks: list[Callable[[Event], None]] | None = []
        self.triggered = False
        self.ok = True
        self.value: Any = None

    @property
    def processed(self) -> bool:
        return self.callbacks is None

    def succeed(self, value: Any = None, priority: int = NORMAL) -> "Event":
        if self.triggered:
            raise RuntimeError(f"{self!r} has already been triggered")
        self.triggered, self.value = True, value
        self.env._schedule(self, 0.0, priority)
        return self

    def fail(self, exception: BaseException, priority: int = NORMAL) -> "Event":
        """Trigger the event as failed: `exception` is thrown into the processes waiting on it."""
        if not isinstance(exception, BaseException):
            raise TypeError(f"{exception!r} is not an exception; fail() takes an exception instance")
        if self.triggered:
            raise RuntimeError(f"{self!r} has already been triggered")
        self.triggered, self.ok, self.value = True, False, exception
        self.env._schedule(self, 0.0, priority)
        return self

    def _state(self) -> str:
        state = "processed" if self.processed else "triggered" if self.triggered else "pending"
        return state if self.ok else f"{state}, failed with {self.value!r}"

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self._state()} at t={self.env.now:.6f}>"


class Timeout(Event):
    __slots__ = ("delay",)

    def __init__(self, env: "Environment", delay: float):
        if delay < 0:
            raise ValueError(f"negative timeout delay {delay!r}")
        # Event.__init__ and Environment._schedule inlined: the kernel's most frequent path. One
        # assignment each: a multiple assignment builds and unpacks a tuple (4% of a kernel run).
        self.env = env
        self.callbacks = []
        self.triggered = self.ok = True
        self.value = None
        self.delay = delay
        heappush(env._heap, (env.now + delay, NORMAL, next(env._seq), self))

    def __repr__(self) -> str:
        return f"<Timeout {self.delay:g}s {'processed' if self.processed else 'pending'}>"


class Condition(Event):
    """Succeeds when `needed` of `events` have been processed (any_of: one, all_of: all), with
    the values of those processed so far by event; fails with the first failure among them.
    Events processed before the condition was made count at once."""

    __slots__ = ("events", "needed")

    def __init__(self, env: "Environment", events: tuple[Event, ...], needed: int):
        super().__init__(env)
        self.events, self.needed = events, needed
        if needed == 0:
            self.succeed({})
        for event in events:
            if event.callbacks is None:
                self._check(event)
            else:
                event.callbacks.append(self._check)

    def _check(self, event: Event) -> None:
        if self.triggered:
            return
        if not event.ok:
            self.fail(event.value)
            return
        self.needed -= 1
        if self.needed == 0:
            self.succeed({e: e.value for e in self.events if e.callbacks is None and e.ok})

    def __repr__(self) -> str:
        done = sum(e.callbacks is None for e in self.events)
        return f"<Condition {done} of {len(self.events)} events processed, {self._state()}>"


class Process(Event):
    """Runs a generator; the process is itself an event that triggers when the generator returns."""

    __slots__ = ("generator", "name", "target", "_resumer")

    def __init__(self, env: "Environment", generator: Generator, name: str = ""):
        super().__init__(env)
        self.generator, self.name = generator, name or getattr(generator, "__name__", "process")
        self.target: Event | None = None
        self._resumer = self._resume  # one bound method, appended to every event it waits on
        start = Event(env)
        start.callbacks.append(self._resumer)
        start.succeed(priority=URGENT)

    @property
    def is_alive(self) -> bool:
        return not self.triggered

    def interrupt(self, cause: Any = None) -> None:
        """Throw Interrupt(cause) into the process at the current time, ahead of normal events."""
        if not self.is_alive:
            return
        kick = Event(self.env)
        kick.ok, kick.value = False, Interrupt(cause)
        kick.callbacks.append(self._resumer)
        kick.triggered = True
        self.env._schedule(kick, 0.0, URGENT)

    def _resume(self, event: Event) -> None:
        if self.triggered:  # no longer alive
            return
        target = self.target
        if target is not None and target is not event and target.callbacks is not None:
            # An interruption overtakes the event the process was waiting on.
            target.callbacks.remove(self._resumer)
        self.target = None
        try:
            if event.ok:
                nxt = self.generator.send(event.value)
            else:
                nxt = self.generator.throw(event.value)
        except StopIteration as stop:
            self.triggered, self.value = True, stop.value
            self.env._schedule(self, 0.0, NORMAL)
            return
        except Exception as error:  # the process fails: its waiters get the error, or run() raises it
            error.add_note(f"raised in process {self.name!r} at t={self.env.now:.6f}")
            self.triggered, self.ok, self.value = True, False, error
            self.env._schedule(self, 0.0, URGENT)
            return
        if not isinstance(nxt, Event):
            raise TypeError(f"process {self.name!r} yielded {nxt!r}; yield an Event")
        callbacks = nxt.callbacks
        if callbacks is None:  # already processed: resume right away, with its value or its failure
            resume = Event(self.env)
            resume.callbacks.append(self._resumer)
            if nxt.ok:
                resume.succeed(nxt.value, priority=URGENT)
            else:
                resume.fail(nxt.value, priority=URGENT)
            self.target = resume
        else:
            callbacks.append(self._resumer)
            self.target = nxt

    def __repr__(self) -> str:
        state = "alive" if self.is_alive else "done" if self.ok else f"failed with {self.value!r}"
        return f"<Process {self.name} {state}>"


class Environment:
    """The virtual clock and the event heap."""

    def __init__(self) -> None:
        self.now = 0.0
        self._heap: list[tuple[float, int, int, Event]] = []
        self._seq = count()

    def _schedule(self, event: Event, delay: float, priority: int) -> None:
        heappush(self._heap, (self.now + delay, priority, next(self._seq), event))

    def event(self) -> Event:
        return Event(self)

    def timeout(self, delay: float) -> Timeout:
        return Timeout(self, delay)

    def process(self, generator: Generator, name: str = "") -> Process:
        return Process(self, generator, name)

    def any_of(self, *events: Event) -> Condition:
        """An event that succeeds, once, when the first of `events` is processed (at once if one is)."""
        return Condition(self, events, min(1, len(events)))

    def all_of(self, *events: Event) -> Condition:
        """An event that succeeds when every one of `events` has been processed."""
        return Condition(self, events, len(events))

    def call_at(self, time: float, callback: Callable[[], None]) -> Event:
        """Run a plain callback at an absolute time (used for message delivery)."""
        event = Timeout(self, max(0.0, time - self.now))
        event.callbacks.append(lambda _e: callback())
        return event

    def peek(self) -> float:
        return self._heap[0][0] if self._heap else float("inf")

    def lag(self) -> float:
        """How far the clock of the world is ahead of `now` (virtual time: never)."""
        return 0.0

    def step(self) -> None:
        self.now, _, _, event = heappop(self._heap)
        callbacks, event.callbacks = event.callbacks, None
        for callback in callbacks:
            callback(event)
        if not event.ok and not callbacks:
            raise event.value  # a failure nobody waits for must not pass silently

    def run(self, until: float | Event | None = None) -> None:
        """Process events until the heap is empty, a time is reached, or an event is processed."""
        heap, step = self._heap, self.step
        if isinstance(until, Event):
            while until.callbacks is not None and heap:  # not yet processed
                step()
            return
        limit = float("inf") if until is None else until
        while heap and heap[0][0] <= limit:
            step()
        if until is not None:
            self.now = max(self.now, limit)

    def __repr__(self) -> str:
        return f"<Environment t={self.now:.6f} pending={len(self._heap)}>"
