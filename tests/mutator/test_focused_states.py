"""Focused tests reach the state a property speaks of (issue 47): on a lifecycle-like target whose
rules are IN and OUT properties (sql/oracles/in.sql, out.sql), a test's context is the golden's
way into the state its requests need (configure, activate before a goal), without the transitions
that leave the state the running activity needs; the aims of the ROS 2 types (responsiveness,
cancel, goal policy, nothing outliving the state) get that context for the goal that must run.
Read only from the interface, the properties and the golden script and run."""
import pytest

from harness.mutator.focused import Plan
from harness.mutator.states import entry_needs, leavers
from harness.mutator.timeline import ScriptTimeline
from harness.target.interface import Property, load_interface, load_properties
from harness.target.script import parse
from harness.trace import Trace

INTERFACE = """
[replies]
ok = "T"
aborted = "T"
canceled = "Z"
refused = "R"

[modules.arm]
services.configure = { kind = "control" }
services.activate = { kind = "control" }
services.deactivate = { kind = "control" }
services.cleanup = { kind = "control" }
services.home = { kind = "control" }
services.move = { kind = "exec", args = { order = { type = "float", min = 1.0, max = 50.0 } } }
services.move_cancel = { kind = "control" }
services.grip = { kind = "exec", args = { order = { type = "float", min = 1.0, max = 10.0 } } }
"""
# configure, activate, a trajectory, a grip, home, then deactivate and cleanup: each awaited
GOLDEN_SENDS = [("configure", ""), ("activate", ""), ("move", " order=10"), ("grip", " order=3"),
                ("home", ""), ("deactivate", ""), ("cleanup", "")]
RUN_S = {"move": 2.0, "grip": 0.3}
LIFECYCLE = """
[[property]]
id = "ACTIVE(arm)"
family = "ACTIVE"
type = "IN"
x = ["arm.move", "arm.grip", "arm.home"]
q = ["arm.activate"]
y = ["arm.deactivate"]
r_p = "refused"
""" + "".join(f"""
[[property]]
id = "TRANSITION(arm.{name})"
family = "TRANSITION"
type = "{kind}"
x = ["arm.{name}"]
q = {q}
{f"y = {y}" if y else ""}
r_p = "refused"
""" for name, kind, q, y in [
    ("configure", "OUT", ["arm.configure"], ["arm.cleanup"]),
    ("activate", "IN", ["arm.configure", "arm.deactivate"], ["arm.activate", "arm.cleanup"]),
    ("deactivate", "IN", ["arm.activate"], ["arm.deactivate"]),
    ("cleanup", "IN", ["arm.configure", "arm.deactivate"], ["arm.activate", "arm.cleanup"])])
INTERLOCK = """
[[property]]
id = "NO_GRIP_WHILE_MOVING(arm.grip)"
family = "INTERLOCK"
type = "ES"
x = ["arm.grip"]
y = ["arm.move"]
r_p = "refused"
"""


def golden_run():
    """The golden script and its run's trace: every request ends ok after its run time."""
    lines, events, t = [], [], 0.0
    for n, (name, args) in enumerate(GOLDEN_SENDS, 1):
        lines += [f"send arm.{name}{args} as h{n}", f"wait h{n} timeout=5"]
        events.append((2 * n - 1, t, "request", n, "arm", name, None, None))
        t += RUN_S.get(name, 0.01)
        events.append((2 * n, t, "final", n, "arm", name, None, "ok"))
        t += 0.01
    return parse("\n".join(lines) + "\n", "golden.mission"), Trace("sim", 0, events=events)


def plan(tmp_path, properties: str, extra: tuple[Property, ...] = ()) -> Plan:
    (tmp_path / "interface.toml").write_text(INTERFACE)
    (tmp_path / "properties.toml").write_text(properties)
    interface = load_interface(tmp_path / "interface.toml")
    golden, trace = golden_run()
    timeline = ScriptTimeline(golden, trace, interface.replies)
    loaded = load_properties(tmp_path / "properties.toml", interface) + list(extra)
    return Plan(golden, timeline, interface, loaded, 1, str(tmp_path / "properties.toml"))


def made_for(p: Plan, situation: str) -> list[list[str]]:
    made = [p.test(n, f"t{n}") for n in range(len(p.aims))]
    found = [[line for line in m.body.splitlines() if line] for m in made
             if m.operations[0]["situation"] == situation]
    assert found, f"no aim {situation!r} among {[m.operations[0]['situation'] for m in made]}"
    assert all(m.valid for m in made)
    return found


def sends(test: list[str]) -> list[str]:
    return [line.split()[1] for line in test if line.startswith("send")]


def test_an_interlock_test_brings_the_node_up_before_the_trajectory_and_the_grip(tmp_path):
    p = plan(tmp_path, LIFECYCLE + INTERLOCK)
    (test,) = made_for(p, "arm.grip in the start phase of arm.move")
    assert sends(test) == ["arm.configure", "arm.activate", "arm.move", "arm.grip"]
    assert test[:4] == ["send arm.configure as c1", "wait c1 timeout=1.02",
                        "send arm.activate as c2", "wait c2 timeout=1.02"]
    assert test[4:] == ["send arm.move order=10", "sleep 0.01", "send arm.grip order=3"]


def test_without_the_span_properties_the_context_is_what_it_was(tmp_path):
    """Dala's case (no IN or OUT property): the interlock's test has no context at all."""
    (test,) = made_for(plan(tmp_path, INTERLOCK), "arm.grip in the start phase of arm.move")
    assert sends(test) == ["arm.move", "arm.grip"]


