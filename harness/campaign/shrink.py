"""`python -m harness shrink TRACE_ID [--property ID]`: the smallest script showing a trace's bad
behaviour, as a stored script of kind `shrunk` and a `.mission` file that `run` replays.

A bad behaviour is a hang, or an FN or FP verdict on one property, of one variant. The trace's
script is re-run on the same variant with the same seed and observation delays, then reduced by
delta debugging (ddmin) over its steps, then by halving each sleep, keeping a candidate only if
its run still shows the same behaviour (judged by the analyzer's oracles, in memory). Each
shrink is stored as a campaign of kind "shrink" holding every run it made, each a trace linked to
the trace it shrinks (table shrink_runs; Tables II-IV and the findings leave them out), and the
shrunk script (parent: the trace's script; mutations: what was shrunk, from what, in how many
runs); a shrink that fails keeps its runs too. The .mission file is written to --out, by default
the folder `shrunk` beside the store; the report writes the same files from the store.

A store may come from elsewhere: the command of an external SUT recorded in it is never run
unless the user names that SUT again (--sut, or --mission whose suts.toml defines it) or
confirms it (--run-stored-command).
"""
from __future__ import annotations

import shlex
import time
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Callable

from harness import DEFAULT_EPSILON_S, store
from harness.errors import BudgetSpent, ScriptError, StoreError, UntimelyError
from harness.files import make_folder
from harness.store import campaign_reads
from harness.sut.executive import run_script
from harness.target.mission import INTERFACE_FILE, WORLD_FILE
from harness.target.interface import Interface, Property, load_interface
from harness.analysis.judge import Judge
from harness.mutator.ddmin import ddmin
from harness.mutator.operators import plausible
from harness.target.script import Script, parse, validate
from harness.target.suts import ExternalSut
from harness.trace import Trace
from harness.dispatch import transport
from harness.dispatch.description import Task
from harness.store.record import CampaignRecord, RunRecord, ShrinkRecord, record_of

MIN_SLEEP_S = 0.01  # sleeps are halved down to this


@dataclass(frozen=True)
class Behaviour:
    sut: str
    verdict: str  # FN, FP or hung
    property_id: str | None = None  # None for a hang

    def __str__(self) -> str:
        return f"hang on {self.sut}" if self.verdict == "hung" else \
            f"{self.verdict} on {self.property_id} on {self.sut}"

    def shown_by(self, outcome: str, verdicts: list[dict]) -> bool:
        if self.verdict == "hung":
            return outcome == "hung"
        return any(v["property_id"] == self.property_id and v["verdict"] == self.verdict for v in verdicts)


@dataclass
class Original:
    """A stored trace to shrink and what re-running it needs."""
    trace_id: int
    script_id: int
    sut: str
    seed: int
    outcome: str
    body: str
    mission: Path
    max_delay: float
    external: dict[str, ExternalSut]  # the campaign's external SUTs, by name
    slot: int = 0  # the slot its re-runs take (shrinks running side by side take different ones)
    # what runs a script on a simulated variant, with run_script's signature (tests give a broken one)
    runner: Callable = field(default=run_script, repr=False)
    made: list = field(default_factory=list, init=False)  # every re-run: (body, Trace), to be stored

    @cached_property
    def interface(self) -> Interface:
        return load_interface(self.mission / INTERFACE_FILE)

    def run(self, body: str) -> Trace:
        """Run a script on the trace's variant with its seed, as the campaign's workers do."""
        setup = transport.setup(self.runner, self.mission / INTERFACE_FILE, self.mission / WORLD_FILE, self.max_delay,
                      self.external)
        trace = setup.run(Task(self.trace_id, self.script_id, self.sut, self.seed, body), self.interface, self.slot)
        self.made.append((body, trace))
        return trace


def original(con, trace_id: int, mission: str | None = None) -> Original:
    found = campaign_reads.trace_to_shrink(con, trace_id)
    if found is None:
        raise StoreError(f"no trace {trace_id} in the store; pick one from "
                         "python -m harness sql \"select * from bad_behaviours\"")
    trace_id, script_id, sut, seed, outcome, body, campaign_mission, config = found
    record = record_of(config)
    if body is None or not isinstance(record, (CampaignRecord, RunRecord)):
        raise UntimelyError(f"trace {trace_id} was imported: it has no script to shrink; shrink a trace "
                            "that a campaign or `run` made")
    folder = record.target(campaign_mission)
    return Original(trace_id, script_id, sut, seed, outcome, body, Path(mission) if mission else folder,
                    record.max_delay, record.external)


def _codes(prop: Property) -> set[str]:
    return {c for c in (prop.r_p, prop.z_p) if c}


