"""Mutation operators: each does what it says, seeded reproducibility, invalid mutants."""
import json
import random
import re

import pytest

from harness import DEFAULT_MISSION_DIR
from harness.mutator import operators
from harness.mutator.operators import Draw, chosen, generate, mutate
from harness.mutator.timeline import ScriptTimeline
from harness.target.script import Script, load_script, parse, validate
from harness.trace import Trace
from tests.support.arm_interface import arm_interface

SMALL = """\
send rflex.Init as ri
wait ri
send rflex.SetMode mode=velocity as mode
sleep 2
send ndd.Init
wait all
"""


@pytest.fixture(scope="module")
def golden(interface):
    return load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)


def small():
    return list(parse(SMALL, "small").steps)


def rendered(steps):
    return [s.render() for s in steps]


def test_delete_request_removes_one_send_and_records_it(interface):
    for seed in range(10):
        steps, before = small(), rendered(small())
        record = operators.delete_request(steps, random.Random(seed), interface)
        removed = before[record["line"] - 1]
        assert record == {"op": "delete_request", "line": record["line"], "step": removed}
        assert removed.startswith("send ")
        assert rendered(steps) == [t for t in before if t != removed]


def test_insert_request_adds_a_plausible_request_at_the_recorded_position(interface):
    handles = set()
    for seed in range(200):
        steps = small()
        record = operators.insert_request(steps, random.Random(seed), interface)
        new = steps[record["position"] - 1]
        assert len(steps) == len(small()) + 1 and new.render() == record["step"]
        service = interface.services[new.service]
        assert [name for name, _ in new.args] == list(service.args)
        for name, value in new.args:
            arg = service.args[name]
            assert (arg.min <= float(value) <= arg.max) if arg.type == "float" else value in arg.choices
        handles.add(new.handle)
        validate(parse("".join(s.render() + "\n" for s in steps)), interface)
    assert None in handles and "extra1" in handles and not handles & {"ri", "mode"}


def test_inserted_handle_is_fresh(interface):
    steps = list(parse("send rflex.Init as extra1\n").steps)
    assert operators._fresh_handle(steps) == "extra2"


def test_swap_requests_exchanges_two_sends_only(interface):
    for seed in range(10):
        steps, before = small(), rendered(small())
        record = operators.swap_requests(steps, random.Random(seed), interface)
        a, b = (line - 1 for line in record["lines"])
        assert record["steps"] == [before[a], before[b]]
        expected = list(before)
        expected[a], expected[b] = before[b], before[a]
        assert rendered(steps) == expected


def test_drop_wait_removes_one_wait(interface):
    steps, before = small(), rendered(small())
    record = operators.drop_wait(steps, random.Random(1), interface)
    assert record["step"] in ("wait ri", "wait all")
    assert rendered(steps) == [t for t in before if t != record["step"]]


def test_change_sleep_rescales_within_a_decade(interface):
    for seed in range(20):
        steps = small()
        record = operators.change_sleep(steps, random.Random(seed), interface)
        assert record["line"] == 4 and record["step"] == "sleep 2"
        assert steps[3].seconds == record["seconds"] and 0.2 <= record["seconds"] <= 20
        assert [s.op for s in steps] == [s.op for s in small()]


def test_operators_without_a_target_do_not_apply(interface):
    steps = list(parse("send rflex.Init as ri\n").steps)
    rng = random.Random(0)
    assert operators.swap_requests(steps, rng, interface) is None
    assert operators.drop_wait(steps, rng, interface) is None
    assert operators.change_sleep(steps, rng, interface) is None
    mutant = mutate(parse("send rflex.Init as ri\n"), interface, rng, operations=3, operators=chosen(None, True))
    assert len(mutant.operations) == 3