def test_the_state_is_entered_the_goldens_way_and_the_outside_needs_nothing(tmp_path):
    p = plan(tmp_path, LIFECYCLE)
    golden, trace = golden_run()
    properties = load_properties(tmp_path / "properties.toml", load_interface(tmp_path / "interface.toml"))
    needs = entry_needs(properties, ScriptTimeline(golden, trace, p.interface.replies))
    # cleanup's state (inactive) was entered by deactivate in the golden, activate's by configure
    assert needs == {"arm.move": {"arm.activate"}, "arm.grip": {"arm.activate"}, "arm.home": {"arm.activate"},
                     "arm.activate": {"arm.configure"}, "arm.deactivate": {"arm.activate"},
                     "arm.cleanup": {"arm.deactivate"}}
    assert leavers(properties)["arm.move"] == {"arm.deactivate"}
    assert leavers(properties)["arm.configure"] == {"arm.configure"}
    (test,) = made_for(p, "arm.move with arm.activate never sent")  # IN's Q never entered: a bare move
    assert sends(test) == ["arm.move"]
    (test,) = made_for(p, "arm.move while arm.activate runs (before it ended ok)")
    assert sends(test) == ["arm.configure", "arm.activate", "arm.move"]


@pytest.mark.parametrize("situation, expected", [
    # IN: x once a y left its state, and while a y runs; OUT: x once a q entered the span
    ("arm.move after arm.deactivate ended ok", ["configure", "activate", "deactivate", "move"]),
    ("arm.move in the start phase of arm.deactivate", ["configure", "activate", "deactivate", "move"]),
    ("arm.activate after arm.cleanup ended ok", ["configure", "activate", "deactivate", "cleanup", "activate"]),
    ("arm.activate after arm.activate ended ok", ["configure", "activate", "activate"]),
    ("arm.configure after arm.configure ended ok", ["configure", "configure"])])
def test_a_span_propertys_state_is_left_the_goldens_way(tmp_path, situation, expected):
    (test,) = made_for(plan(tmp_path, LIFECYCLE), situation)
    assert sends(test) == [f"arm.{name}" for name in expected]
    assert all(line.startswith("wait c") for line in test if line.startswith("wait"))  # the context awaited


ROS2_TYPES = (Property("RSP(arm.home)", "RSP", "RSP", ("arm.home",), ("arm.move",)),
              Property("CANCEL(arm.move)", "CANCEL", "CAN", ("arm.move_cancel",), ("arm.move",), z_p="canceled"),
              Property("ONE_TRAJECTORY(arm.move)", "POLICY", "GOAL", ("arm.move",)),
              Property("STOP_ON_DEACTIVATE(arm.move)", "LIFECYCLE", "OUTLIVE", ("arm.move",),
                       ("arm.deactivate", "arm.cleanup")))


@pytest.mark.parametrize("situation, expected", [
    ("arm.home while arm.move runs", ["arm.move", "arm.home"]),
    ("arm.move_cancel in the start phase of arm.move", ["arm.move", "cancel"]),  # of that goal, by its handle
    ("arm.move while arm.move runs", ["arm.move", "arm.move"]),
    ("arm.deactivate while arm.move runs", ["arm.move", "arm.deactivate"]),
    # cleanup while a goal runs: its own state (inactive) would leave move's, so it lands in active
    ("arm.cleanup in the start phase of arm.move", ["arm.move", "arm.cleanup"])])
def test_the_goal_that_must_run_is_sent_in_its_state(tmp_path, situation, expected):
    """RSP, CAN, GOAL and OUTLIVE aims (their falsifiers are targeted.py's generic ones): the goal
    that must run is sent with its own context, the node brought up first."""
    for test in made_for(plan(tmp_path, LIFECYCLE, ROS2_TYPES), situation):
        requests = [line.split()[1] if line.startswith("send") else "cancel"
                    for line in test if line.startswith(("send", "cancel"))]
        assert requests == ["arm.configure", "arm.activate"] + expected
        goals = {line.split()[-1]: line.split()[1] for line in test if line.startswith("send") and " as " in line}
        assert all(goals.get(line.split()[1]) == "arm.move" for line in test if line.startswith("cancel")), test


def test_a_targeted_mutants_fresh_goal_goes_where_the_node_was_brought_up(tmp_path):
    """targeted.py places a fresh r where its preconditions hold: now also in the golden's active state."""
    import random
    from harness.mutator.targeted import Falsifier, Planner
    p = plan(tmp_path, LIFECYCLE + INTERLOCK)
    golden, trace = golden_run()
    properties = load_properties(tmp_path / "properties.toml", p.interface)
    planner = Planner(golden, ScriptTimeline(golden, trace, p.interface.replies), p.interface, properties,
                      random.Random(5))
    fresh = Falsifier("during", send=("arm.grip",), running=("arm.move",))
    sites = [planner.site(fresh) for _ in range(60)]
    positions = [position for position, steps, what in sites if "a new arm.move" in what]
    # after `wait h2` (activate's ok), until `wait h6` (deactivate's) is passed: while active
    assert positions and min(positions) == 4 and max(positions) <= 11
    after = {planner.site(Falsifier("after_ok", send=("arm.move",), need=("arm.deactivate",)))[0] for _ in range(20)}
    assert min(after) == 12  # after `wait h6` (deactivate's)