class Reproducer:
    """Runs candidate scripts and says whether they still show the behaviour (memoised)."""

    def __init__(self, orig: Original, behaviour: Behaviour, properties: list[Property]):
        self.orig, self.behaviour = orig, behaviour
        self.interface = orig.interface
        target = next((p for p in properties if p.id == behaviour.property_id), None)
        # the property and those sharing its codes: enough for the shared-code rule of FP verdicts
        related = [p for p in properties if target and (p is target or _codes(p) & _codes(target))]
        self.judge = Judge(self.interface, related or properties[:1], DEFAULT_EPSILON_S)
        self.runs, self.seen = 0, {}
        self.smallest: list | None = None  # the fewest steps a run has shown the behaviour with

    def shows(self, steps) -> bool:
        script = Script(tuple(steps), "shrink candidate").renumbered()
        body = script.render()
        if body not in self.seen:
            try:
                validate(script, self.interface)
            except ScriptError:
                self.seen[body] = False
                return False
            trace = self.orig.run(body)
            self.runs += 1
            self.seen[body] = self.behaviour.shown_by(trace.outcome, self.judge.verdicts([trace])[0])
            if self.seen[body] and (self.smallest is None or len(steps) <= len(self.smallest)):
                self.smallest = list(steps)
        return self.seen[body]


def behaviour_of(orig: Original, properties: list[Property], property_id: str | None,
                 verdict: str | None = None) -> Behaviour:
    """The trace's bad behaviour, from re-running it: the hang, else its first FN or FP (on
    `property_id` if given: the `verdict` given, else an FN before an FP)."""
    trace = orig.run(orig.body)
    bad = [v for v in Judge(orig.interface, properties).verdicts([trace])[0] if v["verdict"] in ("FN", "FP")]
    if property_id is not None:
        wanted = sorted((v for v in bad if v["property_id"] == property_id and verdict in (None, v["verdict"])),
                        key=lambda v: v["verdict"] != "FN")
        if not wanted:
            shown = sorted({f"{v['verdict']} on {v['property_id']}" for v in bad}) or ["none"]
            raise UntimelyError(f"trace {orig.trace_id} has no {verdict or 'FN or FP'} on {property_id!r} when "
                                f"re-run; it has: {', '.join(shown)}")
        return Behaviour(orig.sut, wanted[0]["verdict"], property_id)
    if trace.outcome == "hung":
        return Behaviour(orig.sut, "hung")
    if not bad:
        raise UntimelyError(f"trace {orig.trace_id} ({orig.sut}) shows no bad behaviour when re-run "
                            f"(outcome {trace.outcome}, no FN or FP); pick one from the bad_behaviours view")
    return Behaviour(orig.sut, bad[0]["verdict"], bad[0]["property_id"])


def shorter_sleeps(steps: list, shows) -> list:
    """Halve each sleep while the behaviour stays, down to MIN_SLEEP_S."""
    steps = list(steps)
    for i, step in enumerate(steps):
        while step.op == "sleep" and step.seconds / 2 >= MIN_SLEEP_S:
            shorter = replace(step, seconds=plausible(step.seconds / 2))
            if not shows(steps[:i] + [shorter] + steps[i + 1:]):
                break
            steps[i] = step = shorter
    return steps


def shrink(orig: Original, behaviour: Behaviour, properties: list[Property]) -> tuple[Script, int, bool]:
    """The shrunk script, the number of runs it took, and whether it went to its end: a budget
    spent once the script has shown the behaviour again gives the smallest one a run showed it with."""
    reproducer = Reproducer(orig, behaviour, properties)
    steps = list(parse(orig.body, f"trace {orig.trace_id}").steps)
    if not reproducer.shows(steps):
        raise UntimelyError(f"trace {orig.trace_id}'s script does not show the {behaviour} again when re-run "
                            f"with seed {orig.seed}; it cannot be shrunk")
    try:
        steps = shorter_sleeps(ddmin(steps, reproducer.shows), reproducer.shows)
    except BudgetSpent:
        return Script(tuple(reproducer.smallest), "shrunk").renumbered(), reproducer.runs, False
    awaited = {s.handle for s in steps if s.op == "wait"}
    tidy = [replace(s, comment="", handle=s.handle if s.op != "send" or s.handle in awaited else None)
            for s in steps]  # a handle no wait names should change nothing; checked by one more run
    try:
        shown = reproducer.shows(tidy)
    except BudgetSpent:
        return Script(tuple(steps), "shrunk").renumbered(), reproducer.runs, False
    return Script(tuple(tidy if shown else steps), "shrunk").renumbered(), reproducer.runs, True


def mission_file(out: Path, script_id: int) -> Path:
    return out / f"script-{script_id}.mission"


