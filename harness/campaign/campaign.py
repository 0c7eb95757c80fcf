"""`python -m harness campaign`: golden + seeded mutants on every variant, in parallel, resumable.

Everything a campaign produces is a function of its arguments and mission files, never of
scheduling (harness.campaign.runs: trace ids and seeds).

Nothing lost, nothing doubled: the golden runs first on every variant (so a variant or world
that cannot be built is reported before anything is stored); the campaign, its scripts and
those golden traces are then committed together, and later traces in batches (runs.Batches). A
campaign killed at any moment restarts from what its store holds: the runs whose trace ids are
missing, which are at most the one batch it had not committed. Only this process writes to the
store; workers return traces to it.
"""
from __future__ import annotations

import os
import sys
import time
from contextlib import ExitStack

from harness import DEFAULT_MISSION_DIR, store
from harness.analysis import analyzer
from harness.analysis.summary import analysis_summary
from harness.analysis.provenance import last_epsilon
from harness.campaign import budget, budgeted, focused_summary, representatives, sharding, shrink
from harness.campaign.config import campaign_config, find_campaign
from harness.campaign.context import CampaignContext
from harness.campaign.request import CampaignRequest
from harness.campaign.runs import Batches, Tally, pending_tasks, tasks
from harness.campaign.slots import campaign_slots
from harness.mutator import strategies
from harness.mutator.operators import Mutant
from harness.progress import Progress
from harness.store import campaign_reads
from harness.sut.executive import run_script
from harness.dispatch.executor import open_executor
from harness.sut.external.kept import kept_adapters
from harness.dispatch import transport
from harness.dispatch.description import script_label
from harness.schema import cut
from harness.store.reads import observed_events
from harness.store.sql import render_query
from harness.files import read_text
from harness.target.mission import MISSING, PROPERTIES_FILE, load_mission
from harness.target.script import script_of
from harness.trace import Trace
from harness.textable import real_time_factor

RUN_WALL_LIMIT_S = 600.0  # of a simulated run; a real-time one has the executive's watchdogs
REALTIME_WALL_LIMIT_S = 3 * 3600.0
SHOW_GENERATION = 2_000  # from this many mutants on, generating them shows its progress


def _create(ctx: CampaignContext, golden_id: int, mutants: list[Mutant], tally: Tally) -> int:
    """The golden runs on every variant, then the campaign, its scripts and those traces, stored together."""
    config, golden_runs, golden_text = ctx.config, [], ctx.golden_text

    def keep(task, trace):
        golden_runs.append((task, trace))
        tally.count(trace)
    ctx.executor.run_all(sharding.part(tasks([(golden_id, golden_text)], golden_id, config), config.shard), keep)
    with store.transaction(ctx.con):
        campaign_id = store.next_id(ctx.con, "campaigns", "campaign_id")
        store.add_campaign(ctx.con, campaign_id, config.mission, config.seed, config)
        store.add_reply_codes(ctx.con, ctx.interface)
        store.place(ctx.con, "variant_positions", "sut", config.sut)
        store.add_scripts(ctx.con, [store.ScriptRow(golden_id, campaign_id, "golden", golden_text)] + [
            store.ScriptRow(golden_id + n, campaign_id, "mutant", m.body, golden_id, m.operations, m.valid,
                            m.invalid_reason) for n, m in enumerate(mutants, 1)])
        store.insert_traces(ctx.con, campaign_id, [(task.trace_id, task.script_id, trace, None)
                                                   for task, trace in golden_runs])
    ctx.campaign_id = campaign_id
    return campaign_id


def _generate(ctx: CampaignContext, golden_id: int) -> list[Mutant]:
    """The campaign's mutants (harness.mutator.strategies); a long random generation shows its progress."""
    config = ctx.config

    def run_golden() -> Trace:  # on the first variant
        return ctx.setup.run(tasks([(golden_id, ctx.golden.render())], golden_id, config)[0], ctx.interface, 0)
    progress = Progress(config.mutants, unit="mutants") if config.mutants >= SHOW_GENERATION else None
    mutants = []
    for mutant in strategies.mutants(config, ctx.golden, ctx.interface, ctx.properties, run_golden,
                                     name=lambda n: script_label(golden_id + n)):
        mutants.append(mutant)
        if progress:
            progress.advance()
    if progress:
        progress.close()
    return mutants


