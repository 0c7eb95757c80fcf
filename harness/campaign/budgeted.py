"""A focused campaign's runs (`campaign --strategy focused [--budget D] [--shrink]`): tests made,
run and judged ROUND_TESTS at a time, in the plan's order (harness.mutator.focused), on every
variant the stopping rule has not ended yet, within the budget (harness.campaign.budget). With
--shrink, each new finding's first trace is shrunk as soon as it shows, its runs within the
budget too.

Resumable and a function of the arguments only: rounds are fixed (not a function of --jobs), a
variant's rule is applied to its tests in order, and a resumed campaign replays its stored
traces' findings (view trace_findings) through the same rounds before it runs anything new.
Every run is a stored trace, shrink runs included (table shrink_runs): what the campaign has
spent is the sum of their mission seconds, read from the store when it starts or resumes and
after every round (sql/report/campaign_spent.sql). The table campaign_budgets records the budget,
the rule, the shrink runs' share of that sum and why the campaign stopped.
"""
from __future__ import annotations

import json
import threading
from concurrent.futures import Future
from contextlib import nullcontext
from dataclasses import dataclass, field, fields

from harness import store
from harness.campaign import runs, shrink
from harness.campaign.budget import RULE, Budget, VariantState
from harness.campaign.context import CampaignContext
from harness.campaign.slots import Slots
from harness.store.budgets import BudgetRow, record_budget
from harness.store.record import ShrinkRecord, records
from harness.store.scripts import ScriptRow, add_scripts
from harness.store.sql import render_query
from harness.analysis.judge import Judge
from harness.errors import UntimelyError
from harness.mutator.focused import Plan, bound_s
from harness.target.script import parse
from harness.dispatch.workers import Task
from harness.textable import format_table

ROUND_TESTS = 8
PATIENCE = 40  # tests per variant without anything new, once every aim was exercised (budget.RULE)


class BudgetSpent(UntimelyError):
    """A shrink run that would not fit in the budget."""

    def __init__(self, message: str = "the budget is spent"):
        super().__init__(message)


@dataclass
class MeteredOriginal(shrink.Original):
    """A trace to shrink whose re-runs are counted against the campaign's budget (shrinks run
    side by side: one lock keeps the budget's account), each on a slot taken for that run alone."""
    budget: Budget | None = None
    bound: float = 0.0  # no candidate outlasts the original script's bound
    account: threading.Lock = field(default_factory=threading.Lock)  # shared by the shrinks of a campaign
    slots: Slots | None = None  # None: in process, on slot 0

    def run(self, body: str, runner=None):
        with self.account:
            if not self.budget.fits(self.bound):
                raise BudgetSpent()
            self.budget.spent_s += self.bound  # reserved until the run says what it took
        with self.slots.taken() if self.slots else nullcontext(self.slot) as self.slot:
            trace = super().run(body, runner) if runner else super().run(body)
        with self.account:
            self.budget.spent_s += trace.sim_s - self.bound
        return trace


def record(con, campaign_id: int, budget: Budget, shrink_s: float, tests: int, stopped: str | None) -> None:
    record_budget(con, BudgetRow(campaign_id, budget.limit_s, RULE.format(patience=PATIENCE), shrink_s, tests, stopped))


