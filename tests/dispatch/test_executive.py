"""The executive against a small fake layer: sends, waits, delays, hang, crash, determinism."""
import pytest

from harness.errors import ScriptError
from harness.sut.executive import DRAIN_S, REACTION_S, Runner
from harness.target.script import parse, validate
from tests.support.arm_interface import arm_interface


class FakeLayer:
    """Takes each request after `take_s`, ends it `ok` after `duration` s; `deadlock_at` stops
    it answering anything."""

    duration, take_s, deadlock_at, crash_on, bad_code = 1.0, 0.0, None, None, None

    def __init__(self, env, variant, interface, world_file):
        self.env, self.world_events = env, [(0.5, "collision", '{"with": "rock"}')]

    def alive(self):
        return self.deadlock_at is None or self.env.now < self.deadlock_at

    def receive(self, rqst_id, service, args, reply):
        self.env.call_at(self.env.now + self.take_s, lambda: reply(rqst_id, "request", None))
        if service == self.crash_on:
            raise ZeroDivisionError("codel divided by zero")

        def finish():
            if self.alive():
                reply(rqst_id, "final", self.bad_code or "ok")
        if service.endswith("TrackSpeedStart"):
            return  # runs until stopped: never answers here
        self.env.call_at(self.env.now + self.duration, finish)

    def ping(self, answer):
        if self.alive():
            self.env.call_at(self.env.now + 0.01, answer)


def play(interface, text, seed=1, layer=FakeLayer, **kw):
    script = parse(text, "t.mission")
    validate(script, interface)
    return Runner(layer)(script, "fake", seed, interface, None, **kw)


SCRIPT = "send rflex.Init as ri\nsend sick.Init as si\nwait ri\nsleep 2\nsend ndd.Init\nwait all\n"


def test_send_is_non_blocking_and_wait_blocks_on_final_replies(interface):
    trace = play(interface, SCRIPT)
    assert trace.outcome == "completed"
    kinds = [(e[2], e[3]) for e in trace.events]
    assert kinds[:2] == [("request", 1), ("request", 2)]  # both sent before any reply
    t = {(e[2], e[3]): e[1] for e in trace.events}
    assert t[("request", 3)] == pytest.approx(t[("final", 1)] + REACTION_S + 2)  # reaction, sleep 2
    assert len(trace.events) == len(trace.internal_events) == 6
    assert trace.sim_s == pytest.approx(t[("final", 3)] + REACTION_S)


def test_observation_delays_are_seeded_and_bounded(interface):
    a, b, c = play(interface, SCRIPT, seed=7), play(interface, SCRIPT, seed=7), play(interface, SCRIPT, seed=8)
    assert a.events == b.events and a.internal_events == b.internal_events
    assert [e[1] for e in a.events] != [e[1] for e in c.events]
    internal = {(e[2], e[3]): e[1] for e in a.internal_events}
    for seq, t, kind, rqst_id, *_ in a.events:
        lag = internal[(kind, rqst_id)] - t if kind == "request" else t - internal[(kind, rqst_id)]
        assert 0 <= lag <= 0.003
    assert [e[0] for e in a.events] == list(range(1, 7))


def test_args_are_stored_as_typed_json(interface):
    trace = play(interface, "send ndd.GotoPosition x=8 y=2.5\nsend rflex.SetMode mode=velocity\nwait all\n")
    args = [e[6] for e in trace.events if e[2] == "request"]
    assert args == ['{"x": 8.0, "y": 2.5}', '{"mode": "velocity"}']


def test_a_layer_that_stops_answering_ends_the_trace_hung(interface):
    class Deadlocked(FakeLayer):
        deadlock_at = 3.0
    trace = play(interface, "send rflex.Init\nwait all\nsleep 5\nsend sick.Init as s\nwait s\n", layer=Deadlocked)
    assert trace.outcome == "hung"
    assert trace.sim_s < 5  # detected by the liveness probe, long before any wait times out
    assert ("request", 2) not in [(e[2], e[3]) for e in trace.events]
    assert any(kind == "probe_unanswered" for _, kind, _ in trace.world_events)


