"""What a user asks of the campaign layer's commands (`run`, `campaign`, `shrink`), typed: the
command line builds one (harness/commands/) after checking each flag's value, and so may a
program or a test. The defaults here are the command line's."""
from __future__ import annotations

from dataclasses import dataclass

from harness import DEFAULT_DB, DEFAULT_MISSION_DIR

MAX_DELAY_S = 0.003  # largest interface observation delay of a simulated run


@dataclass(frozen=True)
class RunRequest:
    """`run`: one script on one SUT."""
    script: str  # the mission script (the command line's MISSION); a "mission" is a target's folder
    sut: str
    seed: int = 0
    interface: str | None = None  # default: interface.toml beside the script
    world: str | None = None  # default: world.toml beside the script
    max_delay: float = MAX_DELAY_S
    time_scale: float | None = None  # external SUTs: default their own
    db: str = str(DEFAULT_DB)


@dataclass(frozen=True)
class CampaignRequest:
    """`campaign`: golden + mutants on each SUT (docs/reference/commands.md names each field's flag)."""
    mission: str = str(DEFAULT_MISSION_DIR)
    mutants: int = 300
    sut: str | None = None  # comma-separated; default: the layer's default_suts
    seed: int = 2012
    jobs: int = 0  # 0: all cores
    strategy: str = "random"
    budget: str | None = None  # focused only, e.g. "40m"
    ops_per_mutant: int | None = None  # default: the strategy's
    shrink: bool = False
    time_mutations: bool = False
    value_mutations: bool = False
    operators: str | None = None  # comma-separated
    cluster: str | None = None  # tcp://HOST:PORT or local:N
    max_delay: float = MAX_DELAY_S
    shard: str | None = None  # I/N
    allow_code_change: bool = False  # resume a campaign another version of the bench's code made
    time_scale: float | None = None
    db: str = str(DEFAULT_DB)


@dataclass(frozen=True)
class ShrinkRequest:
    """`shrink`: one bad trace's script, reduced."""
    trace_id: int
    property: str | None = None
    verdict: str | None = None  # FN or FP, with property
    mission: str | None = None  # default: the trace's campaign's
    sut: str | None = None  # an external SUT named again
    run_stored_command: bool = False
    out: str | None = None  # default: shrunk/ beside the store
    db: str = str(DEFAULT_DB)