class FocusedRun:
    def __init__(self, ctx: CampaignContext, plan: Plan, golden_id: int, batches, slots: Slots | None = None):
        con, campaign_id, config = ctx.con, ctx.campaign_id, ctx.config
        self.con, self.campaign_id, self.config, self.plan = con, campaign_id, config, plan
        self.golden_id, self.batches, self.slots = golden_id, batches, slots
        self.run_tasks = slots.run_all if slots else ctx.executor.run_all
        self.properties, self.interface, self.shrink_to = ctx.properties, ctx.interface, ctx.shrink_to
        self.judge = Judge(ctx.interface, ctx.properties)
        self.account = threading.Lock()  # the budget's, shared with shrinks running in the background
        self.shrinking: list[tuple[shrink.Behaviour, MeteredOriginal, Future]] = []
        self.state = {sut: VariantState() for sut in config.sut}
        (self.stopped,) = con.execute("select stopped from campaign_budgets where campaign_id = ?",
                                      [campaign_id]).fetchone() or (None,)
        self.budget, self.shrink_s = Budget(config.budget_s), 0.0
        self.account_from_store()
        self.scripts = {json.loads(m)[0]["test"]: (script_id, body) for script_id, m, body in con.execute(
            "select script_id, mutations, body from scripts where campaign_id = ? and kind = 'mutant'",
            [campaign_id]).fetchall()}
        self.shown = {}  # trace_id -> findings, of the traces stored before this session
        for trace_id, property_id, kind in con.execute(
                "select trace_id, property_id, kind from trace_findings join traces using (trace_id) "
                "where campaign_id = ?", [campaign_id]).fetchall():
            self.shown.setdefault(trace_id, set()).add((property_id, kind))
        self.stored = {t for (t,) in con.execute("select trace_id from traces where campaign_id = ?",
                                                 [campaign_id]).fetchall()}
        # what was shrunk, or tried (its runs are stored): a resumed campaign does not try again, unless
        # the campaign was stopped while it ran
        self.shrunk = {(s.sut, s.verdict, s.property) for _, _, s in records(con, ShrinkRecord) if not s.interrupted}

    def account_from_store(self) -> None:
        """What the campaign has spent: the mission seconds of its stored traces and shrink runs
        (called with no shrink running: a running shrink's runs are counted, but not yet stored)."""
        traces_s, self.shrink_s = self.con.execute(render_query("campaign_spent"),
                                                   {"campaign": self.campaign_id}).fetchone()
        with self.account:
            self.budget.spent_s = traces_s + self.shrink_s

    def script(self, n: int) -> tuple[int, str]:
        """Test n's (script_id, body), made and stored the first time (shrunk scripts and the
        trace ids of shrink runs shift later tests' script ids)."""
        if n not in self.scripts:
            script_id = store.next_script_id(self.con, len(self.config.sut))
            test = self.plan.test(n, f"script {script_id}")
            if not test.valid:
                raise UntimelyError(f"focused test {n} is not a valid script ({test.invalid_reason}); "
                                    "the golden script or the properties name services the interface lacks")
            with store.transaction(self.con):
                add_scripts(self.con, [ScriptRow(script_id, self.campaign_id, "mutant", test.body, self.golden_id,
                                                 test.operations)])
            self.scripts[n] = (script_id, test.body)
        return self.scripts[n]

    def run(self) -> str:
        """Runs rounds until the campaign stops; returns why (rule, budget or tests)."""
        if self.stopped:
            print(f"campaign {self.campaign_id} is complete; nothing to run")
            return self.stopped
        n, cap = 0, self.config.mutants
        while True:
            active = [s for s in self.config.sut if not self.state[s].done]
            if not active:
                return self._stop("rule", n)
            if n >= cap:
                return self._stop("tests", n)
            tests = [(k, [t for t in runs.tasks([self.script(k)], self.golden_id, self.config) if t.sut in active])
                     for k in range(n, min(n + ROUND_TESTS, cap))]
            admitted, reserved, cut = [], 0.0, None
            for k, tasks in tests:
                for task in tasks:
                    if task.trace_id in self.stored:
                        continue
                    bound = bound_s(parse(task.body))
                    if not self.budget.fits(reserved + bound):
                        cut = k
                        break
                    reserved += bound
                    admitted.append(task)
                if cut is not None:
                    break
            fresh = {}
            if admitted:
                self.run_tasks(admitted, lambda task, trace: (fresh.__setitem__(task.trace_id, trace),
                                                              self.batches.add(task, trace)))
                self.batches.commit()
                traces = sorted(fresh.items())
                for (trace_id, trace), found in zip(traces, self.judge.findings([t for _, t in traces])):
                    self.shown[trace_id] = found
                    with self.account:
                        self.budget.spent_s += trace.sim_s
                self.stored |= set(fresh)
            found = []
            for k, tasks in tests:
                if k == cut:
                    break
                for task in tasks:
                    new = self.state[task.sut].record(self.shown.get(task.trace_id, set()), len(self.plan.aims),
                                                      PATIENCE)
                    found += [(task, property_id, kind) for property_id, kind in sorted(new, key=str)]
                n = k + 1
            self._shrink(found)
            if not self.shrinking:
                self.account_from_store()
            record(self.con, self.campaign_id, self.budget, self.shrink_s, n, None)
            if cut is not None:
                return self._stop("budget", n)

    def _shrink(self, found: list[tuple[Task, str | None, str]]) -> None:
        """Says what a round found; shrinks each new finding from the trace that showed it, at once
        in process, in the background on external SUTs; stores the shrinks done, in order."""
        for task, property_id, kind in found:
            what = f"{kind} on {property_id}" if property_id else kind
            print(f"found     {task.sut}: {what} (trace {task.trace_id}, script {task.script_id})")
            if self.shrink_to is None or kind == "crashed" or (task.sut, kind, property_id) in self.shrunk:
                continue
            orig = shrink.original(self.con, task.trace_id)
            metered = MeteredOriginal(**{f.name: getattr(orig, f.name) for f in fields(orig) if f.init},
                                      budget=self.budget, bound=bound_s(parse(orig.body)), account=self.account,
                                      slots=self.slots)
            behaviour = shrink.Behaviour(task.sut, kind, property_id)
            self.shrunk.add((behaviour.sut, behaviour.verdict, behaviour.property_id))
            start = self.slots.background if self.slots else at_once
            try:
                self.shrinking.append((behaviour, metered, start(shrink.shrunk, metered, behaviour, self.properties)))
            except KeyboardInterrupt:  # stopped in the midst of an in-process shrink
                shrink.store_interrupted(self.con, metered, behaviour)
                raise
        self._store_shrunk(wait=False)

    def store_interrupted(self) -> None:
        """The campaign was stopped: the runs of the shrinks still running are stored, marked
        interrupted (a resumed campaign counts them against its budget, and shrinks again)."""
        for behaviour, orig, future in self.shrinking:
            if not future.done():
                shrink.store_interrupted(self.con, orig, behaviour)
        self.shrinking = [s for s in self.shrinking if s[2].done()]
        self._store_shrunk(wait=True)

    def _store_shrunk(self, wait: bool) -> None:
        """Stores the shrinks done (all of them, waiting, if `wait`), in the order they were started,
        each with its runs, even if it failed."""
        while self.shrinking and (wait or self.shrinking[0][2].done()):
            behaviour, _, future = self.shrinking.pop(0)
            result = future.result()
            line = shrink.stored(self.con, behaviour, result, self.shrink_to)
            if result.error:
                print(f"          {line}")
                continue
            spent = sum(trace.sim_s for _, trace in result.orig.made)
            print(f"          shrunk in {spent:,.0f} mission s: " + line.split(": ", 1)[1])

    def _stop(self, reason: str, tests: int) -> str:
        self._store_shrunk(wait=True)
        self.account_from_store()
        record(self.con, self.campaign_id, self.budget, self.shrink_s, tests, reason)
        return reason


