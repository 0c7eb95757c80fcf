"""`python -m harness campaign`: golden + seeded mutants on every variant, in parallel, resumable.

Everything a campaign produces is a function of its arguments and mission files, never of
scheduling: the mutants come from the campaign seed; run (script, variant) gets the trace id
(script_id - 1) * len(variants) + variant index + 1 and a seed hashed from the campaign seed,
the script's number in the campaign (golden 0, mutant n) and the variant's name.

Nothing lost, nothing doubled: the golden runs first on every variant (so a variant or world
that cannot be built is reported before anything is stored); the campaign, its scripts and
those golden traces are then committed together, and later traces in batches (Batches). A
campaign killed at any moment restarts from what its store holds: the runs whose trace ids are
missing, which are at most the one batch it had not committed. Only this process writes to the
store; workers return traces to it.
"""
from __future__ import annotations

import hashlib
import os
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from harness import DEFAULT_MISSION_DIR, store
from harness.schema import cut
from harness.analysis import analyzer
from harness.campaign import budgeted, representatives, sharding, shrink
from harness.campaign.config import campaign_config, find_campaign
from harness.campaign.request import CampaignRequest
from harness.campaign.slots import campaign_slots
from harness.errors import StoreError
from harness.run.executive import run_script
from harness.files import read_text
from harness.target.interface import Interface
from harness.target.mission import load_mission
from harness.mutator import strategies
from harness.mutator.operators import Mutant
from harness.store.reads import observed_events
from harness.store.sql import render_query
from harness.progress import Progress
from harness.analysis.provenance import last_epsilon
from harness.run.external.definitions import ExternalSut
from harness.run.external.kept import kept_adapters
from harness.trace import Trace
from harness.run.workers import Pool, Setup, Task, script_label

RUN_WALL_LIMIT_S = 600.0  # of a simulated run; a real-time one has the executive's watchdogs
REALTIME_WALL_LIMIT_S = 3 * 3600.0
# A transaction per simulated run cost a quarter of a campaign; a killed campaign re-runs at most
# one batch: up to BATCH_RUNS runs, or those that came in during BATCH_S (a couple of seconds' work).
BATCH_RUNS = 64
BATCH_S = 2.0
SHOW_GENERATION = 2_000  # from this many mutants on, generating them shows its progress


def run_seed(campaign_seed: int, script_number: int, sut: str) -> int:
    digest = hashlib.sha256(f"{campaign_seed}:{script_number}:{sut}".encode()).digest()
    return int.from_bytes(digest[:8], "big") >> 1  # fits a signed BIGINT


def _tasks(scripts: list[tuple[int, str]], golden_id: int, config: dict) -> list[Task]:
    n = len(config["sut"])
    return [Task(sharding.trace_id(script_id, v, n), script_id, sut,
                 run_seed(config["seed"], script_id - golden_id, sut), body)
            for script_id, body in scripts for v, sut in enumerate(config["sut"])]


@dataclass
class Session:
    """What this invocation ran (a resumed campaign's earlier runs are not counted)."""
    progress: Progress
    start: float
    runs: int = 0
    sim_s: float = 0.0

    def count(self, trace: Trace) -> None:
        self.runs += 1
        self.sim_s += trace.sim_s
        self.progress.advance()


def _create(con, config: dict, golden_id: int, golden_text: str, mutants: list[Mutant],
            interface: Interface, run_tasks, session: Session) -> int:
    golden_runs = []

    def keep(task, trace):
        golden_runs.append((task, trace))
        session.count(trace)
    run_tasks(sharding.part(_tasks([(golden_id, golden_text)], golden_id, config), config["shard"]), keep)
    with store.transaction(con):
        campaign_id = store.next_id(con, "campaigns", "campaign_id")
        store.add_campaign(con, campaign_id, config["mission"], config["seed"], config)
        store.add_reply_codes(con, interface)
        store.place(con, "variant_positions", "sut", config["sut"])
        store.add_scripts(con, [store.ScriptRow(golden_id, campaign_id, "golden", golden_text)] + [
            store.ScriptRow(golden_id + n, campaign_id, "mutant", m.body, golden_id, m.operations, m.valid,
                            m.invalid_reason) for n, m in enumerate(mutants, 1)])
        store.insert_traces(con, campaign_id, [(task.trace_id, task.script_id, trace, None)
                                               for task, trace in golden_runs])
    return campaign_id


