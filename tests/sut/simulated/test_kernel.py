"""The event kernel: ordering in virtual time, processes, interrupts, failures, reprs."""
import pytest

from harness.sut.simulated.kernel import Environment, Interrupt


def test_equal_time_events_run_in_the_order_they_were_scheduled():
    env, order = Environment(), []
    for name in "abcde":
        env.call_at(2.0, lambda name=name: order.append(name))
    env.call_at(1.0, lambda: order.append("first"))
    env.run()
    assert order == ["first", *"abcde"]
    assert env.now == 2.0


def test_processes_wait_on_timeouts_and_return_values():
    env, log = Environment(), []

    def worker(name, period, times):
        for _ in range(times):
            yield env.timeout(period)
            log.append((env.now, name))
        return f"{name} done"

    a, b = env.process(worker("a", 1.0, 3)), env.process(worker("b", 1.5, 2))
    env.run()
    # at 3.0, b's timeout (scheduled at 1.5) runs before a's (scheduled at 2.0)
    assert log == [(1.0, "a"), (1.5, "b"), (2.0, "a"), (3.0, "b"), (3.0, "a")]
    assert (a.value, b.value, a.is_alive) == ("a done", "b done", False)


def test_a_process_can_wait_for_another_and_for_a_processed_event():
    env = Environment()
    child = env.process(iter_timeout(env, 2.0, "child"))

    def parent():
        got = yield child
        again = yield child  # already processed: resumes at once with the same value
        return got, again, env.now

    p = env.process(parent())
    env.run()
    assert p.value == ("child", "child", 2.0)


def iter_timeout(env, delay, value):
    yield env.timeout(delay)
    return value


def test_interrupt_overtakes_the_awaited_event_and_carries_its_cause():
    env, log = Environment(), []

    def sleeper():
        try:
            yield env.timeout(10.0)
            log.append("woke")
        except Interrupt as i:
            log.append((env.now, i.cause))
            yield env.timeout(1.0)
            log.append((env.now, "cleaned up"))

    p = env.process(sleeper())
    env.call_at(3.0, lambda: p.interrupt("stop"))
    env.run()
    assert log == [(3.0, "stop"), (4.0, "cleaned up")]  # the 10 s timeout no longer resumes it


def test_interrupting_a_finished_process_does_nothing():
    env = Environment()
    p = env.process(iter_timeout(env, 1.0, "ok"))
    env.run()
    p.interrupt("late")
    env.run()
    assert (p.value, p.is_alive) == ("ok", False)


def test_run_until_a_time_or_an_event():
    env, ticks = Environment(), []

    def clock():
        while True:
            yield env.timeout(1.0)
            ticks.append(env.now)

    env.process(clock())
    env.run(until=3.5)
    assert (ticks, env.now) == ([1.0, 2.0, 3.0], 3.5)
    stop = env.timeout(2.0)
    env.run(until=stop)
    assert ticks == [1.0, 2.0, 3.0, 4.0, 5.0] and env.now == 5.5


def test_an_exception_in_a_process_propagates_out_of_run():
    env = Environment()

    def broken():
        yield env.timeout(1.0)
        raise ZeroDivisionError("codel divided by zero")

    env.process(broken())
    with pytest.raises(ZeroDivisionError, match="codel"):
        env.run()


def test_yielding_something_else_than_an_event_is_refused():
    env = Environment()

    def wrong():
        yield 3

    env.process(wrong(), "wrong")
    with pytest.raises(TypeError, match="process 'wrong' yielded 3; yield an Event"):
        env.run()


def test_events_trigger_once_and_negative_delays_are_refused():
    env = Environment()
    event = env.event().succeed(1)
    with pytest.raises(RuntimeError, match="already been triggered"):
        event.succeed(2)
    with pytest.raises(ValueError, match="negative timeout delay -1"):
        env.timeout(-1)


def test_reprs_say_what_and_when():
    env = Environment()
    p = env.process(iter_timeout(env, 1.0, None), "walker")
    t = env.timeout(2.5)
    assert repr(env) == "<Environment t=0.000000 pending=2>"
    assert repr(p) == "<Process walker alive>"
    assert repr(t) == "<Timeout 2.5s pending>"
    env.run()
    assert (repr(p), repr(t)) == ("<Process walker done>", "<Timeout 2.5s processed>")
    assert repr(env.event()) == "<Event pending at t=2.500000>"


def test_any_of_succeeds_once_at_the_first_event():
    env = Environment()
    first, later = env.timeout(1.0), env.timeout(3.0)
    either = env.any_of(later, first)
    seen = []

    def waiter():
        yield either
        seen.append(env.now)

    env.process(waiter())
    env.run()
    assert seen == [1.0] and either.processed and later.processed


def test_a_failed_event_throws_its_exception_into_its_waiter():
    env = Environment()
    broken = env.event()
    caught = []

    def waiter():
        try:
            yield broken
        except KeyError as e:
            caught.append((env.now, e.args[0]))

    env.process(waiter())
    env.call_at(2.0, lambda: broken.fail(KeyError("no such map")))
    env.run()
    assert caught == [(2.0, "no such map")]
    assert repr(broken).startswith("<Event processed, failed with KeyError('no such map')")
    with pytest.raises(TypeError, match="'oops' is not an exception"):
        env.event().fail("oops")
    with pytest.raises(RuntimeError, match="already been triggered"):
        broken.fail(KeyError("again"))


def test_a_failure_nobody_waits_for_is_raised_out_of_run():
    env = Environment()
    env.event().fail(ValueError("unseen"))
    with pytest.raises(ValueError, match="unseen"):
        env.run()


def test_an_exception_in_a_process_names_the_process_and_reaches_its_waiter():
    env = Environment()

    def broken():
        yield env.timeout(1.5)
        raise ZeroDivisionError("codel divided by zero")

    child = env.process(broken(), "odometry")
    seen = []

    def parent():
        try:
            yield child
        except ZeroDivisionError as e:
            seen.append((env.now, e.__notes__))

    env.process(parent(), "parent")
    env.run()
    assert seen == [(1.5, ["raised in process 'odometry' at t=1.500000"])]
    assert repr(child) == "<Process odometry failed with ZeroDivisionError('codel divided by zero')>"


def test_combinators_count_events_processed_before_them():
    env = Environment()
    done, later = env.event().succeed("early"), env.timeout(2.0)
    env.run(until=1.0)
    assert done.processed
    either, both, none = env.any_of(later, done), env.all_of(done, later), env.all_of()
    results = {}

    def waiter(name, condition):
        results[name] = (yield condition), env.now

    for name, condition in (("either", either), ("both", both), ("none", none)):
        env.process(waiter(name, condition))
    env.run()
    assert results == {"either": ({done: "early"}, 1.0), "both": ({done: "early", later: None}, 2.0),
                       "none": ({}, 1.0)}
    assert repr(both) == "<Condition 2 of 2 events processed, processed>"


def test_a_combinator_fails_with_the_first_failure_and_a_processed_failure_is_thrown_again():
    env = Environment()
    bad, slow = env.event(), env.timeout(5.0)
    both = env.all_of(slow, bad)
    bad.fail(OSError("laser unplugged"))
    caught = []

    def waiter(event):
        try:
            yield event
        except OSError as e:
            caught.append((env.now, str(e)))

    env.process(waiter(both))
    env.run(until=1.0)
    env.process(waiter(bad))  # bad is processed: waiting on it throws its failure again at once
    env.run()
    assert caught == [(0.0, "laser unplugged"), (1.0, "laser unplugged")]