def summary(con, campaign_id: int, tally: Tally) -> str:
    scripts, valid, distinct = campaign_reads.script_counts(con, campaign_id)
    lines = [f"scripts   {scripts}: golden + {scripts - 1} mutants, {valid - 1} valid, "
             f"{scripts - valid} invalid (stored, not run), {distinct} distinct bodies"]
    for sut, runs, completed, hung, crashed, sim in con.execute(
            render_query("campaign_runs"), {"campaign": campaign_id}).fetchall():
        lines.append(f"{sut:<9} {runs} runs: {completed} completed, {hung} hung, {crashed} crashed; "
                     f"{sim:,.0f} simulated s")
    lines += [f"crashed   {runs} run(s) on {sut}: {reason}" for campaign, sut, reason, runs in
              con.execute(render_query("crash_reasons")).fetchall() if campaign == campaign_id]
    wall = time.monotonic() - tally.start
    if tally.runs:
        lines.append(f"this run  {tally.runs} runs in {wall:.1f} s wall ({tally.runs / wall:.1f} runs/s), "
                     f"{tally.sim_s:,.0f} simulated s: {real_time_factor(tally.sim_s, wall)} real time")
    return "\n".join(lines)


def _judged(ctx: CampaignContext, show: bool = True) -> None:
    """Verdicts for every stored trace (new traces, or an invocation stopped while judging)."""
    if not analyzer.judges_every_trace(ctx.con):
        epsilon = last_epsilon(ctx.con)  # a resumed campaign keeps the epsilon its verdicts were made with
        analyzer.materialise(ctx.con, ctx.properties, epsilon, ctx.interface, ctx.mission / PROPERTIES_FILE)
        if show:
            print(f"verdicts  materialised for every trace of {ctx.db} (epsilon {epsilon:g} s)\n")
            for failure in analyzer.failed_oracles(ctx.con):
                print(failure + "\n")
            print(analysis_summary(ctx.con, epsilon))


def _focused(ctx: CampaignContext, start: float) -> None:
    """A focused campaign: the golden on every variant, then tests until it stops (harness.campaign.budgeted)."""
    con, config = ctx.con, ctx.config
    if ctx.campaign_id is None:
        tally = Tally(Progress(len(config.sut)), start)
        _create(ctx, store.next_id(con, "scripts", "script_id"), [], tally)
        tally.progress.close()
    golden_id = campaign_reads.golden_script_id(con, ctx.campaign_id)
    golden_trace = Trace(config.sut[0], 0, events=observed_events(con, tasks([(golden_id, "")], golden_id,
                                                                               config)[0].trace_id))
    plan = strategies.plan(config, ctx.golden, ctx.interface, ctx.properties, golden_trace)
    _judged(ctx, show=False)  # what the stored traces found
    tally = Tally(budget.progress(con, ctx.campaign_id, config.budget_s), start)
    with Batches(con, ctx.campaign_id, tally, set(config.external)) as batches, \
            campaign_slots(ctx) as slots:
        focused_run = budgeted.FocusedRun(ctx, plan, golden_id, batches, slots)
        try:
            reason = focused_run.run()
        except KeyboardInterrupt:  # Ctrl-C or a stop signal: what the running shrinks made is stored
            focused_run.store_interrupted()
            raise
    tally.progress.close()
    print(summary(con, ctx.campaign_id, tally))
    print(focused_summary.stopped_line(focused_run, reason))
    _judged(ctx)
    print("\nfindings (view findings):\n" + focused_summary.findings_table(con))