def _generate(config: dict, golden, interface: Interface, properties, run_golden,
              golden_id: int) -> list[Mutant]:
    """The campaign's mutants (harness.mutator.strategies); a long random generation shows its progress."""
    progress = Progress(config["mutants"], unit="mutants") if config["mutants"] >= SHOW_GENERATION else None
    mutants = strategies.generate(config, golden, interface, properties, run_golden=run_golden,
                                  name=lambda n: script_label(golden_id + n),
                                  on_mutant=progress.advance if progress else lambda: None)
    if progress:
        progress.close()
    return mutants


def pending_tasks(con, campaign_id: int, config: dict) -> list[Task]:
    scripts = con.execute("select script_id, body from scripts where campaign_id = ? and valid "
                          "order by script_id", [campaign_id]).fetchall()
    golden_id = scripts[0][0]
    tasks = _tasks(scripts, golden_id, config)
    owners = dict(con.execute("select trace_id, campaign_id from traces where trace_id >= ?",
                              [tasks[0].trace_id]).fetchall())
    for task in tasks:
        if owners.get(task.trace_id, campaign_id) != campaign_id:
            raise StoreError(f"trace id {task.trace_id}, which campaign {campaign_id} needs for script "
                             f"{task.script_id} on {task.sut}, is taken by campaign {owners[task.trace_id]}; "
                             "add ad-hoc runs to another --db while a campaign is unfinished")
    return [t for t in sharding.part(tasks, config["shard"]) if t.trace_id not in owners]


class Batches:
    """Traces committed together: when BATCH_RUNS have come in, when the oldest has waited BATCH_S,
    at once for a real-time run (it took wall-clock time to make), and at the end of the session.
    A session ended by an exception (Ctrl-C included) still commits the traces it holds."""

    def __init__(self, con, campaign_id: int, session: Session, realtime: set[str]):
        self.con, self.campaign_id, self.session, self.realtime = con, campaign_id, session, realtime
        self.held: list[tuple[int, int, Trace, None]] = []
        self.oldest = 0.0

    def add(self, task: Task, trace: Trace) -> None:
        if not self.held:
            self.oldest = time.monotonic()
        self.held.append((task.trace_id, task.script_id, trace, None))
        self.session.count(trace)
        if (len(self.held) >= BATCH_RUNS or time.monotonic() - self.oldest >= BATCH_S
                or task.sut in self.realtime):
            self.commit()

    def commit(self) -> None:
        try:
            if self.held:
                with store.transaction(self.con):
                    store.insert_traces(self.con, self.campaign_id, self.held)
        except BaseException:  # a stop signal as the commit returns: stored, so not to be stored again
            if self.con.execute("select count(*) from traces where trace_id = ?", [self.held[0][0]]).fetchall()[0][0]:
                self.held = []
            raise
        self.held = []

    def __enter__(self) -> "Batches":
        return self

    def __exit__(self, *_exception) -> None:
        self.commit()


