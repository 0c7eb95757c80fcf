"""What one run of a script on a variant produced, before it goes to the store."""
from __future__ import annotations

from dataclasses import dataclass, field

# Column order of an event row, shared by `events` and `internal_events` (docs/reference/store.md).
EVENT_COLUMNS = ("seq", "t", "kind", "rqst_id", "module", "service", "args", "reply")
# A file of events to import, and a bag read into rows: each event with its trace, and the trace's outcome and SUT.
IMPORTED_COLUMNS = ("trace_id", *EVENT_COLUMNS, "outcome", "sut")
WORLD_EVENT_COLUMNS = ("t", "kind", "detail")
# A `taken` reply (seq on the counter of the trace's events, which skip its numbers).
TAKEN_EVENT_COLUMNS = ("seq", "t", "rqst_id")
OUTCOMES = ("completed", "hung", "crashed")


@dataclass
class Trace:
    sut: str
    seed: int
    outcome: str = "completed"
    sim_s: float = 0.0
    wall_s: float = 0.0
    error: str | None = None
    # Rows in EVENT_COLUMNS order; args is a JSON text or None, reply None on requests.
    events: list[tuple] = field(default_factory=list)
    internal_events: list[tuple] = field(default_factory=list)
    world_events: list[tuple] = field(default_factory=list)  # (t, kind, detail JSON text)
    taken_events: list[tuple] = field(default_factory=list)  # (seq, t, rqst_id)
    # Where, when and with what interface latency a real-time run ran (a trace_runs row).
    provenance: dict | None = None

    def __repr__(self) -> str:
        return (f"<Trace {self.sut} seed={self.seed} {self.outcome} {len(self.events)} events "
                f"sim={self.sim_s:.1f}s>")