def main(request: CampaignRequest, runner=None) -> int:
    """`runner` replaces harness.sut.executive.run_script (tests inject failing ones)."""
    target = load_mission(request.mission)
    golden_text = read_text(target.golden_file, MISSING)
    golden = script_of(golden_text, target.golden_file, target.interface)
    config = campaign_config(request, target, golden)
    properties = target.properties()  # refused before anything starts
    external = config.external
    setup = transport.setup(runner or run_script, target.interface_file, target.world_file, request.max_delay,
                  external, REALTIME_WALL_LIMIT_S if external else RUN_WALL_LIMIT_S)
    # A real-time run mostly waits: its slots may outnumber the cores.
    jobs = request.jobs or max([len(os.sched_getaffinity(0))] + [s.slots for s in external.values()])
    with ExitStack() as stack:
        executor = stack.enter_context(open_executor(request.cluster, setup, jobs))
        stack.enter_context(kept_adapters())
        ctx = CampaignContext(con=store.connect(request.db), db=request.db, target=target, golden=golden,
                              golden_text=golden_text, properties=properties, config=config, setup=setup,
                              executor=executor, jobs=jobs, cluster=request.cluster,
                              shrink_to=shrink.default_out(request.db) if request.shrink else None,
                              allow_code_change=request.allow_code_change)
        return _run(ctx)


def _warn_of_a_default_target(ctx: CampaignContext) -> None:
    """An external SUT every run of which crashed on the default target (Dala) was likely made for
    another one: say so, with its first error, rather than let Dala's properties judge it."""
    if ctx.mission.resolve() != DEFAULT_MISSION_DIR.resolve():
        return
    for sut, error in campaign_reads.all_crashed(ctx.con, ctx.campaign_id):
        if sut in ctx.config.external:
            print(f"every run of {sut} crashed on the default target {DEFAULT_MISSION_DIR} (first: "
                  f"{cut(error or 'no reason given')}); if {sut} is made for another target, pass --mission "
                  "FOLDER with its interface.toml and golden.mission", file=sys.stderr)


def _tally(ctx: CampaignContext, start: float) -> tuple[Tally, list]:
    """This invocation's runs: a new campaign's (its golden runs made and stored), or a resumed one's."""
    con, config, variants = ctx.con, ctx.config, len(ctx.config.sut)
    if ctx.campaign_id is None:
        golden_id = store.next_id(con, "scripts", "script_id")
        mutants = _generate(ctx, golden_id)
        runs = variants * (1 + sum(m.valid for m in mutants))
        tally = Tally(Progress(sharding.share(runs, config.shard)), start)
        _create(ctx, golden_id, mutants, tally)
        return tally, pending_tasks(con, ctx.campaign_id, config)
    pending = pending_tasks(con, ctx.campaign_id, config)
    total = sharding.share(variants * len(campaign_reads.valid_scripts(con, ctx.campaign_id)), config.shard)
    if pending:
        print(f"resuming campaign {ctx.campaign_id} in {ctx.db}: {total - len(pending)} of {total} runs "
              f"stored, {len(pending)} to go", file=sys.stderr)
    else:
        print(f"campaign {ctx.campaign_id} in {ctx.db} is complete ({total} runs stored); nothing to run")
    return Tally(Progress(total, total - len(pending)), start), pending


def _run(ctx: CampaignContext) -> int:
    ctx.campaign_id = find_campaign(ctx.con, ctx.config, ctx.db, ctx.allow_code_change)
    start = time.monotonic()
    if ctx.config.strategy == "focused":
        _focused(ctx, start)
        return 0
    tally, pending = _tally(ctx, start)
    if pending:
        with Batches(ctx.con, ctx.campaign_id, tally, set(ctx.config.external)) as batches:
            ctx.executor.run_all(pending, batches.add)
    if tally.runs:
        tally.progress.close()
    print(summary(ctx.con, ctx.campaign_id, tally))
    _warn_of_a_default_target(ctx)
    _judged(ctx)
    if ctx.shrink_to:
        print("\nshrunk reproducers, one per distinct bad behaviour (view bad_behaviours):")
        representatives.representatives(ctx, lambda line: print(line, flush=True))
    return 0