def test_time_operators_only_behind_the_flag(golden, interface):
    plain = {op["op"] for m in generate(golden, interface, Draw(60, seed=3)) for op in m.operations}
    timed = {op["op"] for m in generate(golden, interface, Draw(60, seed=3, time_mutations=True))
             for op in m.operations}
    assert plain == {"delete_request", "insert_request", "swap_requests"}
    assert timed == plain | {"drop_wait", "change_sleep"}


def test_same_seed_gives_byte_identical_mutants(golden, interface):
    first = list(generate(golden, interface, Draw(40, seed=2012, operations=2, time_mutations=True)))
    again = list(generate(golden, interface, Draw(40, seed=2012, operations=2, time_mutations=True)))
    other = list(generate(golden, interface, Draw(40, seed=2013, operations=2, time_mutations=True)))
    assert [m.body for m in first] == [m.body for m in again]
    assert [json.dumps(m.operations) for m in first] == [json.dumps(m.operations) for m in again]
    assert [m.body for m in first] != [m.body for m in other]
    assert all(len(m.operations) == 2 for m in first)


def test_mutants_are_distinct_and_differ_from_golden(golden, interface):
    mutants = list(generate(golden, interface, Draw(100, seed=7)))
    bodies = [m.body for m in mutants]
    assert len(set(bodies)) == 100 and golden.renumbered().render() not in bodies


def test_deleting_a_waited_request_gives_an_invalid_mutant(interface):
    script = parse("send rflex.Init as ri\nwait ri\n", "tiny")
    mutants = list(generate(script, interface, Draw(12, seed=5)))
    deleted = [m for m in mutants if m.operations[0]["op"] == "delete_request"]
    assert deleted, "seed 5 should draw a deletion among 12 mutants"
    for m in deleted:
        n = mutants.index(m) + 1
        assert not m.valid and m.body == "wait ri\n"
        assert m.invalid_reason == f"mutant {n}:1: wait on handle 'ri', which no earlier line sends"
    assert all(m.valid for m in mutants if m.operations[0]["op"] == "insert_request")


def test_swapping_a_wait_before_its_send_is_invalid(interface):
    script = parse("send rflex.Init as ri\nwait ri\nsend sick.Init as si\n", "tiny")
    mutants = list(generate(script, interface, Draw(30, seed=1)))
    swapped = [m for m in mutants if m.operations[0]["op"] == "swap_requests"]
    assert swapped and all("wait on handle 'ri'" in m.invalid_reason for m in swapped)


def test_operators_named_from_the_registry_are_the_only_ones_drawn(golden, interface):
    assert operators.chosen(None) == ("delete_request", "insert_request", "swap_requests")
    assert operators.chosen(None, time_mutations=True)[3:] == ("drop_wait", "change_sleep")
    named = operators.chosen("change_sleep, swap_requests")
    assert named == ("swap_requests", "change_sleep")  # in the registry's order, whatever the order given
    drawn = {op["op"] for m in generate(golden, interface, Draw(40, seed=3, operators=named)) for op in m.operations}
    assert drawn == {"swap_requests", "change_sleep"}
    # absent, the default draws exactly as before the registry
    assert [m.body for m in generate(golden, interface, Draw(20, seed=3))] == \
        [m.body for m in generate(golden, interface, Draw(20, seed=3, operators=operators.chosen(None)))]


@pytest.mark.parametrize("names, time_mutations, message", [
    ("delete_request,fly", False, "--operators 'delete_request,fly': no operator 'fly'; give a comma-separated "
                                  "list of delete_request, insert_request, swap_requests, drop_wait, change_sleep"),
    (" , ", False, "--operators ' , ': none named"),
    ("drop_wait", True, "with --operators, name them in its list instead"),
])
def test_unknown_operators_are_refused_naming_the_registry(names, time_mutations, message):
    with pytest.raises(operators.UntimelyError, match=re.escape(message)):
        operators.chosen(names, time_mutations)


def test_a_mutant_whose_operators_do_not_apply_keeps_no_operation(interface):
    mutant = mutate(parse("send rflex.Init as ri\n"), interface, random.Random(0), operations=2,
                    operators=("swap_requests", "drop_wait"))
    assert mutant.operations == () and mutant.valid