def at_once(work, *args) -> Future:
    """`work(*args)` run now, as a finished future (in process, shrinks keep the rounds' order)."""
    future = Future()
    future.set_result(work(*args))
    return future


def stopped_line(run: FocusedRun, reason: str) -> str:
    why = {"rule": "its stopping rule says nothing new is expected: "
                   + RULE.format(patience=PATIENCE),
           "budget": "the next test does not fit in the budget",
           "tests": f"it made --mutants {run.config.mutants} tests"}[reason]
    limit = "no budget" if run.budget.limit_s is None else f"budget {run.budget.limit_s:,.0f}"
    # every other run is admitted only if its bound fits: only the golden runs, made first, overrun it
    over = ("; the golden runs alone took more than the budget: give a larger --budget to a new --db"
            if run.budget.left() < 0 else "")
    return (f"stopped   ({reason}) {why}; spent {run.budget.spent_s:,.0f} mission s ({limit}), "
            f"of which shrinking {run.shrink_s:,.0f}{over}")


def findings_table(con) -> str:
    rows = con.execute("select sut, coalesce(property_id, '-'), kind, first_trace, traces, reproducer, "
                       "reproducer_steps from findings").fetchall()
    if not rows:
        return "nothing went wrong"
    return format_table(["variant", "property", "kind", "first trace", "traces", "reproducer", "steps"], rows,
                        null="-")