def store_shrink(con, orig: Original, behaviour: Behaviour, script: Script | None, runs: int,
                 ended: dict | None = None) -> int | None:
    """Stores a shrink as a campaign of kind "shrink": every run it made (orig.made, as traces linked
    to the trace it shrinks) and the shrunk script if it came out; returns the script's id. A shrink
    `interrupted` (Ctrl-C, SIGTERM) keeps the runs it made so far, marked so: it is tried again."""
    made = list(orig.made)  # a shrink interrupted in another thread may still add to it
    record = ShrinkRecord(op="shrink", max_delay=orig.max_delay, trace=orig.trace_id, sut=orig.sut,
                          seed=orig.seed, verdict=behaviour.verdict, property=behaviour.property_id,
                          steps_before=len(parse(orig.body).steps),
                          **({"steps_after": len(script.steps)} if script else {}), runs=runs,
                          **(ended or {}))
    if script is None and not made:
        return None
    with store.transaction(con):
        campaign_id = store.next_id(con, "campaigns", "campaign_id")
        store.add_campaign(con, campaign_id, str(orig.mission), orig.seed, record)
        store.add_shrink_runs(con, campaign_id, orig.trace_id, made)
        if script is None:
            return None
        script_id = store.next_id(con, "scripts", "script_id")
        store.add_scripts(con, [store.ScriptRow(script_id, campaign_id, "shrunk", script.render(),
                                                orig.script_id)])
    return script_id


def store_interrupted(con, orig: Original, behaviour: Behaviour) -> None:
    """Store the runs a shrink stopped by Ctrl-C or a signal made so far."""
    store_shrink(con, orig, behaviour, None, len(orig.made), {"interrupted": True})


def header(orig: Original, behaviour: Behaviour, script_id: int, path: Path, runs: int, steps_before: int) -> str:
    return (f"# Shrunk reproducer (script {script_id}): {behaviour}, from trace {orig.trace_id} "
            f"(script {orig.script_id}, {steps_before} steps) in {runs} runs.\n"
            f"# Replay: {replay_command(orig, path)}\n")


def replay_command(orig: Original, path: Path) -> str:
    """The command that replays a shrunk file as written from any folder: the installed `untimely`,
    absolute paths, the target named by its interface (run takes the world and SUTs beside it), an
    external SUT at the time scale it ran at."""
    scale = orig.external[orig.sut].time_scale if orig.sut in orig.external else None
    words = ["untimely", "run", str(path.resolve()), "--sut", orig.sut, "--seed", str(orig.seed),
             "--max-delay", f"{orig.max_delay:g}", "--interface", str((orig.mission / INTERFACE_FILE).resolve()),
             *(["--time-scale", f"{scale:g}"] if scale is not None else [])]
    return shlex.join(words)


def write_mission(out: Path, orig: Original, behaviour: Behaviour, script_id: int, body: str, runs: int) -> Path:
    path = mission_file(make_folder(out, "the shrunk scripts"), script_id)
    try:
        path.write_text(header(orig, behaviour, script_id, path, runs, len(parse(orig.body).steps)) + body)
    except OSError as e:
        raise UntimelyError(f"cannot write {str(path)!r}: {e.strerror}; the shrunk script is stored as script "
                            f"{script_id}: pass a writable --out and shrink again to write it") from None
    return path


@dataclass
class Shrunk:
    """What a shrink came to: the shrunk script and the runs it took, or why it failed; the trace it
    shrank holds every run it made (orig.made)."""
    orig: Original
    script: Script | None
    runs: int
    seconds: float
    error: str | None = None
    whole: bool = True  # False: the budget was spent before the shrink's end (the smallest shown so far)


def shrunk(orig: Original, behaviour: Behaviour, properties: list[Property]) -> Shrunk:
    started = time.perf_counter()
    try:
        script, runs, whole = shrink(orig, behaviour, properties)
    except UntimelyError as e:
        return Shrunk(orig, None, 0, time.perf_counter() - started, str(e))
    return Shrunk(orig, script, runs, time.perf_counter() - started, whole=whole)


def stored(con, behaviour: Behaviour, result: Shrunk, out: Path) -> str:
    """Store a shrink (its runs, its script) and write its .mission file; one line saying what came out."""
    orig, script = result.orig, result.script
    script_id = store_shrink(con, orig, behaviour, script, result.runs, None if result.whole else {"budget_spent": True})
    if script is None:
        return f"{behaviour}: not shrunk: {result.error}"
    path = write_mission(out, orig, behaviour, script_id, script.render(), result.runs)
    cut = "" if result.whole else " (the budget ran out: the smallest script a run showed it with)"
    return (f"{behaviour}: trace {orig.trace_id} shrunk from {len(parse(orig.body).steps)} to "
            f"{len(script.steps)} steps in {result.runs} runs, {result.seconds:.1f} s{cut} -> {path}")


def default_out(db: str) -> Path:
    return Path(db).resolve().parent / "shrunk"
