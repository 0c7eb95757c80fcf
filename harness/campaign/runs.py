"""A campaign's runs: which (script, variant) pair is which trace, with which seed, and how the
traces reach the store.

Run (script, variant) gets the trace id (script_id - 1) * len(variants) + variant index + 1 and
a seed hashed from the campaign seed, the script's number in the campaign (golden 0, mutant n)
and the variant's name: never a function of scheduling. Traces are committed in batches
(Batches): a campaign killed at any moment restarts from the runs whose trace ids are missing.
"""
from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass

from harness import store
from harness.campaign import sharding
from harness.errors import StoreError
from harness.progress import Progress
from harness.dispatch.description import Task
from harness.store import campaign_reads
from harness.store.record import CampaignRecord
from harness.trace import Trace

# A transaction per simulated run cost a quarter of a campaign; a killed campaign re-runs at most
# one batch: up to BATCH_RUNS runs, or those that came in during BATCH_S (a couple of seconds' work).
BATCH_RUNS = 64
BATCH_S = 2.0


def run_seed(campaign_seed: int, script_number: int, sut: str) -> int:
    digest = hashlib.sha256(f"{campaign_seed}:{script_number}:{sut}".encode()).digest()
    return int.from_bytes(digest[:8], "big") >> 1  # fits a signed BIGINT


def tasks(scripts: list[tuple[int, str]], golden_id: int, config: CampaignRecord) -> list[Task]:
    n = len(config.sut)
    return [Task(sharding.trace_id(script_id, v, n), script_id, sut,
                 run_seed(config.seed, script_id - golden_id, sut), body)
            for script_id, body in scripts for v, sut in enumerate(config.sut)]


@dataclass
class Tally:
    """The tally of what this invocation ran (a resumed campaign's earlier runs are not counted)."""
    progress: Progress
    start: float
    runs: int = 0
    sim_s: float = 0.0

    def count(self, trace: Trace) -> None:
        self.runs += 1
        self.sim_s += trace.sim_s
        self.progress.ran(trace)


def pending_tasks(con, campaign_id: int, config: CampaignRecord) -> list[Task]:
    scripts = campaign_reads.valid_scripts(con, campaign_id)
    golden_id = scripts[0][0]
    every = tasks(scripts, golden_id, config)
    owners = campaign_reads.trace_owners(con, every[0].trace_id)
    for task in every:
        if owners.get(task.trace_id, campaign_id) != campaign_id:
            raise StoreError(f"trace id {task.trace_id}, which campaign {campaign_id} needs for script "
                             f"{task.script_id} on {task.sut}, is taken by campaign {owners[task.trace_id]}; "
                             "add ad-hoc runs to another --db while a campaign is unfinished")
    return [t for t in sharding.part(every, config.shard) if t.trace_id not in owners]


class Batches:
    """Traces committed together: when BATCH_RUNS have come in, when the oldest has waited BATCH_S,
    at once for a real-time run (it took wall-clock time to make), and at the end of the invocation.
    An invocation ended by an exception (Ctrl-C included) still commits the traces it holds."""

    def __init__(self, con, campaign_id: int, tally: Tally, realtime: set[str]):
        self.con, self.campaign_id, self.tally, self.realtime = con, campaign_id, tally, realtime
        self.held: list[tuple[int, int, Trace, None]] = []
        self.oldest = 0.0

    def add(self, task: Task, trace: Trace) -> None:
        if not self.held:
            self.oldest = time.monotonic()
        self.held.append((task.trace_id, task.script_id, trace, None))
        self.tally.count(trace)
        if (len(self.held) >= BATCH_RUNS or time.monotonic() - self.oldest >= BATCH_S
                or task.sut in self.realtime):
            self.commit()

    def commit(self) -> None:
        try:
            if self.held:
                with store.transaction(self.con):
                    store.insert_traces(self.con, self.campaign_id, self.held)
        except BaseException:  # a stop signal as the commit returns: stored, so not to be stored again
            if campaign_reads.is_stored(self.con, self.held[0][0]):
                self.held = []
            raise
        self.held = []

    def __enter__(self) -> "Batches":
        return self

    def __exit__(self, *_exception) -> None:
        self.commit()