def test_wait_watchdog_abandons_a_wait_on_a_live_layer(interface):
    trace = play(interface, "send rflex.TrackSpeedStart as t\nwait t timeout=4\nsend rflex.Init as i\nwait i\n")
    assert trace.outcome == "completed"
    notes = [(t, kind) for t, kind, _ in trace.world_events if kind == "wait_timeout"]
    assert notes[0] == (pytest.approx(4.0), "wait_timeout")
    # the never-ending activity stays without a final reply after the bounded drain
    assert not any(e[2] == "final" and e[3] == 1 for e in trace.events)
    assert trace.sim_s == pytest.approx(4.0 + 1.0 + 2 * REACTION_S + DRAIN_S, abs=0.01)


def test_an_exception_inside_the_layer_ends_the_trace_crashed(interface):
    class Crashing(FakeLayer):
        crash_on = "sick.Init"
    trace = play(interface, SCRIPT, layer=Crashing)
    assert trace.outcome == "crashed"
    assert trace.error == "ZeroDivisionError: codel divided by zero"
    assert [e[2] for e in trace.events] == ["request", "request"]  # what happened before is kept


def test_a_reply_outside_the_catalogue_is_a_crash_naming_the_code(interface):
    class Garbling(FakeLayer):
        bad_code = "maybe"
    trace = play(interface, SCRIPT, layer=Garbling)
    assert trace.outcome == "crashed"
    assert "replied 'maybe' to request 1 (rflex.Init)" in trace.error


def test_internal_request_instant_is_when_the_layer_takes_it(interface):
    class Queueing(FakeLayer):
        take_s = 0.25
    trace = play(interface, "send rflex.Init\nwait all\n", layer=Queueing)
    observed = {(e[2], e[3]): e[1] for e in trace.events}
    internal = {(e[2], e[3]): e[1] for e in trace.internal_events}
    assert 0.25 <= internal[("request", 1)] - observed[("request", 1)] <= 0.253


def test_a_layer_that_takes_a_request_twice_crashes_the_trace(interface):
    class Stuttering(FakeLayer):
        def receive(self, rqst_id, service, args, reply):
            reply(rqst_id, "request", None)
            super().receive(rqst_id, service, args, reply)
    trace = play(interface, "send rflex.Init\nwait all\n", layer=Stuttering)
    assert trace.outcome == "crashed" and "took request 1 (rflex.Init) twice" in trace.error


def test_a_cancel_is_a_request_of_its_own_naming_the_goal_it_cancels(tmp_path):
    """`cancel g1` sends arm.move_cancel with goal = g1's request id, without blocking; `as c`
    names it for a wait; the layer receives the id as an integer."""
    arm = arm_interface(tmp_path)
    received = []

    class Recording(FakeLayer):
        def receive(self, rqst_id, service, args, reply):
            received.append((rqst_id, service, args))
            super().receive(rqst_id, service, args, reply)
    trace = play(arm, "send arm.grip\nsend arm.move order=3 as g1\ncancel g1 as c\nsend arm.grip\nwait c\n",
                 layer=Recording)
    assert sorted(received) == [(1, "arm.grip", {}), (2, "arm.move", {"order": "3"}), (3, "arm.move_cancel", {"goal": 2}),
                        (4, "arm.grip", {})]
    requests = [e for e in trace.events if e[2] == "request"]
    assert [(e[3], e[4], e[5], e[6]) for e in requests][2] == (3, "arm", "move_cancel", '{"goal": 2}')
    assert requests[3][1] == requests[2][1]  # the cancel did not block the next send
    t = {(e[2], e[3]): e[1] for e in trace.events}
    assert trace.sim_s >= t[("final", 3)] + REACTION_S  # wait c awaited the cancel's final


def test_the_simulated_layer_refuses_a_script_with_a_cancel(tmp_path):
    arm = arm_interface(tmp_path)
    script = parse("send arm.move order=3 as g1\ncancel g1\n", "t.mission")
    validate(script, arm)
    with pytest.raises(ScriptError, match="t.mission:2: cancel g1: the simulated layer .* has no cancels"):
        Runner()(script, "fake", 1, arm, None)
