"""A focused campaign's runs (`campaign --strategy focused [--budget D] [--shrink]`): tests made,
run and judged ROUND_TESTS at a time, in the plan's order (harness.mutator.focused), on every
variant the stopping rule has not ended yet, within the budget (harness.campaign.budget). With
--shrink, each new finding's first trace is shrunk as soon as it shows, its runs within the
budget too. On slots (harness.campaign.slots), the next round's runs start while a round's tail
runs, as far as the round-by-round campaign is certain to make them (lookahead): the same tests,
stopping point and traces, the slots kept busy.

Resumable and a function of the arguments only: rounds are fixed (not a function of --jobs), a
variant's rule is applied to its tests in order, and a resumed campaign replays its stored
traces' findings (view trace_findings) through the same rounds before it runs anything new.
Every run is a stored trace, shrink runs included (table shrink_runs): what the campaign has spent
is the sum of their mission seconds, read from the store when it starts or resumes and after every
round (sql/report/campaign_spent.sql); its progress bar counts them (budget.progress). The table
campaign_budgets records the budget, the rule, the shrink runs' share of that sum, why it stopped."""
from __future__ import annotations

import json
from concurrent.futures import FIRST_COMPLETED, Future, wait
from dataclasses import fields

from harness import store
from harness.campaign import runs, shrink
from harness.campaign.budget import RULE, Budget, MeteredOriginal, VariantState
from harness.campaign.context import CampaignContext
from harness.campaign.rounds import ROUND_TESTS, Round
from harness.campaign.slots import Slots, at_once, traced
from harness.store import campaign_reads
from harness.store.budgets import BudgetRow, record_budget
from harness.store.record import ShrinkRecord, records
from harness.store.scripts import ScriptRow, add_scripts
from harness.analysis.judge import Judge
from harness.errors import UntimelyError
from harness.mutator.focused import Plan
from harness.mutator.script_time import bound_s
from harness.target.script import parse
from harness.dispatch.description import Task