CANCELLING = "send arm.move order=3 as g1\nsleep 0.5\ncancel g1 as c\nsend arm.grip as gr\nwait c\n"


@pytest.fixture
def arm(tmp_path):
    return arm_interface(tmp_path)


def test_the_request_operators_take_a_cancel_for_a_request(arm):
    """Deleting the goal leaves its cancel naming nothing (invalid, as a wait would be); deleting
    the cancel leaves its wait naming nothing; swaps move a cancel like a send, and one before its
    goal is invalid; every other mutant stays valid."""
    mutants = list(generate(parse(CANCELLING, "c"), arm, Draw(60, seed=3)))
    seen = set()
    for m in mutants:
        record = m.operations[0]
        kind = record["op"], record.get("step") or tuple(record.get("steps", ()))
        seen.add(record["op"])
        if kind == ("delete_request", "send arm.move order=3 as g1"):
            assert m.invalid_reason.endswith("cancel of handle 'g1', which no earlier line sends")
        elif kind == ("delete_request", "cancel g1 as c"):
            assert m.invalid_reason.endswith("wait on handle 'c', which no earlier line sends")
        elif record["op"] == "swap_requests" and m.body.index("cancel g1") < m.body.index("send arm.move"):
            assert "cancel of handle 'g1', which no earlier line sends" in m.invalid_reason
        elif record["op"] != "swap_requests" or "cancel g1 as c" not in record["steps"]:
            assert m.valid, (m.body, m.invalid_reason)
    assert seen == {"delete_request", "insert_request", "swap_requests"}
    assert any(m.operations[0].get("steps", [None])[0] == "cancel g1 as c" for m in mutants)


def test_an_inserted_cancel_request_cancels_an_earlier_goal(arm):
    """insert_request drawing arm.move_cancel after a goal with a handle writes `cancel HANDLE`."""
    inserted = []
    for seed in range(80):
        steps = list(parse(CANCELLING, "c").steps)
        record = operators.insert_request(steps, random.Random(seed), arm)
        if "move_cancel" in record["step"] or record["step"].startswith("cancel"):
            inserted.append((record, steps))
    cancels = [(r, s) for r, s in inserted if r["step"].startswith("cancel g1")]
    assert cancels and all(r["position"] > 1 for r, _ in cancels)
    sends = [r for r, _ in inserted if r["step"].startswith("send arm.move_cancel")]
    assert sends and all(r["position"] == 1 for r in sends)  # before the goal: a plain send of the service
    for _, steps in inserted:
        validate(Script(tuple(steps), "m").renumbered(), arm)


def test_the_timeline_counts_a_cancel_as_a_request_of_its_cancel_service(arm):
    """Request ids follow the steps that send (a cancel among them): the grip after a cancel is
    request 3, and the cancel an activity of arm.move_cancel."""
    script = parse("send arm.move order=3 as g1\ncancel g1 as c\nsend arm.grip\nwait c\n", "c")
    events = [(1, 0.0, "request", 1, "arm", "move", "{}", None), (2, 0.1, "request", 2, "arm", "move_cancel", "{}", None),
              (3, 0.1, "request", 3, "arm", "grip", "{}", None), (4, 0.2, "final", 2, "arm", "move_cancel", None, "ok"),
              (5, 0.3, "final", 1, "arm", "move", None, "canceled"), (6, 0.4, "final", 3, "arm", "grip", None, "ok")]
    timeline = ScriptTimeline(script, Trace("arm", 0, events=events), arm.replies)
    assert [(a.service, a.end, a.reply) for a in timeline.activities] == [
        ("arm.move", 0.3, "canceled"), ("arm.move_cancel", 0.2, "ok"), ("arm.grip", 0.4, "ok")]
    assert timeline.ended_ok(3) == set() and timeline.ended_ok(4) == {"arm.move_cancel"}  # after wait c