def summary(con, campaign_id: int, session: Session) -> str:
    scripts, valid, distinct = con.execute(
        "select count(*), count(*) filter (where valid), count(distinct body) from scripts "
        "where campaign_id = ?", [campaign_id]).fetchone()
    lines = [f"scripts   {scripts}: golden + {scripts - 1} mutants, {valid - 1} valid, "
             f"{scripts - valid} invalid (stored, not run), {distinct} distinct bodies"]
    for sut, runs, completed, hung, crashed, sim in con.execute(
            render_query("campaign_runs"), {"campaign": campaign_id}).fetchall():
        lines.append(f"{sut:<9} {runs} runs: {completed} completed, {hung} hung, {crashed} crashed; "
                     f"{sim:,.0f} simulated s")
    lines += [f"crashed   {runs} run(s) on {sut}: {reason}" for campaign, sut, reason, runs in
              con.execute(render_query("crash_reasons")).fetchall() if campaign == campaign_id]
    wall = time.monotonic() - session.start
    if session.runs:
        lines.append(f"this run  {session.runs} runs in {wall:.1f} s wall ({session.runs / wall:.1f} runs/s), "
                     f"{session.sim_s:,.0f} simulated s: {session.sim_s / wall:,.0f}x real time")
    return "\n".join(lines)


@contextmanager
def _backend(cluster: str | None, setup: Setup, jobs: int):
    """`run_tasks(tasks, on_trace)` on the local pool, or on a checked Dask cluster."""
    if not cluster:
        with Pool(setup, jobs) as pool:
            yield pool.run_all
        return
    from harness.run import cluster as dask_cluster  # Dask is an optional dependency
    with dask_cluster.connect(cluster, setup, jobs) as backend:
        yield backend.run_all


def _judged(con, db, properties, interface, mission, show: bool = True) -> None:
    """Verdicts for every stored trace (new traces, or a session stopped while judging)."""
    if not analyzer.judges_every_trace(con):
        epsilon = last_epsilon(con)  # a resumed campaign keeps the epsilon its verdicts were made with
        analyzer.materialise(con, properties, epsilon, interface, mission / "properties.toml")
        if show:
            print(f"verdicts  materialised for every trace of {db} (epsilon {epsilon:g} s)\n")
            for failure in analyzer.failed_oracles(con):
                print(failure + "\n")
            print(analyzer.summary(con, epsilon))


def _focused(args, con, campaign_id, config, mission, interface, golden, properties, run_tasks, start,
             setup: Setup, jobs: int) -> None:
    """A focused campaign: the golden on every variant, then tests until it stops (harness.campaign.budgeted)."""
    if campaign_id is None:
        golden_id = store.next_id(con, "scripts", "script_id")
        session = Session(Progress(len(config["sut"])), start)
        campaign_id = _create(con, config, golden_id, read_text(mission / "golden.mission"), [], interface,
                              run_tasks, session)
        session.progress.close()
    golden_id = con.execute("select min(script_id) from scripts where campaign_id = ?", [campaign_id]).fetchone()[0]
    golden_trace = Trace(config["sut"][0], 0, events=observed_events(con, _tasks([(golden_id, "")], golden_id,
                                                                                    config)[0].trace_id))
    plan = strategies.plan(config, golden, interface, properties, golden_trace)
    _judged(con, args.db, properties, interface, mission, show=False)  # what the stored traces found
    session = Session(Progress(len(config["sut"]) * len(plan.aims), unit="runs"), start)
    out = shrink.default_out(args.db) if args.shrink else None
    with Batches(con, campaign_id, session, set(config["external"])) as batches, \
            campaign_slots(config, setup, interface, jobs, args.cluster) as slots:
        focused_run = budgeted.FocusedRun(con, campaign_id, config, plan, golden_id,
                                          lambda script_id, body: _tasks([(script_id, body)], golden_id, config),
                                          run_tasks, batches, properties, interface, out, print, slots)
        try:
            reason = focused_run.run()
        except KeyboardInterrupt:  # Ctrl-C or a stop signal: what the running shrinks made is stored
            focused_run.store_interrupted()
            raise
    session.progress.close()
    print(summary(con, campaign_id, session))
    print(budgeted.stopped_line(focused_run, reason))
    _judged(con, args.db, properties, interface, mission)
    print("\nfindings (view findings):\n" + budgeted.findings_table(con))


