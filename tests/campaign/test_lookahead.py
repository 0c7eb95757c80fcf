"""The focused campaign's lookahead (harness.campaign.budgeted): on slots, the next round's runs
start while a round's slowest run is still running, and the campaign makes the same tests, stops
at the same point and stores the same traces as the round-by-round campaign. Deterministic: the
runs are the in-process simulator's, played on slots by threads, one of them held back on purpose."""
import threading
from contextlib import contextmanager

import pytest

from harness import store
from harness.campaign import campaign
from harness.campaign.budget import VariantState
from harness.campaign.rounds import ROUND_TESTS
from harness.campaign.slots import Slots
from harness.cli import main as cli

TRACES = "select trace_id, script_id, sut, seed, outcome, sim_s, error from traces order by trace_id"
EVENTS = "select trace_id, count(*), sum(hash(seq, t, kind, rqst_id, module, service, args, reply)) from events group by all order by all"
STOP = "select tests, stopped, shrink_s from campaign_budgets"
FINDINGS = "select * from findings order by all"


class HeldBack:
    """Setup.run in this process, on slots; the first test's first run is held until a run of the
    second round starts (or 30 s pass: then the lookahead never happened), so that round 0's
    slowest run is still running when round 1's start."""

    def __init__(self, setup, golden_id: int):
        self.setup, self.first = setup, golden_id + 1  # without shrinks, test k is script golden + 1 + k
        self.second_round_started = threading.Event()
        self.held_while_it_started = False

    def run(self, task, interface, slot: int):
        if task.script_id >= self.first + ROUND_TESTS:
            self.second_round_started.set()
        if task.script_id == self.first and task.sut == "genom":
            self.held_while_it_started = self.second_round_started.wait(timeout=30)
        return self.setup.run(task, interface, slot)


def on_slots(monkeypatch) -> list[HeldBack]:
    """Makes the campaign play its focused runs on 4 slots of this process (campaign_slots gives
    none for variants in process); returns the setups it used."""
    used = []

    @contextmanager
    def slots(ctx):
        used.append(HeldBack(ctx.setup, ctx.con.execute("select min(script_id) from scripts").fetchone()[0]))
        held = Slots(used[-1], ctx.interface, 4)
        try:
            yield held
        finally:
            held.close()
    monkeypatch.setattr(campaign, "campaign_slots", slots)
    return used


@pytest.mark.slow
@pytest.mark.parametrize("suts, budget, stopped", [("genom,bip-a", "4000s", "rule"), ("genom,bip-a", "10m", "budget")])
def test_the_lookahead_starts_a_round_before_the_last_ends_and_changes_nothing_the_campaign_makes(
        tmp_path, monkeypatch, suts, budget, stopped):
    args = ["campaign", "--strategy", "focused", "--budget", budget, "--sut", suts, "--seed", "5"]
    assert cli(args + ["--db", str(tmp_path / "rounds.duckdb")]) == 0
    used = on_slots(monkeypatch)
    assert cli(args + ["--db", str(tmp_path / "ahead.duckdb")]) == 0
    assert used and used[0].held_while_it_started, "round 1 never started while round 0's first run ran"
    rounds = store.connect(tmp_path / "rounds.duckdb", read_only=True)
    ahead = store.connect(tmp_path / "ahead.duckdb", read_only=True)
    assert rounds.execute(STOP).fetchone()[1] == stopped
    for query in (STOP, TRACES, EVENTS, FINDINGS):
        assert ahead.execute(query).fetchall() == rounds.execute(query).fetchall(), query


@pytest.mark.parametrize("tests, quiet, aims, stays", [
    (0, 0, 12, True),  # nothing shown yet
    (10, 31, 12, True),  # quiet, but a round of 8 cannot make it 40 quiet
    (10, 32, 20, True),  # 40 quiet at the round's end, but not every aim exercised yet
    (4, 32, 12, False),  # both can be met by the round's end
])
def test_a_variant_stays_active_only_if_no_outcome_of_the_round_can_end_it(tests, quiet, aims, stays):
    state = VariantState(tests=tests, quiet=quiet)
    assert state.stays_active(ROUND_TESTS, aims, patience=40) is stays
    # a round showing nothing new ends the variant exactly when stays_active said it could
    for _ in range(ROUND_TESTS):
        state.record(set(), aims, patience=40)
    assert state.done is not stays