PATIENCE = 40  # tests per variant without anything new, once every aim was exercised (budget.RULE)
AHEAD = 2  # rounds made ahead of the one being judged (judging one takes the bench seconds)


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
        self.shrinking: list[tuple[shrink.Behaviour, MeteredOriginal, Future]] = []
        self.state = {sut: VariantState() for sut in config.sut}
        self.in_flight: list[Round] = []  # the rounds whose runs were started on slots, not all back
        self.stopped = campaign_reads.budget_stopped(con, campaign_id)
        self.budget, self.shrink_s = Budget(config.budget_s), 0.0
        self.account_from_store()
        self.scripts = {json.loads(m)[0]["test"]: (script_id, body)
                        for script_id, m, body in campaign_reads.mutant_scripts(con, campaign_id)}
        self.shown = {}  # trace_id -> findings, of the traces stored before this session
        for trace_id, property_id, kind in campaign_reads.campaign_findings(con, campaign_id):
            self.shown.setdefault(trace_id, set()).add((property_id, kind))
        self.stored = campaign_reads.campaign_trace_ids(con, campaign_id)
        # what was shrunk or tried (its runs stored): not tried again on resume, unless it was interrupted
        self.shrunk = {(s.sut, s.verdict, s.property) for _, _, s in records(con, ShrinkRecord) if not s.interrupted}

    def account_from_store(self) -> None:
        """What the campaign has spent: its stored traces' and shrink runs' mission seconds, its test
        runs in flight at their bounds (with no shrink running: its runs are counted, not stored)."""
        traces_s, self.shrink_s = campaign_reads.spent_s(self.con, self.campaign_id)
        with self.budget.account:
            self.budget.spent_s = traces_s + self.shrink_s + sum(
                bound for rnd in self.in_flight for trace_id, bound in rnd.bounds.items() if trace_id not in rnd.fresh)

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
        n, ahead = 0, []
        self._shrink(self._golden_findings())
        while True:
            current = ahead.pop(0) if ahead else self._round(n)
            if isinstance(current, str):
                return self._stop(current, n)
            while len(ahead) < AHEAD and (later := self._lookahead([current, *ahead])):
                ahead.append(later)
            self._store_shrunk(wait=False)  # on slots, once the runs ahead are started
            self._collect(current)
            n = self._judged(current)
            if current.cut is not None and not current.bounds:  # not one more run fits, none in flight
                return self._stop("budget", n)
            self._release(ahead)

    def _golden_findings(self) -> list[tuple[Task, str | None, str]]:
        """What the golden runs showed (judged before the campaign runs): shrunk like a test's finding,
        so a test that shows it again does not shrink it. The stopping rule counts tests only."""
        golden = runs.tasks([(self.golden_id, "")], self.golden_id, self.config)
        return [(task, property_id, kind) for task in golden
                for property_id, kind in sorted(self.shown.get(task.trace_id, ()), key=str)]

    def _round(self, n: int) -> Round | str:
        """The round from test n, started; or why the campaign stops before it."""
        active = [s for s in self.config.sut if not self.state[s].done]
        if not active:
            return "rule"
        if n >= self.config.mutants:
            return "tests"
        return self._admitted(n, active)

    def _lookahead(self, unjudged: list[Round]) -> Round | None:
        """The round after those `unjudged`, started now, as the round-by-round campaign is certain
        to make it whatever they find: only if each of its runs fits the budget with those in
        flight counted at their bounds, and the runs of a variant that they could end (the
        stopping rule) held until they have not (_release)."""
        n, tests = unjudged[-1].end, sum(len(rnd.tests) for rnd in unjudged)
        if self.slots is None or unjudged[-1].cut is not None or n >= self.config.mutants:
            return None
        active = [s for s in self.config.sut if not self.state[s].done]
        held = {s for s in active if not self.state[s].stays_active(tests, len(self.plan.aims), PATIENCE)}
        return None if held == set(active) else self._admitted(n, active, held)

    def _admitted(self, n: int, active: list[str], held: set[str] | None = None) -> Round | None:
        """The round from test n on the active variants, each run's bound reserved in the budget
        while it fits, started. Made ahead (`held` not None): None unless every run fits, and the
        runs of the held variants are reserved, not started."""
        cap = self.config.mutants
        tests = [(k, [t for t in runs.tasks([self.script(k)], self.golden_id, self.config) if t.sut in active])
                 for k in range(n, min(n + ROUND_TESTS, cap))]
        rnd = Round(n // ROUND_TESTS, tests)
        with self.budget.account:
            for k, task in ((k, t) for k, tasks in tests for t in tasks if t.trace_id not in self.stored):
                bound = bound_s(parse(task.body))
                if not self.budget.fits(bound):
                    rnd.cut = k
                    break
                self.budget.reserve(bound)
                rnd.bounds[task.trace_id] = bound
            if held is not None and rnd.cut is not None:
                for bound in rnd.bounds.values():
                    self.budget.settle(bound, 0.0)
                return None
        admitted = [t for _, tasks in tests for t in tasks if t.trace_id in rnd.bounds]
        rnd.held = [t for t in admitted if t.sut in (held or ())]
        if self.slots:
            rnd.pending = self.slots.submit([t for t in admitted if t not in rnd.held], rnd.number)
            self.in_flight.append(rnd)
            self._rank_shrinks()
        elif admitted:
            self.run_tasks(admitted, lambda task, trace: self._arrived(rnd, task, trace))
        return rnd

    def _release(self, ahead: list[Round]) -> None:
        """Once a round is judged, the held runs of the rounds made ahead: dropped if their variant
        has ended (bounds freed, the round's tests without them), started once the rounds before
        theirs cannot end it."""
        ended = {s for s in self.config.sut if self.state[s].done}
        before = 0  # the unjudged tests before the round
        for rnd in ahead:
            rnd.tests = [(k, [t for t in tasks if t.sut not in ended]) for k, tasks in rnd.tests]
            sure = [t for t in rnd.held if t.sut not in ended
                    and self.state[t.sut].stays_active(before, len(self.plan.aims), PATIENCE)]
            with self.budget.account:
                for task in [t for t in rnd.held if t.sut in ended]:
                    self.budget.settle(rnd.bounds.pop(task.trace_id), 0.0)
            rnd.pending.update(self.slots.submit(sure, rnd.number))
            rnd.held = [t for t in rnd.held if t.sut not in ended and t not in sure]
            before += len(rnd.tests)

    def _collect(self, current: Round) -> None:
        """Waits for the runs of `current`, storing every trace in flight as it comes back."""
        while current.pending:
            futures = {f: rnd for rnd in self.in_flight for f in rnd.pending}
            done, _ = wait(futures, return_when=FIRST_COMPLETED)
            for future in sorted(done, key=lambda f: futures[f].pending[f].trace_id):
                rnd = futures[future]
                self._arrived(rnd, rnd.pending.pop(future), traced(future))
        if current in self.in_flight:
            self.in_flight.remove(current)
            self._rank_shrinks()
        self.batches.commit()

    def _rank_shrinks(self) -> None:
        """Shrink runs take free slots after the first round in flight's runs, before a round started ahead."""
        self.slots.shrink_rank = min(rnd.number for rnd in self.in_flight) + 0.5 if self.in_flight else 0.5

    def _arrived(self, rnd: Round, task: Task, trace) -> None:  # stored as it comes back, its bound freed
        rnd.fresh[task.trace_id] = trace
        self.batches.add(task, trace)
        with self.budget.account:
            self.budget.settle(rnd.bounds[task.trace_id], trace.sim_s)

    def _judged(self, rnd: Round) -> int:
        """Judges a round's traces, applies the rule to its tests in order, shrinks what is new;
        returns the next test's number."""
        traces = sorted(rnd.fresh.items())
        for (trace_id, _), found in zip(traces, self.judge.findings([t for _, t in traces])):
            self.shown[trace_id] = found
        self.stored |= set(rnd.fresh)
        found = []
        for k, tasks in rnd.tests[:rnd.recorded]:
            for task in tasks:
                new = self.state[task.sut].record(self.shown.get(task.trace_id, set()), len(self.plan.aims),
                                                  PATIENCE)
                found += [(task, property_id, kind) for property_id, kind in sorted(new, key=str)]
        self._shrink(found)
        if not self.shrinking:
            self.account_from_store()
        record(self.con, self.campaign_id, self.budget, self.shrink_s, rnd.end, None)
        return rnd.end

    def _shrink(self, found: list[tuple[Task, str | None, str]]) -> None:
        """Says what a round found; shrinks each new finding from the trace that showed it, at once
        in process (and stores it), in the background on external SUTs (run() stores them)."""
        for task, property_id, kind in found:
            what = f"{kind} on {property_id}" if property_id else kind
            print(f"found     {task.sut}: {what} (trace {task.trace_id}, script {task.script_id})")
            if self.shrink_to is None or kind == "crashed" or (task.sut, kind, property_id) in self.shrunk:
                continue
            orig = shrink.original(self.con, task.trace_id)
            metered = MeteredOriginal(**{f.name: getattr(orig, f.name) for f in fields(orig) if f.init},
                                      budget=self.budget, bound=bound_s(parse(orig.body)),
                                      slots=self.slots)
            behaviour = shrink.Behaviour(task.sut, kind, property_id)
            self.shrunk.add((behaviour.sut, behaviour.verdict, behaviour.property_id))
            start = self.slots.background if self.slots else at_once
            try:
                self.shrinking.append((behaviour, metered, start(shrink.shrunk, metered, behaviour, self.properties)))
            except KeyboardInterrupt:  # stopped in the midst of an in-process shrink
                shrink.store_interrupted(self.con, metered, behaviour)
                raise
        if not self.slots:  # in process, before the next round's scripts (their ids follow the shrinks')
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
            self.batches.tally.progress.spent(spent)
            print(f"          shrunk in {spent:,.0f} mission s: " + line.split(": ", 1)[1])

    def _stop(self, reason: str, tests: int) -> str:
        self._store_shrunk(wait=True)
        self.account_from_store()
        record(self.con, self.campaign_id, self.budget, self.shrink_s, tests, reason)
        return reason