def main(args: CampaignRequest, runner=None) -> int:
    """`runner` replaces harness.run.executive.run_script (tests inject failing ones)."""
    config = campaign_config(args)
    target = load_mission(args.mission)
    mission, interface = target.folder, target.interface
    golden, properties = target.golden(), target.properties()
    external = {name: ExternalSut(**spec) for name, spec in config["external"].items()}
    setup = Setup(runner or run_script, target.interface_file, target.world_file, args.max_delay,
                  external, REALTIME_WALL_LIMIT_S if external else RUN_WALL_LIMIT_S)
    # A real-time run mostly waits: its slots may outnumber the cores.
    jobs = args.jobs or max([len(os.sched_getaffinity(0))] + [s.slots for s in external.values()])
    with _backend(args.cluster, setup, jobs) as run_tasks, kept_adapters():
        return _run(args, config, mission, interface, golden, properties, setup, jobs, run_tasks)


def _warn_of_a_default_target(con, campaign_id: int, mission: Path, config: dict) -> None:
    """An external SUT every run of which crashed on the default target (Dala) was likely made for
    another one: say so, with its first error, rather than let Dala's properties judge it."""
    if mission.resolve() != DEFAULT_MISSION_DIR.resolve():
        return
    for sut, error in con.execute("""select sut, arg_min(error, trace_id) from traces where campaign_id = ?
                                     group by sut having bool_and(outcome = 'crashed')""", [campaign_id]).fetchall():
        if sut in config["external"]:
            print(f"every run of {sut} crashed on the default target {DEFAULT_MISSION_DIR} (first: "
                  f"{cut(error or 'no reason given')}); if {sut} is made for another target, pass --mission "
                  "FOLDER with its interface.toml and golden.mission", file=sys.stderr)


def _run(args, config, mission, interface, golden, properties, setup, jobs, run_tasks) -> int:
    con = store.connect(args.db)
    campaign_id = find_campaign(con, config, args.db)
    variants = len(config["sut"])
    start = time.monotonic()
    if config["strategy"] == "focused":
        _focused(args, con, campaign_id, config, mission, interface, golden, properties, run_tasks, start,
                 setup, jobs)
        return 0
    if campaign_id is None:
        golden_id = store.next_id(con, "scripts", "script_id")
        golden_run = _tasks([(golden_id, golden.render())], golden_id, config)[0]  # on the first variant
        mutants = _generate(config, golden, interface, properties, lambda: setup.run(golden_run, interface, 0),
                            golden_id)
        runs = variants * (1 + sum(m.valid for m in mutants))
        session = Session(Progress(sharding.share(runs, config["shard"])), start)
        campaign_id = _create(con, config, golden_id, read_text(mission / "golden.mission"), mutants,
                              interface, run_tasks, session)
        pending = pending_tasks(con, campaign_id, config)
    else:
        pending = pending_tasks(con, campaign_id, config)
        total = sharding.share(variants * con.execute("select count(*) from scripts where campaign_id = ? and valid",
                                                      [campaign_id]).fetchone()[0], config["shard"])
        session = Session(Progress(total, total - len(pending)), start)
        if pending:
            print(f"resuming campaign {campaign_id} in {args.db}: {total - len(pending)} of {total} runs "
                  f"stored, {len(pending)} to go", file=sys.stderr)
        else:
            print(f"campaign {campaign_id} in {args.db} is complete ({total} runs stored); nothing to run")
    if pending:
        with Batches(con, campaign_id, session, set(config["external"])) as batches:
            run_tasks(pending, batches.add)
    if session.runs:
        session.progress.close()
    print(summary(con, campaign_id, session))
    _warn_of_a_default_target(con, campaign_id, mission, config)
    _judged(con, args.db, properties, interface, mission)
    if args.shrink:
        print("\nshrunk reproducers, one per distinct bad behaviour (view bad_behaviours):")
        for line in representatives.representatives(con, properties, shrink.default_out(args.db), setup.external,
                                                    setup.runner, 1 if setup.external else jobs):  # external: one at a time
            print(line, flush=True)
    return 0
