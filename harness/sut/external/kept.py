"""Adapters kept between runs: one adapter per SUT and slot serves run after run.

Starting an adapter can cost more than the run it serves: a ROS adapter starts a master and a
node, seconds of work on a loaded machine. An adapter whose hello answer offers `reuse`
(untimely/1, docs/protocol.md) takes the next run's hello after `bye`, once it has answered
that bye with its own (nothing of the ended run comes after it). Within a `kept_adapters()`
block, a run that ended cleanly leaves its channel here, and the next run of the same SUT on the
same slot takes it; a hung or crashed run's adapter is ended as always, so a run never inherits
a sick one. A kept adapter that died while idle is replaced before the next run, never blamed:
`take` leaves out one whose process has ended, and a run whose taken adapter does not answer its
hello starts a fresh one (harness.sut.external.runner). The block's end closes every kept
channel: no process left behind.
"""
from __future__ import annotations

import threading
from contextlib import contextmanager
from typing import Iterator

from harness.sut.external.channel import Channel
from harness.target.suts import ExternalSut

_lock = threading.Lock()
_idle: dict[tuple[str, int], Channel] | None = None  # None: outside a kept_adapters() block


def _key(sut: ExternalSut, slot: int) -> tuple[str, int]:
    return sut.model_dump_json(), slot


@contextmanager
def kept_adapters() -> Iterator[None]:
    """Keep reusable adapters while the block runs (blocks nest: the outermost closes them)."""
    global _idle
    with _lock:
        outermost = _idle is None
        if outermost:
            _idle = {}
    try:
        yield
    finally:
        if outermost:
            with _lock:
                idle, _idle = _idle, None
            for connection in idle.values():
                connection.close()


def keeping() -> bool:
    """Whether a kept_adapters() block is open."""
    return _idle is not None


def take(sut: ExternalSut, slot: int) -> Channel | None:
    """The idle channel of `sut` on `slot`, if one is kept and its adapter still runs."""
    with _lock:
        connection = _idle.pop(_key(sut, slot), None) if _idle is not None else None
    if connection is not None and (connection.gone() or connection.exited()):
        connection.close()
        return None
    return connection


def keep(connection: Channel, sut: ExternalSut, slot: int) -> bool:
    """Keep `connection` for the next run of `sut` on `slot`; False if it cannot be (no block)."""
    with _lock:
        if _idle is None or _key(sut, slot) in _idle:
            return False
        _idle[_key(sut, slot)] = connection
        return True
